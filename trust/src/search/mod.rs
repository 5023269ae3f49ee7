//! Search strategies for trust-guided adaptation: what to try when no case helps.
//!
//! Every strategy implements [`cbr_core::Searcher`] over [`crate::Evaluated`] evidence and
//! [`crate::Outcome`] feedback; [`TrustSearcher`] names that shape.

pub mod random_walk;

pub use random_walk::RandomWalk;

use crate::{Evaluated, Outcome};
use cbr_core::Searcher;

/// A search strategy as the trust adapter drives it.
pub type TrustSearcher = dyn Searcher<Evidence = Evaluated, Feedback = Outcome>;

/// `E_max`: the first evaluated pair with the largest time (it resisted the longest).
pub fn longest_resisting(evaluated: &[Evaluated]) -> Option<&Evaluated> {
    evaluated
        .iter()
        .fold(None, |best: Option<&Evaluated>, e| match best {
            Some(b) if b.time >= e.time => Some(b),
            _ => Some(e),
        })
}
