//! The sparse cost matrix every sparse solve reads: CSR rows, absent entries forbidden.

use crate::assign::csr::csr;
use crate::error::{CoreError, CoreResult};

/// A sparse cost matrix in CSR form; absent entries are forbidden pairs. Duplicate entries
/// are allowed and the cheapest one counts.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseCosts {
    n_rows: usize,
    n_cols: usize,
    row_offsets: Vec<usize>,
    col_indices: Vec<usize>,
    values: Vec<f64>,
}

impl SparseCosts {
    /// Validates a CSR matrix: `row_offsets` has `n_rows + 1` non-decreasing entries from 0 to
    /// `col_indices.len() == values.len()`, every column index is `< n_cols`, values finite.
    ///
    /// ```
    /// use passive_assoc_core::assign::lap::SparseCosts;
    /// let c = SparseCosts::new(2, 2, vec![0, 1, 3], vec![1, 0, 1], vec![-1.0, -2.0, -3.0]);
    /// assert!(c.is_ok());
    /// ```
    pub fn new(
        n_rows: usize,
        n_cols: usize,
        row_offsets: Vec<usize>,
        col_indices: Vec<usize>,
        values: Vec<f64>,
    ) -> CoreResult<Self> {
        if row_offsets.len().checked_sub(1) != Some(n_rows) {
            let got = row_offsets.len();
            return Err(CoreError::shape(
                "row_offsets",
                format!("length {got} is not n_rows + 1 = {}", n_rows + 1),
            ));
        }
        if col_indices.len() != values.len() {
            let (a, b) = (col_indices.len(), values.len());
            return Err(CoreError::shape(
                "values",
                format!("length {b} differs from col_indices length {a}"),
            ));
        }
        if row_offsets[0] != 0 || row_offsets[n_rows] != values.len() {
            return Err(CoreError::out_of_range(
                "row_offsets",
                format!(
                    "must start at 0 and end at the number of entries {}",
                    values.len()
                ),
            ));
        }
        if let Some(r) = (0..n_rows).find(|&r| row_offsets[r] > row_offsets[r + 1]) {
            return Err(CoreError::out_of_range(
                "row_offsets",
                format!("decreases after row {r}"),
            ));
        }
        if let Some(k) = col_indices.iter().position(|&j| j >= n_cols) {
            let j = col_indices[k];
            return Err(CoreError::out_of_range(
                "col_indices",
                format!("entry {k} is {j} but n_cols is {n_cols}"),
            ));
        }
        crate::error::ensure_finite("values", &values)?;
        crate::assign::check_cost_range("values", &values)?;
        Ok(Self {
            n_rows,
            n_cols,
            row_offsets,
            col_indices,
            values,
        })
    }

    /// Builds from `(row, col, cost)` triplets in any order, validated like [`SparseCosts::new`].
    pub fn from_triplets(
        n_rows: usize,
        n_cols: usize,
        triplets: &[(usize, usize, f64)],
    ) -> CoreResult<Self> {
        if let Some(k) = triplets.iter().position(|t| t.0 >= n_rows) {
            let i = triplets[k].0;
            return Err(CoreError::out_of_range(
                "triplets",
                format!("entry {k} has row {i} but n_rows is {n_rows}"),
            ));
        }
        let (row_offsets, entries) = csr(n_rows, triplets.iter().map(|&(i, j, c)| (i, (j, c))));
        let (col_indices, values) = entries.into_iter().unzip();
        Self::new(n_rows, n_cols, row_offsets, col_indices, values)
    }

    /// CSR parts built by the S-D solvers, valid by construction (checked in debug builds).
    pub(crate) fn from_csr_unchecked(
        n_rows: usize,
        n_cols: usize,
        row_offsets: Vec<usize>,
        col_indices: Vec<usize>,
        values: Vec<f64>,
    ) -> Self {
        debug_assert!(Self::new(
            n_rows,
            n_cols,
            row_offsets.clone(),
            col_indices.clone(),
            values.clone()
        )
        .is_ok());
        Self {
            n_rows,
            n_cols,
            row_offsets,
            col_indices,
            values,
        }
    }

    /// Gives back `(row_offsets, col_indices, values)`, so a caller that builds one matrix per
    /// iteration can reuse their allocations.
    pub(crate) fn into_parts(self) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        (self.row_offsets, self.col_indices, self.values)
    }

    /// Row `i`'s entries as a range into [`SparseCosts::col_indices`] and the values.
    pub(crate) fn span(&self, i: usize) -> std::ops::Range<usize> {
        self.row_offsets[i]..self.row_offsets[i + 1]
    }

    pub(crate) fn col_indices(&self) -> &[usize] {
        &self.col_indices
    }

    pub(crate) fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    pub fn n_rows(&self) -> usize {
        self.n_rows
    }

    pub fn n_cols(&self) -> usize {
        self.n_cols
    }

    /// The stored costs, row by row.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The transpose (columns become rows), valid by construction.
    pub(super) fn transposed(&self) -> Self {
        let entries = (0..self.n_rows).flat_map(|i| {
            let span = self.row_offsets[i]..self.row_offsets[i + 1];
            (self.col_indices[span.clone()].iter())
                .zip(&self.values[span])
                .map(move |(&j, &c)| (j, (i, c)))
        });
        let (row_offsets, entries) = csr(self.n_cols, entries);
        let (col_indices, values) = entries.into_iter().unzip();
        Self::from_csr_unchecked(self.n_cols, self.n_rows, row_offsets, col_indices, values)
    }

    /// The cheapest stored entry at (i, j) (`+inf` if none).
    pub(super) fn cheapest(&self, i: usize, j: usize) -> f64 {
        self.row(i)
            .filter(|e| e.0 == j)
            .map(|e| e.1)
            .fold(f64::INFINITY, f64::min)
    }

    pub(super) fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let span = self.row_offsets[i]..self.row_offsets[i + 1];
        self.col_indices[span.clone()]
            .iter()
            .copied()
            .zip(self.values[span].iter().copied())
    }
}
