//! One counting-sort CSR builder, shared by the sparse cost matrix and the local searches.

/// CSR of `(key, value)` pairs over keys `0..n_keys` by a counting sort: `offs[k]..offs[k + 1]`
/// are key `k`'s values, in input order.
pub(crate) fn csr<T: Copy + Default>(
    n_keys: usize,
    pairs: impl Iterator<Item = (usize, T)> + Clone,
) -> (Vec<usize>, Vec<T>) {
    let mut offs = vec![0; n_keys + 1];
    pairs.clone().for_each(|(k, _)| offs[k + 1] += 1);
    for k in 0..n_keys {
        offs[k + 1] += offs[k];
    }
    let (mut fill, mut vals) = (offs.clone(), vec![T::default(); offs[n_keys]]);
    for (k, v) in pairs {
        vals[fill[k]] = v;
        fill[k] += 1;
    }
    (offs, vals)
}
