//! The similarity measure abstraction: how alike two things are, on a scale from 0 to 1.

/// A similarity measure over values of type `T`.
///
/// Implementations return a number in `[0, 1]`; 1 means "as alike as possible". A measure
/// need not be symmetric (the paper's set similarity is not).
pub trait SimilarityMeasure<T: ?Sized> {
    /// How similar `a` (the query side) is to `b` (the stored side).
    fn similarity(&self, a: &T, b: &T) -> f64;
}

impl<T: ?Sized, F: Fn(&T, &T) -> f64> SimilarityMeasure<T> for F {
    fn similarity(&self, a: &T, b: &T) -> f64 {
        self(a, b)
    }
}
