//! The grasping modules the robot can switch between, and the arithmetic of a grasp:
//! whether it holds an item through the accelerations of the drive and whether it
//! squeezes the item beyond what it stands.
//!
//! The behavior's `grip_force` is the force the module is commanded to apply: the
//! clamping force of the jaws or fingers, or the vacuum pull of the suction cup. A pinch
//! holds by friction on two faces, `2 mu F`; a suction cup holds by its pull, `seal x F`,
//! where the seal is the share of the pull a surface keeps (a porous or ribbed surface
//! leaks). An item's centre of mass hangs below or beside the grasp, so a horizontal
//! acceleration `a` loads the grasp by a moment as well as by gravity: the grasp slips
//! when its holding force, varied by how well this grasp landed, is below
//! `m (g + a x lever)`. The squeeze crushes the item when it exceeds the item's limit for
//! rigid pads times how widely the module spreads its force. Reasons for every number:
//! the crate's README ("Grippers").

use crate::items::{Item, Surface};
use rand::{Rng, RngCore};
use trustcbr::rand;

/// Standard gravity (m/s^2).
pub const GRAVITY: f64 = 9.81;

/// How far one grasp's holding force may lie from nominal, either way (where on the item
/// the contacts land, dust, an off-centre grasp): a factor uniform in `1 ± GRASP_SPREAD`.
pub const GRASP_SPREAD: f64 = 0.3;

/// A grasping module.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gripper {
    /// A 50 mm bellows vacuum cup.
    Suction,
    /// Two rigid jaws with rubber pads.
    ParallelJaw,
    /// Three pneumatic silicone fingers that wrap around the item.
    SoftFingers,
}

impl Gripper {
    /// Every module, in the order of the `gripper` component's labels.
    pub const ALL: [Gripper; 3] = [Gripper::Suction, Gripper::ParallelJaw, Gripper::SoftFingers];

    /// The label in behaviors (`gripper=suction`).
    pub fn label(self) -> &'static str {
        match self {
            Gripper::Suction => "suction",
            Gripper::ParallelJaw => "parallel-jaw",
            Gripper::SoftFingers => "soft-fingers",
        }
    }

    /// Time to grasp an item on the shelf (s): approach, align, close or seal, lift.
    pub fn grasp_time(self) -> f64 {
        match self {
            Gripper::Suction => 1.5,
            Gripper::ParallelJaw => 3.0,
            Gripper::SoftFingers => 4.5,
        }
    }

    /// Time to set the item down at the packing station (s).
    pub fn release_time(self) -> f64 {
        match self {
            Gripper::Suction => 0.5,
            Gripper::ParallelJaw => 1.0,
            Gripper::SoftFingers => 2.0,
        }
    }

    /// The force the module applies when commanded `commanded` N: soft fingers saturate
    /// at the 40 N their actuators can give.
    pub fn applied_force(self, commanded: f64) -> f64 {
        match self {
            Gripper::SoftFingers => commanded.min(40.0),
            Gripper::Suction | Gripper::ParallelJaw => commanded,
        }
    }

    /// How many times an item's rigid-pad crush limit the module's squeeze may reach:
    /// the wider the contact, the lower the pressure.
    pub fn spread(self) -> f64 {
        match self {
            Gripper::ParallelJaw => 1.0,
            Gripper::Suction => 2.0,
            Gripper::SoftFingers => 4.0,
        }
    }

    /// The moment arm of an item's weight under horizontal acceleration over the grasp's
    /// resisting arm: how many `m x a` a braking adds to the load.
    pub fn lever(self) -> f64 {
        match self {
            Gripper::Suction => 3.0,
            Gripper::ParallelJaw => 1.5,
            Gripper::SoftFingers => 1.0,
        }
    }

    /// The share of the commanded force that holds the item against its load: the seal
    /// of a cup, or `2 mu` of a pinch.
    pub fn grip_ratio(self, surface: Surface) -> f64 {
        use Surface::{Cardboard, Clamshell, Film, OilyMetal, Smooth};
        match self {
            Gripper::Suction => match surface {
                Cardboard => 0.5,
                Smooth => 0.7,
                Film => 0.8,
                Clamshell => 0.2,
                OilyMetal => 0.9,
            },
            Gripper::ParallelJaw => {
                2.0 * match surface {
                    Cardboard => 0.6,
                    Smooth => 0.5,
                    Film => 0.4,
                    Clamshell => 0.5,
                    OilyMetal => 0.15,
                }
            }
            Gripper::SoftFingers => {
                2.0 * match surface {
                    Cardboard => 0.9,
                    Smooth => 0.8,
                    Film => 0.7,
                    Clamshell => 0.9,
                    OilyMetal => 0.3,
                }
            }
        }
    }
}

/// One grasp of one item: how much it holds and whether it crushed the item.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grasp {
    /// Holding force of this grasp (N).
    pub holding_n: f64,
    /// The item's mass (kg).
    pub mass_kg: f64,
    /// The module's lever ([`Gripper::lever`]).
    pub lever: f64,
    /// The squeeze (N) as two rigid pads would apply it: the applied force over the
    /// module's spread, what the robot's own force reading tells it.
    pub squeeze_n: f64,
    /// Whether the squeeze exceeded what the item stands.
    pub crushed: bool,
}

impl Grasp {
    /// `gripper` commanded to `commanded` N grasps `item`; one uniform draw from `rng`
    /// (how well the grasp landed).
    pub fn new(gripper: Gripper, commanded: f64, item: &Item, rng: &mut dyn RngCore) -> Self {
        let landed = 1.0 - GRASP_SPREAD + 2.0 * GRASP_SPREAD * rng.random::<f64>();
        let applied = gripper.applied_force(commanded);
        Self {
            holding_n: gripper.grip_ratio(item.surface) * applied * landed,
            mass_kg: item.mass_kg,
            lever: gripper.lever(),
            squeeze_n: applied / gripper.spread(),
            crushed: applied > item.crush_limit_n * gripper.spread(),
        }
    }

    /// The load (N) on the grasp while the robot accelerates or brakes at `accel` m/s^2.
    pub fn load(&self, accel: f64) -> f64 {
        self.mass_kg * (GRAVITY + accel * self.lever)
    }

    /// Whether the item slips out at a horizontal acceleration of `accel` m/s^2.
    pub fn slips(&self, accel: f64) -> bool {
        self.holding_n < self.load(accel)
    }
}
