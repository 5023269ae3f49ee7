//! What operators state up front: how an experiment turns the truth of an operator's
//! preferences ([`Domain::true_statements`](crate::Domain::true_statements)) into what
//! the robot is told as an episode begins ([`trust::Adaptation::begin_episode_hearing`]).
//!
//! People say some of what they mind and not all of it, and misjudge some of what they
//! say: an experiment's [`Stating`] says each true statement with chance `said` (a name
//! left unsaid is unknown to the robot) and says it the wrong way round with chance
//! `wrong`. Both draws are made for every statement whatever the shares, on a stream of
//! their own ([`crate::seeds::Purpose::Statements`]), so experiments that differ only in
//! their shares state from the same draws and no other stream moves.

use cbr_core::Statement;
use rand::{Rng, RngCore};
use serde::{Deserialize, Serialize};

/// How an experiment's operators state their preferences up front.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "StatingDefinition")]
pub struct Stating {
    /// The chance each true statement is said.
    pub said: f64,
    /// The chance a said statement is said the wrong way round.
    pub wrong: f64,
}

/// A stating as written, before it is checked.
#[derive(Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct StatingDefinition {
    said: f64,
    #[serde(default)]
    wrong: f64,
}

/// A stating whose shares are not probabilities.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "stated `{field}` must be a probability in [0, 1], got {}",
    cbr_core::Shown(*.value)
)]
pub struct StatingError {
    /// `said` or `wrong`.
    pub field: &'static str,
    /// The value given.
    pub value: f64,
}

impl TryFrom<StatingDefinition> for Stating {
    type Error = StatingError;

    fn try_from(d: StatingDefinition) -> Result<Self, StatingError> {
        Self::new(d.said, d.wrong)
    }
}

impl Stating {
    /// Operators who say everything they mind, rightly.
    pub const TRUE: Self = Self {
        said: 1.0,
        wrong: 0.0,
    };

    /// Each true statement said with chance `said`, the wrong way round with chance
    /// `wrong`; both in `[0, 1]`.
    pub fn new(said: f64, wrong: f64) -> Result<Self, StatingError> {
        for (field, value) in [("said", said), ("wrong", wrong)] {
            if !(0.0..=1.0).contains(&value) {
                return Err(StatingError { field, value });
            }
        }
        Ok(Self { said, wrong })
    }

    /// What an operator whose true statements are `truth` says, drawn from `rng`: per
    /// statement in order, whether it is said, then whether it is wrong.
    pub fn draw(&self, truth: &[Statement], rng: &mut dyn RngCore) -> Vec<Statement> {
        truth
            .iter()
            .filter_map(|statement| {
                let said = rng.random::<f64>() < self.said;
                let wrong = rng.random::<f64>() < self.wrong;
                said.then(|| {
                    if wrong {
                        statement.negated()
                    } else {
                        statement.clone()
                    }
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn truth() -> Vec<Statement> {
        (0..1000)
            .map(|i| Statement::new(&format!("s{i}"), i % 2 == 0))
            .collect()
    }

    #[test]
    fn true_statements_are_said_as_they_are() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        assert_eq!(Stating::TRUE.draw(&truth(), &mut rng), truth());
    }

    #[test]
    fn partial_and_wrong_statements_come_at_their_shares_from_the_same_draws() {
        let draw = |stating: Stating| stating.draw(&truth(), &mut ChaCha8Rng::seed_from_u64(7));
        let partial = draw(Stating::new(0.5, 0.0).unwrap());
        let wrong = draw(Stating::new(1.0, 0.3).unwrap());
        let both = draw(Stating::new(0.5, 0.3).unwrap());
        assert!((450..550).contains(&partial.len()), "{}", partial.len());
        let flipped = wrong.iter().zip(truth()).filter(|(s, t)| **s != *t).count();
        assert!((250..350).contains(&flipped), "{flipped}");
        // The same draws: what both shares say is what `partial` says, flipped where
        // `wrong` flipped it.
        let expected: Vec<Statement> = partial
            .iter()
            .map(|s| wrong.iter().find(|w| w.name == s.name).unwrap().clone())
            .collect();
        assert_eq!(both, expected);
    }

    #[test]
    fn shares_outside_zero_one_are_refused_by_name() {
        assert_eq!(
            Stating::new(1.0, 1.5),
            Err(StatingError {
                field: "wrong",
                value: 1.5
            })
        );
        let read: Result<Stating, _> = ron::from_str("(said: -0.1)");
        assert!(read.unwrap_err().to_string().contains("`said`"));
        assert_eq!(ron::from_str::<Stating>("(said: 0.5)").unwrap().wrong, 0.0);
    }
}
