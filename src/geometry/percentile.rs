//! Percentiles of a sorted sample by the nearest-rank method (the one every error figure of
//! the toolkit reports).

/// The `percent`-th percentile of ascending, non-empty `sorted` by the nearest-rank method.
#[must_use]
pub fn nearest_rank(sorted: &[f64], percent: usize) -> f64 {
    let rank = (percent * sorted.len()).div_ceil(100).max(1);
    sorted[rank.min(sorted.len()) - 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_percentiles_of_one_to_ten() {
        let e: Vec<f64> = (1..=10).map(f64::from).collect();
        // Ranks ⌈0.5·10⌉ = 5, ⌈0.75·10⌉ = 8, ⌈0.95·10⌉ = 10.
        assert_eq!(nearest_rank(&e, 50), 5.0);
        assert_eq!(nearest_rank(&e, 75), 8.0);
        assert_eq!(nearest_rank(&e, 95), 10.0);
        assert_eq!(nearest_rank(&[3.0], 50), 3.0);
    }
}
