//! What the figures of series over trials share: a moving average of a window of trials,
//! and the trials a long curve is drawn through.

/// Trials averaged by the moving average of the learning-curve plots.
pub(super) const MOVING_AVERAGE_WINDOW: usize = 25;

/// The moving average of `values` over the last `window` values (fewer at the start).
pub(super) fn moving_average(values: &[f64], window: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(values.len());
    let mut sum = 0.0;
    for (i, v) in values.iter().enumerate() {
        sum += v;
        if i >= window {
            sum -= values[i - window];
        }
        out.push(sum / (i + 1).min(window) as f64);
    }
    out
}

/// Points a curve of `n` trials is drawn through: at most `points` (and the last),
/// evenly spaced, the first and the last always (a moving average of
/// [`MOVING_AVERAGE_WINDOW`] changes little from one trial to the next).
pub(super) fn thinned(n: usize, points: usize) -> impl Iterator<Item = usize> {
    let step = n.div_ceil(points).max(1);
    (0..n)
        .step_by(step)
        .chain((n > 0 && !(n - 1).is_multiple_of(step)).then(|| n - 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moving_average_by_hand() {
        // Window 2 over 1, 3, 5, 7: 1, (1+3)/2, (3+5)/2, (5+7)/2.
        assert_eq!(
            moving_average(&[1.0, 3.0, 5.0, 7.0], 2),
            vec![1.0, 2.0, 4.0, 6.0]
        );
    }

    #[test]
    fn curves_are_thinned_to_about_200_points() {
        assert_eq!(thinned(3, 200).collect::<Vec<_>>(), [0, 1, 2]);
        assert_eq!(thinned(10, 4).collect::<Vec<_>>(), [0, 3, 6, 9]);
        let points: Vec<usize> = thinned(500, 200).collect();
        assert_eq!(
            (points.len(), points[1], points.last()),
            (168, 3, Some(&499))
        );
        assert_eq!(thinned(0, 200).count(), 0);
    }
}
