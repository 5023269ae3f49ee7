//! [`ValueCounts`]: how many commands (or any weighed events) each value of each component
//! has seen, the statistic a searcher that learns per component value keeps (the
//! cause-aware search's, a user's Thompson sampling over values).

use cbr_core::Behavior;

/// Counts by component value: `add(behavior)` counts one event at each of the behavior's
/// values, `at(k, v)` reads the count of component `k` at value index `v` (0 for a value
/// never seen).
///
/// ```
/// use trust::search::ValueCounts;
/// use cbr_core::Behavior;
/// let mut counts = ValueCounts::default();
/// counts.add(&Behavior::new(&[2, 0]));
/// counts.add_weighted(&Behavior::new(&[2, 1]), 0.5);
/// assert_eq!((counts.total(), counts.at(0, 2), counts.at(1, 1), counts.at(1, 7)), (1.5, 1.5, 0.5, 0.0));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ValueCounts {
    total: f64,
    /// `by_value[k][v]`: the count of component `k` at value index `v`.
    by_value: Vec<Vec<f64>>,
}

impl ValueCounts {
    /// Counts one event at each value of `behavior`.
    pub fn add(&mut self, behavior: &Behavior) {
        self.add_weighted(behavior, 1.0);
    }

    /// Counts an event of weight `weight` at each value of `behavior`.
    pub fn add_weighted(&mut self, behavior: &Behavior, weight: f64) {
        self.total += weight;
        if self.by_value.len() < behavior.len() {
            self.by_value.resize(behavior.len(), Vec::new());
        }
        for (k, &v) in behavior.indices().iter().enumerate() {
            let counts = &mut self.by_value[k];
            let v = usize::from(v);
            if counts.len() <= v {
                counts.resize(v + 1, 0.0);
            }
            counts[v] += weight;
        }
    }

    /// The count of component `component` at value index `value`.
    pub fn at(&self, component: usize, value: usize) -> f64 {
        self.by_value
            .get(component)
            .and_then(|c| c.get(value))
            .copied()
            .unwrap_or(0.0)
    }

    /// Every event counted (their summed weights).
    pub fn total(&self) -> f64 {
        self.total
    }
}
