//! The items a pick may fetch: the warehouse's item mix.
//!
//! Each command fetches one item, drawn from the mix: its class (by share of picks), its
//! mass (uniform in the class's range) and how much squeeze it stands (the class's
//! limit, varied by packaging from item to item). The numbers and their reasons are in
//! the crate's README ("The item mix").

use rand::{Rng, RngCore};
use trustcbr::rand;

/// What the gripper touches: it sets the friction of a pinch and the seal of a suction cup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surface {
    /// Corrugated cardboard: rough (good friction), porous (a suction cup leaks).
    Cardboard,
    /// Glass or PET, curved: moderate friction, a cup seals on the label panel.
    Smooth,
    /// A polybag's film: slippery to a pinch, seals well where it is taut.
    Film,
    /// A vented, ribbed produce clamshell: grippy, but a cup finds no flat sealed patch.
    Clamshell,
    /// A bare machined part with cutting oil on it: slippery, a cup seals perfectly.
    OilyMetal,
}

/// A class of items in the mix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ItemClass {
    /// The class's name (e.g. `carton`).
    pub name: &'static str,
    /// Share of picks (the shares of the mix sum to 1).
    pub share: f64,
    /// Lightest and heaviest item (kg).
    pub mass_kg: (f64, f64),
    /// What a gripper touches.
    pub surface: Surface,
    /// The squeeze (N) two rigid pads may apply before the item is damaged, for a
    /// typical item; `None` when no gripper can damage it.
    pub crush_limit_n: Option<f64>,
}

/// The warehouse's item mix (an online general-merchandise store's picks).
pub const ITEM_MIX: [ItemClass; 5] = [
    ItemClass {
        name: "carton",
        share: 0.35,
        mass_kg: (0.5, 3.0),
        surface: Surface::Cardboard,
        crush_limit_n: Some(120.0),
    },
    ItemClass {
        name: "bottle",
        share: 0.15,
        mass_kg: (0.5, 1.5),
        surface: Surface::Smooth,
        crush_limit_n: Some(300.0),
    },
    ItemClass {
        name: "polybag",
        share: 0.25,
        mass_kg: (0.2, 1.0),
        surface: Surface::Film,
        crush_limit_n: None,
    },
    ItemClass {
        name: "produce",
        share: 0.15,
        mass_kg: (0.3, 0.8),
        surface: Surface::Clamshell,
        crush_limit_n: Some(15.0),
    },
    ItemClass {
        name: "hardware",
        share: 0.10,
        mass_kg: (2.0, 6.0),
        surface: Surface::OilyMetal,
        crush_limit_n: None,
    },
];

/// How far one item's crush limit may lie from its class's, either way (packaging and
/// ripeness vary): a factor uniform in `1 ± CRUSH_SPREAD`.
pub const CRUSH_SPREAD: f64 = 0.2;

impl ItemClass {
    /// The squeeze (N, two rigid pads) every item of the class stands: the low end of its
    /// spread, what the warehouse's item data rates the class for (infinite when no
    /// gripper damages it).
    pub fn rated_squeeze_n(&self) -> f64 {
        self.crush_limit_n
            .map_or(f64::INFINITY, |limit| limit * (1.0 - CRUSH_SPREAD))
    }
}

/// One item to fetch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Item {
    /// Its class in [`ITEM_MIX`].
    pub class: usize,
    /// Its mass (kg).
    pub mass_kg: f64,
    /// What a gripper touches.
    pub surface: Surface,
    /// The squeeze (N) two rigid pads may apply before it is damaged (infinite for items
    /// no gripper damages).
    pub crush_limit_n: f64,
}

/// Draws the next item from the mix: three uniform draws from `rng` (class, mass, crush
/// limit), always, so the stream's use does not depend on the item.
pub fn draw_item(rng: &mut dyn RngCore) -> Item {
    let pick: f64 = rng.random();
    let mass_draw: f64 = rng.random();
    let crush_draw: f64 = rng.random();
    let mut cumulative = 0.0;
    let class = ITEM_MIX
        .iter()
        .position(|c| {
            cumulative += c.share;
            pick < cumulative
        })
        .unwrap_or(ITEM_MIX.len() - 1);
    let c = &ITEM_MIX[class];
    let (light, heavy) = c.mass_kg;
    Item {
        class,
        mass_kg: light + mass_draw * (heavy - light),
        surface: c.surface,
        crush_limit_n: c.crush_limit_n.map_or(f64::INFINITY, |limit| {
            limit * (1.0 - CRUSH_SPREAD + 2.0 * CRUSH_SPREAD * crush_draw)
        }),
    }
}
