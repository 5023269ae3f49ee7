//! The built-in search strategies, registered in one place: [`strategies`] lists one
//! [`Strategy`] per line, each declared in its searcher's own file (`STRATEGY` there).
//! Everything that offers a strategy reads this list: a config's `search`
//! ([`crate::SearchKind`]), the laboratory's built-in arms, their descriptions and colours
//! in reports and figures, the command line and the Python package.
//!
//! Adding a strategy is its file (the searcher and its `STRATEGY`) and one line in
//! [`strategies`]; nothing else names it.

use super::TrustSearcher;
use std::fmt;
use std::sync::LazyLock;

/// A colour, as red, green and blue.
pub type Rgb = [u8; 3];

/// The marker an arm is drawn with in figures; every marker of one size covers about the
/// same area.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    /// A disc.
    Circle,
    /// A square on its side.
    Square,
    /// A square on its corner.
    Diamond,
    /// A triangle pointing up.
    TriangleUp,
    /// A triangle pointing down.
    TriangleDown,
    /// A regular pentagon.
    Pentagon,
    /// A regular hexagon.
    Hexagon,
    /// A five-pointed star.
    Star,
    /// A plus sign with thick arms.
    Plus,
}

/// How an arm looks in every figure of every report: its colour and its marker.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Look {
    /// Its colour.
    pub colour: Rgb,
    /// Its marker.
    pub marker: Marker,
}

/// A strategy also offered after case reuse: Algorithm 1 first, the strategy when no case
/// fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WithCases {
    /// The arm's name (`case-based+NAME`; the paper's walk's is `case-based`).
    pub name: &'static str,
    /// What the arm does, in one line.
    pub description: &'static str,
    /// How it looks in figures.
    pub look: Look,
}

/// One built-in search strategy.
#[derive(Clone, Copy)]
pub struct Strategy {
    /// Its name in arm names, reports and [`cbr_core::Searcher::name`] (`random-walk`,
    /// `cause-aware`, ...); a config's `search` writes it with `_` for `-`.
    pub name: &'static str,
    /// What it does, in one line.
    pub description: &'static str,
    /// How the strategy alone looks in figures.
    pub look: Look,
    /// How it is offered after case reuse (`None`: alone only).
    pub with_cases: Option<WithCases>,
    /// A fresh searcher.
    pub build: fn() -> Box<TrustSearcher>,
}

impl Strategy {
    /// Whether what it learns in one episode carries into the next (its searcher says:
    /// [`cbr_core::Searcher::learns_across_episodes`]).
    pub fn learns_across_episodes(&self) -> bool {
        (self.build)().learns_across_episodes()
    }

    /// Its name in a config's `search`: the name with `_` for `-` (`cause_aware`).
    pub fn config_name(&self) -> &'static str {
        strategies()
            .iter()
            .position(|s| s == self)
            .map_or(self.name, |k| config_names()[k])
    }
}

impl fmt::Debug for Strategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Strategy")
            .field("name", &self.name)
            .field("with_cases", &self.with_cases.map(|w| w.name))
            .finish_non_exhaustive()
    }
}

impl PartialEq for Strategy {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

impl Eq for Strategy {}

/// Every built-in strategy, the paper's first, one line each.
pub fn strategies() -> &'static [Strategy] {
    static ALL: LazyLock<Vec<Strategy>> = LazyLock::new(|| {
        let mut all = vec![super::random_walk::STRATEGY];
        all.push(super::uniform::STRATEGY);
        all.push(super::cause_aware::STRATEGY);
        #[cfg(feature = "model-based")]
        all.push(super::model_based::STRATEGY);
        all.push(super::conditioned::STRATEGY);
        #[cfg(feature = "model-based")]
        all.push(super::conditioned::HEDGED);
        #[cfg(feature = "model-based")]
        all.push(super::bandit::STRATEGY);
        #[cfg(feature = "model-based")]
        all.push(super::reliable::STRATEGY);
        #[cfg(feature = "model-based")]
        all.push(super::nested::STRATEGY);
        all
    });
    &ALL
}

/// The built-in strategy named `name` (as in arm names: `cause-aware`).
pub fn strategy(name: &str) -> Option<&'static Strategy> {
    strategies().iter().find(|s| s.name == name)
}

/// Every strategy's name in configs (`random_walk`, `cause_aware`, ...), in registry order:
/// made once and kept (`'static`, as a serialized enum variant's name must be).
pub fn config_names() -> &'static [&'static str] {
    static NAMES: LazyLock<&'static [&'static str]> = LazyLock::new(|| {
        Box::leak(
            strategies()
                .iter()
                .map(|s| &*Box::leak(s.name.replace('-', "_").into_boxed_str()))
                .collect::<Vec<&'static str>>()
                .into_boxed_slice(),
        )
    });
    &NAMES
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_strategy_builds_a_searcher_of_its_own_name() {
        let names: Vec<&str> = strategies().iter().map(|s| s.name).collect();
        assert_eq!(names[0], "random-walk", "the paper's first");
        for (k, s) in strategies().iter().enumerate() {
            assert_eq!((s.build)().name(), s.name);
            assert!(!names[..k].contains(&s.name), "{} twice", s.name);
            assert_eq!(strategy(s.name), Some(s));
            assert_eq!(s.config_name(), s.name.replace('-', "_"));
        }
        assert_eq!(strategy("case-based"), None, "an arm, not a strategy");
        assert_eq!(config_names().len(), strategies().len());
    }

    #[test]
    fn the_walk_is_the_paper_s_pair_and_learning_is_the_searcher_s_word() {
        let walk = strategy("random-walk").unwrap();
        assert_eq!(walk.with_cases.map(|w| w.name), Some("case-based"));
        assert!(!walk.learns_across_episodes());
        assert!(strategy("conditioned").unwrap().learns_across_episodes());
        assert_eq!(strategy("uniform").unwrap().with_cases, None);
    }
}

#[cfg(test)]
mod config_tests {
    use crate::SearchKind;

    #[test]
    fn a_config_names_a_strategy_bare_in_ron_and_as_a_string_in_json() {
        #[derive(serde::Deserialize, serde::Serialize, Debug, PartialEq)]
        struct Config {
            search: SearchKind,
        }
        let read: Config = ron::from_str("(search: cause_aware)").unwrap();
        assert_eq!(read.search.name(), "cause-aware");
        assert_eq!(ron::to_string(&read).unwrap(), "(search:cause_aware)");
        let json: Config = serde_json::from_str(r#"{"search": "uniform"}"#).unwrap();
        assert_eq!(json.search.name(), "uniform");
        assert_eq!(
            serde_json::to_string(&json).unwrap(),
            r#"{"search":"uniform"}"#
        );
        let wrong = ron::from_str::<Config>("(search: annealing)")
            .unwrap_err()
            .to_string();
        assert!(
            wrong.contains("annealing") && wrong.contains("random_walk"),
            "{wrong}"
        );
    }
}
