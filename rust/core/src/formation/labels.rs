//! Every input row into exactly one output group: the baseline report whose chosen set holds
//! it, or none. In the independent mode several sets may hold one row (paper line 132); the
//! row then belongs to the tightest of them (smallest radius, ties by the lower baseline
//! index), and `times_chosen` counts them all.

/// `(labels, times_chosen)` over `n_rows` rows from the `B × S` chosen rows and the radii
/// (NaN = no association).
pub(crate) fn partition(rows: &[i64], radius: &[f64], n_rows: usize) -> (Vec<i64>, Vec<i64>) {
    let n_sensors = rows.len() / radius.len().max(1);
    let mut order: Vec<usize> = (0..radius.len()).filter(|&b| !radius[b].is_nan()).collect();
    order.sort_by(|&a, &b| radius[a].total_cmp(&radius[b]).then(a.cmp(&b)));
    let mut labels = vec![-1i64; n_rows];
    let mut times = vec![0i64; n_rows];
    for b in order {
        for &row in &rows[b * n_sensors..(b + 1) * n_sensors] {
            if let Ok(row) = usize::try_from(row) {
                times[row] += 1;
                if labels[row] < 0 {
                    labels[row] = b as i64;
                }
            }
        }
    }
    (labels, times)
}

#[cfg(test)]
mod tests {
    use super::partition;

    #[test]
    fn a_shared_row_goes_to_the_tightest_set() {
        // Two baselines (rows 0 and 1) both chose row 3; baseline 1 clusters tighter.
        // A third baseline (row 2) has no association.
        let rows = [0, 3, -1, 1, 3, 4, 2, -1, -1];
        let radius = [5.0, 2.0, f64::NAN];
        let (labels, times) = partition(&rows, &radius, 6);
        assert_eq!(labels, vec![0, 1, -1, 1, 1, -1]);
        assert_eq!(times, vec![1, 1, 0, 2, 1, 0]);
    }
}
