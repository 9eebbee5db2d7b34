//! Statistics of measured timings: what `--bench`, the window's `--bench-panel` and the page's
//! `data-frame-ms` report.

/// (min, median) of a list of timings.
pub fn min_median(times: &[f64]) -> (f64, f64) {
    let mut sorted = times.to_vec();
    sorted.sort_by(f64::total_cmp);
    let min = sorted.first().copied().unwrap_or(f64::NAN);
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN);
    (min, median)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if the minimum or the median is not taken from the sorted list (the median of an even
    // count is its upper middle, as BENCHMARKS.md's figures were taken), or an empty list is not NaN.
    #[test]
    fn min_and_median_of_timings() {
        assert_eq!(min_median(&[3.0, 1.0, 2.0]), (1.0, 2.0));
        assert_eq!(min_median(&[4.0, 1.0, 3.0, 2.0]), (1.0, 3.0));
        let (min, median) = min_median(&[]);
        assert!(min.is_nan() && median.is_nan());
    }
}
