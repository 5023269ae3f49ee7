//! A family of warehouse operators whose one parameter, `conflict` in `[0, 1]`, sets how
//! much its members disagree: throughput against care (the crate's README, "Operators who
//! disagree").
//!
//! Members start from the shipped **balanced** operator, the compromise both sides relax
//! from (a minute per pick, enforced; collisions not tolerated; half the items checked),
//! and move towards one of two shipped poles:
//! - the **throughput-focused** shift lead: 45 s per pick, enforced; bumps taken in stride;
//!   damage rarely looked at;
//! - the **care-focused** supervisor of fragile goods: two minutes per pick, hardly
//!   enforced; collisions stopped; every item inspected; damage weighing twice the rest.
//!
//! A member at position `x` in `[-1, 1]` is the base moved `|x|` of the way to the
//! throughput pole (`x < 0`) or the care pole (`x > 0`): the time allowed geometrically
//! (a time scales by factors), the reaction probabilities linearly, the give-up factor
//! kept (2 for all three). The weights are its side's pole's: what a pick's ending weighs
//! is what the store ships (fragile goods, or not), a fact of the job rather than a
//! degree; and weights moved by degrees would make the trust estimate's reachable sums
//! dense, so the report's known-operator limit could not be solved. Exact at the ends, so
//! the base and the poles are the shipped operators.

use crate::operator::{WarehouseOperator, builtin_operators};
use trustcbr::lab::seeds::{Purpose, stream};
use trustcbr::rand::Rng;

/// The shipped operator of `name`.
fn shipped(name: &str) -> WarehouseOperator {
    builtin_operators()
        .into_iter()
        .find(|o| o.name == name)
        .expect("a shipped operator")
}

/// The member of the family at position `x` in `[-1, 1]` (-1: throughput-focused, 0:
/// balanced, 1: care-focused), named `name`.
pub fn member(x: f64, name: &str) -> WarehouseOperator {
    let x = x.clamp(-1.0, 1.0);
    let base = shipped("balanced");
    let (to, f) = if x < 0.0 {
        (shipped("throughput-focused"), -x)
    } else {
        (shipped("care-focused"), x)
    };
    if f == 0.0 {
        return WarehouseOperator {
            name: name.to_owned(),
            ..base
        };
    }
    let linear = |p: f64, q: f64| if f == 1.0 { q } else { p + (q - p) * f };
    WarehouseOperator {
        name: name.to_owned(),
        t_complete: if f == 1.0 {
            to.t_complete
        } else {
            base.t_complete.powf(1.0 - f) * to.t_complete.powf(f)
        },
        p_deadline: linear(base.p_deadline, to.p_deadline),
        p_collision: linear(base.p_collision, to.p_collision),
        p_crushed: linear(base.p_crushed, to.p_crushed),
        give_up_factor: base.give_up_factor,
        weights: to.weights,
        // How an operator explains itself is the experiment's to vary, not the family's.
        feedback: base.feedback,
    }
}

/// `size` operators drawn from the family at `conflict` (clamped to `[0, 1]`) with
/// `seed`, named `family-c{conflict:.2}-{i}`.
pub fn family(conflict: f64, size: usize, seed: u64) -> Vec<WarehouseOperator> {
    let c = conflict.clamp(0.0, 1.0);
    draw_positions(c, size, seed)
        .into_iter()
        .enumerate()
        .map(|(i, x)| member(x, &format!("family-c{c:.2}-{i}")))
        .collect()
}

/// LOCAL STAND-IN, to be replaced at merge by the lab's generic two-pole helper
/// (`lab::population`, being written in parallel): `size` positions in `[-1, 1]`, each a
/// side drawn fairly and a spread `u` in `[0, 1)`, at `-+lambda` with
/// `lambda = conflict (1 - (1 - conflict) u)` (the UGV family's rule, docs/simulation.md),
/// from a portable generator seeded with `seed`.
fn draw_positions(conflict: f64, size: usize, seed: u64) -> Vec<f64> {
    let mut rng = stream(seed, 0, 0, Purpose::Setup);
    (0..size)
        .map(|_| {
            let care = rng.random::<bool>();
            let lambda = conflict * (1.0 - (1.0 - conflict) * rng.random::<f64>());
            if care { lambda } else { -lambda }
        })
        .collect()
}
