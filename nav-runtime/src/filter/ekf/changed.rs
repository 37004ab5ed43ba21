//! The entries of `P` a first-order prediction over a model's
//! [`Structure`] changes (docs/runtime.md, "Prediction"): the changed rows
//! of `Phi` (and, mirrored, their columns) and the `Qd` entries outside
//! them. Everything else is the `P` before the step, so a `P` that was
//! clean stays clean there, and only these entries are saved before the
//! step, checked after it and restored if it fails: about a third of the
//! matrix for SDINS-25 (9 changed rows of 25), where saving and checking
//! the whole `P` cost as much as a fifth of the propagation.

use nalgebra::{SMatrix, SVector};

use crate::propagation::Structure;
use crate::real::Real;

/// What a prediction over a structure changes, fixed at compile time
/// ([`changed_entries`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct ChangedEntries<const N: usize> {
    /// `true` for the changed rows.
    pub rows: [bool; N],
    /// `false` if the structure has an index outside `N x N` (a hand-made
    /// structure the kernel would refuse): the whole-matrix path runs.
    pub valid: bool,
    /// `Some(first)` if the changed rows are consecutive from `first` (as
    /// for every INS error state): they are then one run of the storage,
    /// saved and checked as one slice.
    pub consecutive: Option<usize>,
    /// The number of `Qd` entries outside the changed rows (none for the
    /// INS error states, whose process noise drives changed rows only).
    pub outside_noise: usize,
}

/// [`ChangedEntries`] of `structure` (`None`: nothing to save by rows).
pub(super) const fn changed_entries<const N: usize>(
    structure: Option<Structure<'static>>,
) -> ChangedEntries<N> {
    let mut changed = ChangedEntries {
        rows: [false; N],
        valid: false,
        consecutive: None,
        outside_noise: 0,
    };
    let Some(s) = structure else {
        return changed;
    };
    let mut k = 0;
    while k < s.rows.len() {
        if s.rows[k] >= N {
            return changed;
        }
        changed.rows[s.rows[k]] = true;
        k += 1;
    }
    k = 0;
    while k < s.noise.len() {
        let (i, j) = s.noise[k];
        if i >= N || j >= N {
            return changed;
        }
        if !(changed.rows[i] || changed.rows[j]) {
            changed.outside_noise += 1;
        }
        k += 1;
    }
    // Every index is inside `N x N` from here on: the accesses below use
    // `get` all the same, so that no path can panic.
    changed.valid = true;
    let mut consecutive = !s.rows.is_empty();
    k = 1;
    while k < s.rows.len() {
        consecutive &= s.rows[k] == s.rows[k - 1] + 1;
        k += 1;
    }
    if consecutive {
        changed.consecutive = Some(s.rows[0]);
    }
    changed
}

/// The changed rows of `p` as one slice of its storage, if consecutive.
#[inline(always)]
fn consecutive_rows<'p, T: Real, const N: usize>(
    p: &'p SMatrix<T, N, N>,
    structure: &Structure<'_>,
    changed: &ChangedEntries<N>,
) -> Option<&'p [T]> {
    let first = changed.consecutive?;
    p.as_slice()
        .get(first * N..(first + structure.rows.len()) * N)
}

/// The `Qd` positions outside the changed rows and columns, in the order of
/// their slots in the saved entries (the others are saved and checked with
/// their rows).
#[inline(always)]
fn outside<'s, const N: usize>(
    structure: &Structure<'s>,
    changed: &'s ChangedEntries<N>,
) -> impl Iterator<Item = (usize, usize)> + 's {
    let changed_row = |k: usize| changed.rows.get(k).copied().unwrap_or(true);
    structure
        .noise
        .iter()
        .copied()
        .filter(move |&(i, j)| !(changed_row(i) || changed_row(j)))
}

/// `P[i, j]` of the column-major storage, `None` outside it (never for a
/// valid structure; no index can panic).
#[inline(always)]
fn entry<T: Real, const N: usize>(p: &SMatrix<T, N, N>, (i, j): (usize, usize)) -> Option<T> {
    p.data.0.get(j).and_then(|column| column.get(i)).copied()
}

crate::dispatch::avx_dispatch! {
    /// Copies the changed rows of the symmetric `p` (column-major: column
    /// `i` is row `i`) into the first rows of `saved`, then the `Qd`
    /// entries outside them into the slots after those (they lie in the
    /// block of unchanged rows, so they fit). Runs compiled for AVX where
    /// the CPU has it.
    pub(super) fn save_changed<T: Real, const N: usize>(
        saved: &mut [[T; N]; N],
        p: &SMatrix<T, N, N>,
        structure: &Structure<'_>,
        changed: &ChangedEntries<N>,
    ) => save_changed_pass;
}

/// The copy of [`save_changed`].
#[inline(always)]
fn save_changed_pass<T: Real, const N: usize, const AVX: bool, const FUSED: bool>(
    saved: &mut [[T; N]; N],
    p: &SMatrix<T, N, N>,
    structure: &Structure<'_>,
    changed: &ChangedEntries<N>,
) {
    let (rows, rest) = saved.split_at_mut(structure.rows.len());
    match consecutive_rows(p, structure, changed) {
        Some(run) => rows.as_flattened_mut().copy_from_slice(run),
        None => {
            for (row, &i) in rows.iter_mut().zip(structure.rows) {
                if let Some(column) = p.data.0.get(i) {
                    *row = *column;
                }
            }
        }
    }
    if changed.outside_noise == 0 {
        return;
    }
    for (slot, at) in rest
        .as_flattened_mut()
        .iter_mut()
        .zip(outside(structure, changed))
    {
        if let Some(value) = entry(p, at) {
            *slot = value;
        }
    }
}

/// Puts back what [`save_changed`] saved (the step failed).
pub(super) fn restore_changed<T: Real, const N: usize>(
    p: &mut SMatrix<T, N, N>,
    saved: &[[T; N]; N],
    structure: &Structure<'_>,
    changed: &ChangedEntries<N>,
) {
    let cols = &mut p.data.0;
    let (rows, rest) = saved.split_at(structure.rows.len());
    for (&v, (i, j)) in rest.as_flattened().iter().zip(outside(structure, changed)) {
        for (c, r) in [(j, i), (i, j)] {
            if let Some(x) = cols.get_mut(c).and_then(|column| column.get_mut(r)) {
                *x = v;
            }
        }
    }
    for (row, &i) in rows.iter().zip(structure.rows) {
        if let Some(column) = cols.get_mut(i) {
            *column = *row;
        }
        for (col, &v) in cols.iter_mut().zip(row) {
            if let Some(x) = col.get_mut(i) {
                *x = v;
            }
        }
    }
}

/// The diagonal of `P` before the step, from `p` after it and what
/// [`save_changed`] saved (for the repair; off the common path).
pub(super) fn saved_diagonal<T: Real, const N: usize>(
    p: &SMatrix<T, N, N>,
    saved: &[[T; N]; N],
    structure: &Structure<'_>,
    changed: &ChangedEntries<N>,
) -> SVector<T, N> {
    let mut diagonal = p.diagonal();
    let (rows, rest) = saved.split_at(structure.rows.len());
    for (&v, (i, j)) in rest.as_flattened().iter().zip(outside(structure, changed)) {
        if let (true, Some(d)) = (i == j, diagonal.get_mut(i)) {
            *d = v;
        }
    }
    for (row, &i) in rows.iter().zip(structure.rows) {
        if let (Some(&v), Some(d)) = (row.get(i), diagonal.get_mut(i)) {
            *d = v;
        }
    }
    diagonal
}

crate::dispatch::avx_dispatch! {
    /// The clean check (`covariance_is_clean`) over the changed entries, in
    /// the same branch-free way: every changed row finite (its sum is; an
    /// overflowing sum only sends the caller to the exact path) with a
    /// positive diagonal, every `Qd` entry outside them finite and positive
    /// on the diagonal. Runs compiled for AVX where the CPU has it.
    pub(super) fn changed_are_clean<T: Real, const N: usize>(
        p: &SMatrix<T, N, N>,
        structure: &Structure<'_>,
        changed: &ChangedEntries<N>,
    ) -> bool => changed_are_clean_pass;
}

/// The pass of [`changed_are_clean`].
#[inline(always)]
fn changed_are_clean_pass<T: Real, const N: usize, const AVX: bool, const FUSED: bool>(
    p: &SMatrix<T, N, N>,
    structure: &Structure<'_>,
    changed: &ChangedEntries<N>,
) -> bool {
    let mut acc = [T::zero(); 8];
    match consecutive_rows(p, structure, changed) {
        Some(run) => add_to(&mut acc, run),
        None => {
            for column in structure.rows.iter().filter_map(|&i| p.data.0.get(i)) {
                add_to(&mut acc, column);
            }
        }
    }
    let mut diagonal_ok = true;
    for &i in structure.rows {
        let d = entry(p, (i, i)).unwrap_or(T::zero());
        diagonal_ok &= d > T::zero() && d <= T::MAX;
    }
    if changed.outside_noise > 0 {
        for (i, j) in outside(structure, changed) {
            let v = entry(p, (i, j)).unwrap_or(T::zero() / T::zero());
            diagonal_ok &= v.is_finite() && (i != j || v > T::zero());
        }
    }
    diagonal_ok && acc.iter().fold(T::zero(), |s, a| s + *a).is_finite()
}

/// `acc += values` in lanes of eight (a sum that is finite if every value
/// is, as in `covariance_is_clean`).
#[inline(always)]
fn add_to<T: Real>(acc: &mut [T; 8], values: &[T]) {
    let mut chunks = values.chunks_exact(8);
    for chunk in &mut chunks {
        for (a, x) in acc.iter_mut().zip(chunk) {
            *a += *x;
        }
    }
    for (a, x) in acc.iter_mut().zip(chunks.remainder()) {
        *a += *x;
    }
}
