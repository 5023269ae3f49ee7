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
use trustcbr::lab::contract::operator_file;
use trustcbr::lab::population::family::{geometric, linear, toward, two_pole_family};

/// The shipped operator of `name`.
fn shipped(name: &str) -> WarehouseOperator {
    operator_file::find(builtin_operators(), name).expect("a shipped operator")
}

/// The member of the family at position `x` in `[-1, 1]` (-1: throughput-focused, 0:
/// balanced, 1: care-focused), named `name`.
pub fn member(x: f64, name: &str) -> WarehouseOperator {
    let base = shipped("balanced");
    let (to, f) = toward(x, shipped("throughput-focused"), shipped("care-focused"));
    if f == 0.0 {
        // The base itself, whose weights are its own rather than a side's pole's.
        return WarehouseOperator {
            name: name.to_owned(),
            ..base
        };
    }
    WarehouseOperator {
        name: name.to_owned(),
        t_complete: geometric(base.t_complete, to.t_complete, f),
        p_deadline: linear(base.p_deadline, to.p_deadline, f),
        p_collision: linear(base.p_collision, to.p_collision, f),
        p_crushed: linear(base.p_crushed, to.p_crushed, f),
        give_up_factor: base.give_up_factor,
        weights: to.weights,
        // How an operator explains itself is the experiment's to vary, not the family's.
        feedback: base.feedback,
    }
}

/// `size` operators drawn from the family at `conflict` (clamped to `[0, 1]`) with
/// `seed`, named `family-c{conflict:.2}-{i}`: positions drawn by the lab's
/// [`two_pole_family`], the side `true` towards care.
pub fn family(conflict: f64, size: usize, seed: u64) -> Vec<WarehouseOperator> {
    two_pole_family(conflict, size, seed, member)
}
