//! The problem a trust case describes: the context an episode ran in together with the
//! behaviors its operator found untrustworthy (docs/model.md#context).
//!
//! The paper's problem is the evaluated pairs alone; a [`TrustProblem`] in the default
//! context is exactly that, and is written exactly as before (a list of pairs), so every
//! case base, store and vector from before contexts reads unchanged, as learned in the
//! default context. A problem in another context is written as a map with both fields.

use crate::evaluated::Evaluated;
use cbr_core::Context;
use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
use serde::de::{MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// An episode's context and the pairs it evaluated: the problem of a trust case and the
/// query of Algorithm 1.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrustProblem {
    /// The context the episode ran in.
    pub context: Context,
    /// The behaviors found untrustworthy, with their times, in order.
    pub evaluated: Vec<Evaluated>,
}

impl TrustProblem {
    /// The paper's problem: `evaluated` in the default context.
    pub fn new(evaluated: Vec<Evaluated>) -> Self {
        Self {
            context: Context::default(),
            evaluated,
        }
    }

    /// `evaluated` in `context`.
    pub fn in_context(context: Context, evaluated: Vec<Evaluated>) -> Self {
        Self { context, evaluated }
    }
}

impl From<Vec<Evaluated>> for TrustProblem {
    fn from(evaluated: Vec<Evaluated>) -> Self {
        Self::new(evaluated)
    }
}

impl FromIterator<Evaluated> for TrustProblem {
    /// The pairs in the default context.
    fn from_iter<I: IntoIterator<Item = Evaluated>>(pairs: I) -> Self {
        Self::new(pairs.into_iter().collect())
    }
}

/// The map form, for a problem outside the default context.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct InContext<C, E> {
    context: C,
    evaluated: E,
}

impl Serialize for TrustProblem {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        if self.context.is_default() {
            self.evaluated.serialize(serializer)
        } else {
            InContext {
                context: &self.context,
                evaluated: &self.evaluated,
            }
            .serialize(serializer)
        }
    }
}

impl<'de> Deserialize<'de> for TrustProblem {
    /// Either form: a list of pairs (the default context) or the map of `context` and
    /// `evaluated`; what is wrong inside either (a pair, a context variable written twice)
    /// is reported as the part says it, at its place.
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(ProblemVisitor)
    }
}

/// Reads a problem in either of its forms ([`TrustProblem`]'s `Deserialize`).
struct ProblemVisitor;

impl<'de> Visitor<'de> for ProblemVisitor {
    type Value = TrustProblem;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(
            "a problem: a list of (behavior, time) pairs, or a map of `context` and `evaluated`",
        )
    }

    fn visit_seq<A: SeqAccess<'de>>(self, pairs: A) -> Result<TrustProblem, A::Error> {
        Vec::<Evaluated>::deserialize(SeqAccessDeserializer::new(pairs)).map(TrustProblem::new)
    }

    fn visit_map<A: MapAccess<'de>>(self, fields: A) -> Result<TrustProblem, A::Error> {
        let InContext { context, evaluated } =
            InContext::<Context, Vec<Evaluated>>::deserialize(MapAccessDeserializer::new(fields))?;
        Ok(TrustProblem::in_context(context, evaluated))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TrustCase;
    use cbr_core::{Behavior, ContextSpace, ContextVariable};

    fn hazardous() -> Context {
        ContextSpace::new(vec![ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap()
        .context([("cargo", "hazardous")])
        .unwrap()
    }

    fn pairs() -> Vec<Evaluated> {
        vec![Evaluated {
            behavior: Behavior::new(&[3, 4]),
            time: 12.0,
        }]
    }

    #[test]
    fn the_default_context_is_written_as_the_paper_wrote_problems() {
        let case = TrustCase {
            problem: TrustProblem::new(pairs()),
            solution: Behavior::new(&[5, 5]),
        };
        let json = serde_json::to_string(&case).unwrap();
        assert_eq!(
            json,
            r#"{"problem":[{"behavior":[3,4],"time":12.0}],"solution":[5,5]}"#
        );
        assert_eq!(serde_json::from_str::<TrustCase>(&json).unwrap(), case);
        let ron_text = "(problem: [(behavior: [3, 4], time: 12.0)], solution: [5, 5])";
        assert_eq!(ron::from_str::<TrustCase>(ron_text).unwrap(), case);
    }

    #[test]
    fn another_context_is_written_beside_the_pairs_and_read_back() {
        let problem = TrustProblem::in_context(hazardous(), pairs());
        let json = serde_json::to_string(&problem).unwrap();
        assert_eq!(
            json,
            r#"{"context":{"cargo":"hazardous"},"evaluated":[{"behavior":[3,4],"time":12.0}]}"#
        );
        assert_eq!(
            serde_json::from_str::<TrustProblem>(&json).unwrap(),
            problem
        );
        let ron_text = ron::to_string(&problem).unwrap();
        assert_eq!(ron::from_str::<TrustProblem>(&ron_text).unwrap(), problem);
    }

    #[test]
    fn a_problem_of_neither_form_is_refused_with_both_named() {
        let err = serde_json::from_str::<TrustProblem>("12").unwrap_err();
        assert!(
            err.to_string().contains(
                "a list of (behavior, time) pairs, or a map of `context` and `evaluated`"
            ),
            "{err}"
        );
    }

    #[test]
    fn what_is_wrong_inside_a_form_is_said_as_the_part_says_it() {
        let err = serde_json::from_str::<TrustProblem>(r#"{"evaluated":[]}"#).unwrap_err();
        assert!(err.to_string().contains("missing field `context`"), "{err}");
        let twice = r#"(context: {"cargo": "hazardous", "cargo": "normal"}, evaluated: [])"#;
        let err = ron::from_str::<TrustProblem>(twice).unwrap_err();
        assert!(
            err.to_string()
                .contains("context variable `cargo` is given twice; give each variable once"),
            "{err}"
        );
    }
}
