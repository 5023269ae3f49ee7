//! Behaviors and the behavior space.
//!
//! A [`Behavior`] is one value index per component: small, `Copy` and hashable, so sets of
//! behaviors are cheap. A [`BehaviorSpace`] is the Cartesian product of its components: it
//! draws, enumerates, ranks, measures (similarity, number of changes) and displays
//! behaviors in real units. Neither knows what the behaviors are used for.

use crate::component::{ComponentError, NamedComponent};
use crate::similarity::SimilarityMeasure;
use rand::{Rng, RngCore};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Largest number of components a behavior space may have.
pub const MAX_COMPONENTS: usize = 8;

/// One value index per component of a [`BehaviorSpace`].
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Behavior {
    indices: [u16; MAX_COMPONENTS],
    len: u8,
}

impl Behavior {
    /// A behavior from value indices, one per component (at most [`MAX_COMPONENTS`]).
    ///
    /// # Panics
    /// If more than [`MAX_COMPONENTS`] indices are given.
    pub fn new(indices: &[u16]) -> Self {
        assert!(
            indices.len() <= MAX_COMPONENTS,
            "a behavior has at most {MAX_COMPONENTS} components"
        );
        let mut all = [0; MAX_COMPONENTS];
        all[..indices.len()].copy_from_slice(indices);
        Self {
            indices: all,
            len: indices.len() as u8,
        }
    }

    /// The value indices, one per component.
    pub fn indices(&self) -> &[u16] {
        &self.indices[..usize::from(self.len)]
    }

    /// The value index of component `component`.
    pub fn get(&self, component: usize) -> u16 {
        self.indices()[component]
    }

    /// This behavior with component `component` set to value index `value`.
    pub fn with(mut self, component: usize, value: u16) -> Self {
        self.indices[..usize::from(self.len)][component] = value;
        self
    }

    /// Number of components.
    pub fn len(&self) -> usize {
        usize::from(self.len)
    }

    /// Whether the behavior has no components.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl fmt::Debug for Behavior {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Behavior{:?}", self.indices())
    }
}

impl Serialize for Behavior {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.indices().serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for Behavior {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let indices = Vec::<u16>::deserialize(deserializer)?;
        if indices.len() > MAX_COMPONENTS {
            return Err(serde::de::Error::invalid_length(
                indices.len(),
                &"at most 8 value indices",
            ));
        }
        Ok(Self::new(&indices))
    }
}

/// Why a behavior space or a behavior description is not usable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SpaceError {
    /// A component is invalid.
    #[error(transparent)]
    Component(#[from] ComponentError),
    /// No components, or more than [`MAX_COMPONENTS`].
    #[error("a behavior space needs 1 to {MAX_COMPONENTS} components, got {0}")]
    ComponentCount(usize),
    /// Two components share a name.
    #[error("component name `{0}` appears twice")]
    DuplicateName(String),
    /// Weights of the wrong length, negative, or all zero.
    #[error("weights must be one non-negative number per component, not all zero")]
    BadWeights,
    /// The product of the component sizes does not fit in 64 bits.
    #[error("the behavior space is too large to enumerate")]
    TooLarge,
    /// A behavior string names a component the space lacks.
    #[error("unknown component `{name}` (known: {known})")]
    UnknownComponent {
        /// The name given.
        name: String,
        /// The space's component names.
        known: String,
    },
    /// A behavior string gives a value that is not admissible.
    #[error("`{value}` is not an admissible value of `{name}` ({allowed})")]
    BadValue {
        /// Component name.
        name: String,
        /// The value given.
        value: String,
        /// Description of the admissible values.
        allowed: String,
    },
    /// A behavior string leaves components out (every one is named).
    #[error("no value given for {}", name_list("component", .0))]
    MissingComponents(Vec<String>),
    /// A behavior string gives a component twice.
    #[error("component `{0}` is given twice; give each component once")]
    RepeatedComponent(String),
    /// A behavior string is not `name=value` pairs separated by commas.
    #[error("expected `name=value[,name=value...]`, got `{0}`")]
    Syntax(String),
}

/// The Cartesian product of a list of components, with component weights for similarity.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BehaviorSpace {
    components: Vec<NamedComponent>,
    weights: Vec<f64>,
    #[serde(skip)]
    weight_sum: f64,
    #[serde(skip)]
    size: u64,
    /// Every component's similarity of every pair of values, when every component has at
    /// most [`TABLED_VALUES`] values (see [`BehaviorSpace::similarity`]).
    #[serde(skip)]
    similarity_tables: Option<Vec<SimilarityTable>>,
}

/// Largest component for which a space tables the similarities of all value pairs (a table
/// of at most 512 KiB).
pub const TABLED_VALUES: usize = 256;

/// One component's similarity of every pair of values, row-major.
#[derive(Clone, Debug, PartialEq)]
struct SimilarityTable {
    len: usize,
    pairs: Box<[f64]>,
}

impl SimilarityTable {
    fn of(component: &NamedComponent) -> Self {
        let len = component.len();
        let pairs = (0..len as u16)
            .flat_map(|a| (0..len as u16).map(move |b| component.similarity(a, b)))
            .collect();
        Self { len, pairs }
    }

    #[inline]
    fn get(&self, a: u16, b: u16) -> f64 {
        self.pairs[usize::from(a) * self.len + usize::from(b)]
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SpaceDefinition {
    components: Vec<NamedComponent>,
    /// Empty means equal weights.
    #[serde(default)]
    weights: Vec<f64>,
}

impl<'de> Deserialize<'de> for BehaviorSpace {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let definition = SpaceDefinition::deserialize(deserializer)?;
        let weights = (!definition.weights.is_empty()).then_some(definition.weights);
        Self::with_weights(definition.components, weights).map_err(serde::de::Error::custom)
    }
}

impl BehaviorSpace {
    /// A space with equal component weights.
    pub fn new(components: Vec<NamedComponent>) -> Result<Self, SpaceError> {
        Self::with_weights(components, None)
    }

    /// A space with the given component weights (equal weights when `None`).
    pub fn with_weights(
        components: Vec<NamedComponent>,
        weights: Option<Vec<f64>>,
    ) -> Result<Self, SpaceError> {
        if components.is_empty() || components.len() > MAX_COMPONENTS {
            return Err(SpaceError::ComponentCount(components.len()));
        }
        for (i, component) in components.iter().enumerate() {
            component.validate()?;
            if components[..i].iter().any(|c| c.name == component.name) {
                return Err(SpaceError::DuplicateName(component.name.clone()));
            }
        }
        let weights = weights.unwrap_or_else(|| vec![1.0; components.len()]);
        let weight_sum: f64 = weights.iter().sum();
        if weights.len() != components.len()
            || weights.iter().any(|w| !(w.is_finite() && *w >= 0.0))
            || weight_sum <= 0.0
        {
            return Err(SpaceError::BadWeights);
        }
        let size = components
            .iter()
            .try_fold(1u64, |acc, c| acc.checked_mul(c.len() as u64))
            .ok_or(SpaceError::TooLarge)?;
        let similarity_tables = components
            .iter()
            .all(|c| c.len() <= TABLED_VALUES)
            .then(|| components.iter().map(SimilarityTable::of).collect());
        Ok(Self {
            components,
            weights,
            weight_sum,
            size,
            similarity_tables,
        })
    }

    /// The components, in order.
    pub fn components(&self) -> &[NamedComponent] {
        &self.components
    }

    /// The component weights, in order.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The index of the component named `name`.
    pub fn component_index(&self, name: &str) -> Option<usize> {
        self.components.iter().position(|c| c.name == name)
    }

    /// Number of behaviors in the space.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// A behavior drawn uniformly at random.
    pub fn draw(&self, rng: &mut dyn RngCore) -> Behavior {
        let mut indices = [0u16; MAX_COMPONENTS];
        for (slot, component) in indices.iter_mut().zip(&self.components) {
            *slot = rng.random_range(0..component.len() as u16);
        }
        Behavior::new(&indices[..self.components.len()])
    }

    /// The behavior's position in the space's enumeration order (mixed radix, last
    /// component fastest), in `0..size()`.
    pub fn rank(&self, behavior: &Behavior) -> u64 {
        self.components
            .iter()
            .zip(behavior.indices())
            .fold(0u64, |acc, (c, &i)| acc * c.len() as u64 + u64::from(i))
    }

    /// The behavior at position `rank` of the enumeration order (inverse of [`Self::rank`]).
    pub fn unrank(&self, mut rank: u64) -> Behavior {
        let mut indices = [0u16; MAX_COMPONENTS];
        for (slot, component) in indices[..self.components.len()]
            .iter_mut()
            .zip(&self.components)
            .rev()
        {
            let len = component.len() as u64;
            *slot = (rank % len) as u16;
            rank /= len;
        }
        Behavior::new(&indices[..self.components.len()])
    }

    /// Every behavior of the space, in rank order.
    pub fn iter(&self) -> impl Iterator<Item = Behavior> + '_ {
        (0..self.size).map(|rank| self.unrank(rank))
    }

    /// Whether `behavior` has one in-range index per component of this space.
    pub fn contains(&self, behavior: &Behavior) -> bool {
        behavior.len() == self.components.len()
            && self
                .components
                .iter()
                .zip(behavior.indices())
                .all(|(c, &i)| usize::from(i) < c.len())
    }

    /// The behaviors one change away from `behavior`.
    pub fn neighbours<'a>(&'a self, behavior: &'a Behavior) -> impl Iterator<Item = Behavior> + 'a {
        self.components.iter().enumerate().flat_map(move |(k, c)| {
            c.adjacent(behavior.get(k))
                .map(move |v| behavior.with(k, v))
        })
    }

    /// The number of changes needed to turn `a` into `b` (the lattice distance).
    pub fn changes(&self, a: &Behavior, b: &Behavior) -> u32 {
        self.components
            .iter()
            .zip(a.indices().iter().zip(b.indices()))
            .map(|(c, (&x, &y))| c.changes(x, y))
            .sum()
    }

    /// The largest number of changes between any two behaviors of the space.
    pub fn max_changes(&self) -> u32 {
        self.components
            .iter()
            .map(NamedComponent::max_changes)
            .sum()
    }

    /// Calls `visit` for every behavior exactly `changes` changes away from `center`.
    pub fn for_each_at_changes(
        &self,
        center: &Behavior,
        changes: u32,
        visit: &mut dyn FnMut(Behavior),
    ) {
        self.shell_from(0, *center, center, changes, visit);
    }

    fn shell_from(
        &self,
        component: usize,
        partial: Behavior,
        center: &Behavior,
        remaining: u32,
        visit: &mut dyn FnMut(Behavior),
    ) {
        if component == self.components.len() {
            if remaining == 0 {
                visit(partial);
            }
            return;
        }
        let spare: u32 = self.components[component + 1..]
            .iter()
            .map(NamedComponent::max_changes)
            .sum();
        let c = &self.components[component];
        let here = center.get(component);
        for value in 0..c.len() as u16 {
            let used = c.changes(here, value);
            if used <= remaining && remaining - used <= spare {
                self.shell_from(
                    component + 1,
                    partial.with(component, value),
                    center,
                    remaining - used,
                    visit,
                );
            }
        }
    }

    /// Weighted mean of the component similarities of `a` and `b`, in `[0, 1]`.
    ///
    /// Algorithm 2's inner loop: where every component is small the similarities are read
    /// from tables made at construction (the same numbers, summed in the same order, so
    /// the result is bit for bit the components' own).
    pub fn similarity(&self, a: &Behavior, b: &Behavior) -> f64 {
        let pairs = a.indices().iter().zip(b.indices());
        let total: f64 = match &self.similarity_tables {
            Some(tables) => tables
                .iter()
                .zip(&self.weights)
                .zip(pairs)
                .map(|((t, w), (&x, &y))| w * t.get(x, y))
                .sum(),
            None => self
                .components
                .iter()
                .zip(&self.weights)
                .zip(pairs)
                .map(|((c, w), (&x, &y))| w * c.similarity(x, y))
                .sum(),
        };
        (total / self.weight_sum).clamp(0.0, 1.0)
    }

    /// Displays a behavior in real units, e.g. `speed=3.5 m/s, padding=0.4 m`.
    pub fn display<'a>(&'a self, behavior: &'a Behavior) -> BehaviorDisplay<'a> {
        BehaviorDisplay {
            space: self,
            behavior,
        }
    }

    /// Parses `name=value[,name=value...]` (every component exactly once, any order;
    /// numbers must be finite and on the grid).
    pub fn parse(&self, text: &str) -> Result<Behavior, SpaceError> {
        let pairs = text
            .split(',')
            .filter(|p| !p.trim().is_empty())
            .map(|pair| {
                pair.split_once('=')
                    .ok_or_else(|| SpaceError::Syntax(text.to_owned()))
            })
            .collect::<Result<Vec<_>, _>>()?;
        self.from_named_values(pairs)
    }

    /// A behavior from `(component name, value as text)` pairs, every component exactly
    /// once, in any order. Values are numbers on a numeric grid (never `NaN` or an
    /// infinity), labels of a categorical component, or what a custom kind parses.
    pub fn from_named_values<'a>(
        &self,
        pairs: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Behavior, SpaceError> {
        let mut indices: [Option<u16>; MAX_COMPONENTS] = [None; MAX_COMPONENTS];
        for (name, value) in pairs {
            let name = name.trim();
            let k = self
                .component_index(name)
                .ok_or_else(|| SpaceError::UnknownComponent {
                    name: name.to_owned(),
                    known: self.component_names(),
                })?;
            let component = &self.components[k];
            let index = component
                .index_of_text(value)
                .ok_or_else(|| SpaceError::BadValue {
                    name: name.to_owned(),
                    value: value.trim().to_owned(),
                    allowed: component.describe_values(),
                })?;
            if indices[k].replace(index).is_some() {
                return Err(SpaceError::RepeatedComponent(name.to_owned()));
            }
        }
        let missing: Vec<String> = self
            .components
            .iter()
            .zip(indices)
            .filter(|(_, index)| index.is_none())
            .map(|(component, _)| component.name.clone())
            .collect();
        if !missing.is_empty() {
            return Err(SpaceError::MissingComponents(missing));
        }
        let resolved = indices.map(|index| index.unwrap_or(0));
        Ok(Behavior::new(&resolved[..self.components.len()]))
    }

    fn component_names(&self) -> String {
        self.components
            .iter()
            .map(|c| c.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// `component `a`` or `components `a`, `b``.
fn name_list(what: &str, names: &[String]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    let plural = if names.len() == 1 { "" } else { "s" };
    format!("{what}{plural} {}", quoted.join(", "))
}

impl SimilarityMeasure<Behavior> for BehaviorSpace {
    fn similarity(&self, a: &Behavior, b: &Behavior) -> f64 {
        BehaviorSpace::similarity(self, a, b)
    }
}

/// Displays a behavior with its real values and units (see [`BehaviorSpace::display`]).
pub struct BehaviorDisplay<'a> {
    space: &'a BehaviorSpace,
    behavior: &'a Behavior,
}

impl fmt::Display for BehaviorDisplay<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, (component, &index)) in self
            .space
            .components
            .iter()
            .zip(self.behavior.indices())
            .enumerate()
        {
            if k > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{}={}", component.name, component.display_value(index))?;
            if !component.unit.is_empty() {
                write!(f, " {}", component.unit)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{SpaceShape, behavior_spaces};
    use proptest::prelude::*;
    use rand::SeedableRng;
    use std::collections::HashSet;

    fn movement() -> BehaviorSpace {
        BehaviorSpace::new(vec![
            NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 20).unwrap(),
            NamedComponent::numeric("padding", "m", 0.1, 0.1, 20).unwrap(),
        ])
        .unwrap()
    }

    #[test]
    fn size_rank_and_iteration_agree() {
        let space = movement();
        assert_eq!(space.size(), 400);
        let all: Vec<_> = space.iter().collect();
        assert_eq!(all.len(), 400);
        for (rank, b) in all.iter().enumerate() {
            assert_eq!(space.rank(b), rank as u64);
        }
        assert_eq!(all.iter().collect::<HashSet<_>>().len(), 400);
    }

    #[test]
    fn behavior_similarity_is_the_mean_of_component_similarities() {
        let space = movement();
        // speed 1.0 vs 3.5: 1 - 2.5/9.5; padding 0.4 vs 0.4: 1. Mean: (1 - 2.5/9.5 + 1) / 2.
        let a = space.parse("speed=1.0,padding=0.4").unwrap();
        let b = space.parse("padding=0.4, speed=3.5").unwrap();
        let expected = (1.0 - 2.5 / 9.5 + 1.0) / 2.0;
        assert!((space.similarity(&a, &b) - expected).abs() < 1e-12);
    }

    #[test]
    fn weighted_similarity() {
        let space =
            BehaviorSpace::with_weights(movement().components().to_vec(), Some(vec![3.0, 1.0]))
                .unwrap();
        let a = Behavior::new(&[0, 0]);
        let b = Behavior::new(&[19, 0]);
        // speed similarity 0 with weight 3, padding similarity 1 with weight 1: 1/4.
        assert!((space.similarity(&a, &b) - 0.25).abs() < 1e-12);
    }

    #[test]
    fn parse_errors_name_the_problem() {
        let space = movement();
        assert_eq!(
            space.parse("speed=3.5").unwrap_err().to_string(),
            "no value given for component `padding`"
        );
        assert_eq!(
            space.parse("turbo=").unwrap_err().to_string(),
            "unknown component `turbo` (known: speed, padding)"
        );
        assert_eq!(
            space.parse("").unwrap_err().to_string(),
            "no value given for components `speed`, `padding`"
        );
        assert_eq!(
            space.parse("speed=3.5,speed=4.0,padding=0.4").unwrap_err(),
            SpaceError::RepeatedComponent("speed".into())
        );
        for not_a_value in ["NaN", "inf", "-inf", "+infinity"] {
            assert_eq!(
                space
                    .parse(&format!("speed={not_a_value},padding=0.4"))
                    .unwrap_err()
                    .to_string(),
                format!(
                    "`{not_a_value}` is not an admissible value of `speed` (0.5 to 10 in steps of 0.5)"
                )
            );
        }
        assert!(matches!(
            space.parse("speed=3.5,padding=0.4,turbo=1"),
            Err(SpaceError::UnknownComponent { .. })
        ));
        let err = space.parse("speed=30,padding=0.4").unwrap_err();
        assert_eq!(
            err.to_string(),
            "`30` is not an admissible value of `speed` (0.5 to 10 in steps of 0.5)"
        );
        assert_eq!(
            space
                .display(&space.parse("speed=3.5,padding=0.4").unwrap())
                .to_string(),
            "speed=3.5 m/s, padding=0.4 m"
        );
    }

    #[test]
    fn named_values_give_behaviors() {
        let space = movement();
        let b = space
            .from_named_values([("padding", "0.4"), ("speed", "3.5")])
            .unwrap();
        assert_eq!(b, space.parse("speed=3.5,padding=0.4").unwrap());
        assert!(matches!(
            space.from_named_values([("speed", "3.5")]),
            Err(SpaceError::MissingComponents(n)) if n == ["padding"]
        ));
    }

    #[test]
    fn neighbours_are_one_change_away() {
        let space = movement();
        let corner = Behavior::new(&[0, 0]);
        let n: Vec<_> = space.neighbours(&corner).collect();
        assert_eq!(n, vec![Behavior::new(&[1, 0]), Behavior::new(&[0, 1])]);
        let inner = Behavior::new(&[5, 5]);
        assert_eq!(space.neighbours(&inner).count(), 4);
    }

    #[test]
    fn bad_spaces_are_rejected() {
        let c = movement().components().to_vec();
        assert!(matches!(
            BehaviorSpace::new(vec![c[0].clone(), c[0].clone()]),
            Err(SpaceError::DuplicateName(_))
        ));
        assert!(matches!(
            BehaviorSpace::new(vec![]),
            Err(SpaceError::ComponentCount(0))
        ));
        assert!(matches!(
            BehaviorSpace::with_weights(c, Some(vec![0.0, 0.0])),
            Err(SpaceError::BadWeights)
        ));
    }

    #[test]
    fn space_round_trips_through_ron() {
        let space = movement();
        let text = ron::to_string(&space).unwrap();
        let back: BehaviorSpace = ron::from_str(&text).unwrap();
        assert_eq!(back, space);
    }

    fn small_space() -> impl Strategy<Value = BehaviorSpace> {
        behavior_spaces(SpaceShape {
            values: 1..=4,
            ..SpaceShape::small()
        })
    }

    proptest! {
        #[test]
        fn parsing_arbitrary_text_never_panics_and_yields_members(
            space in small_space(),
            text in "[c0-9v=,.a-zNI +-]{0,40}",
            bytes in prop::collection::vec(any::<u8>(), 0..64),
        ) {
            for input in [text, String::from_utf8_lossy(&bytes).into_owned()] {
                if let Ok(behavior) = space.parse(&input) {
                    prop_assert!(space.contains(&behavior));
                    prop_assert_eq!(input.matches('=').count(), space.components().len());
                }
            }
        }

        #[test]
        fn similarity_stays_in_unit_interval_and_is_symmetric(space in small_space(), seed in any::<u64>()) {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let a = space.draw(&mut rng);
            let b = space.draw(&mut rng);
            let s = space.similarity(&a, &b);
            prop_assert!((0.0..=1.0).contains(&s));
            prop_assert_eq!(s, space.similarity(&b, &a));
            prop_assert_eq!(space.similarity(&a, &a), 1.0);
        }

        #[test]
        fn tabled_similarity_is_the_components_own_bit_for_bit(
            space in small_space(),
            weights in prop::collection::vec(0.0f64..5.0, 3),
            seed in any::<u64>(),
        ) {
            let n = space.components().len();
            let mut weights = weights[..n].to_vec();
            weights[0] += 1.0;
            let space = BehaviorSpace::with_weights(space.components().to_vec(), Some(weights)).unwrap();
            prop_assert!(space.similarity_tables.is_some());
            // The same space with a component too large to table takes the other path.
            let mut large = space.components().to_vec();
            large.push(NamedComponent::numeric("large", "", 0.0, 1.0, TABLED_VALUES as u16 + 1).unwrap());
            let mut large_weights = space.weights().to_vec();
            large_weights.push(0.0);
            let large = BehaviorSpace::with_weights(large, Some(large_weights)).unwrap();
            prop_assert!(large.similarity_tables.is_none());
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            for _ in 0..20 {
                let (a, b) = (space.draw(&mut rng), space.draw(&mut rng));
                let total: f64 = space
                    .components()
                    .iter()
                    .zip(space.weights())
                    .zip(a.indices().iter().zip(b.indices()))
                    .map(|((c, w), (&x, &y))| w * c.similarity(x, y))
                    .sum();
                let expected = (total / space.weights().iter().sum::<f64>()).clamp(0.0, 1.0);
                prop_assert_eq!(space.similarity(&a, &b).to_bits(), expected.to_bits());
                let extended = |b: &Behavior| Behavior::new(&[b.indices(), &[7]].concat());
                let (a_large, b_large) = (extended(&a), extended(&b));
                prop_assert_eq!(large.similarity(&a_large, &b_large).to_bits(), expected.to_bits());
            }
        }

        #[test]
        fn shells_partition_the_space(space in small_space(), seed in any::<u64>()) {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let center = space.draw(&mut rng);
            let mut seen = HashSet::new();
            for d in 0..=space.max_changes() {
                space.for_each_at_changes(&center, d, &mut |b| {
                    assert_eq!(space.changes(&center, &b), d);
                    assert!(seen.insert(b));
                });
            }
            prop_assert_eq!(seen.len() as u64, space.size());
        }
    }
}
