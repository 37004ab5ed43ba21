//! `P <- Phi P Phi^T + Qd` over the structure of `Phi` and `Qd` that `model!`
//! knows at compile time. The generated `Model::propagate_covariance` evaluates
//! the nonzero coefficients and noise entries (symbolic, CSE'd) and calls
//! [`propagate_static`], compiled for the model's constant [`Structure`]
//! ([`StaticStructure`]); [`propagate`] takes a structure at run time (for
//! hand-written models and tests) and gives the same results bit for bit.
//!
//! Why a loop over tables and not generated straight-line code: the product
//! unrolled entry by entry is, for a 25-state INS, about 48 KB of scalar code
//! that runs front-end bound, and unrolled row by row it spills registers;
//! here a row of `Phi P` is an `[T; N]` (`T` the model's scalar), each nonzero of `Phi` is one
//! vectorized row operation, and the structure costs a table read per nonzero.
//!
//! With `Phi = I + C` (Euler, continuous models, and discrete ones with a unit
//! diagonal in every changed row) or `Phi = C` (other discrete ones), only
//! the rows of `Phi` that are not unit rows ("changed rows", set `D`) alter `P`:
//! 1. `A = (Phi P)[D, :]`: per changed row, `P[i, :]` (Euler) plus a linear
//!    combination of rows of `P`, vectorized over the columns;
//! 2. `P[D, U] = A[:, U]` (`U`, the unit rows: `Phi[j, :] = e_j`), mirrored;
//! 3. `P[D, D] = A Phi[D, :]^T`, upper triangle, mirrored;
//! 4. `P[U, U]` is untouched; `Qd` is added at its nonzeros.
//!
//! Operations: `sum_D nnz(row) * N` multiply-adds for step 1, `nnz(row s)`
//! per pair `r <= s` of step 3 ([`Structure::ops`]). The tests here check
//! [`propagate`] against the dense product on random structures; every
//! generated model's tests check its own.

use nalgebra::SMatrix;

use crate::real::Real;

/// Structure of `Phi` and `Qd`, emitted by `model!` as a constant.
#[derive(Clone, Copy, Debug)]
pub struct Structure<'a> {
    /// `Phi = I + C` if true (continuous models, Euler; discrete models whose
    /// changed rows all have a unit diagonal), `Phi = C` if false.
    pub identity: bool,
    /// The changed rows `D`, ascending. Every other row of `Phi` is a unit row.
    pub rows: &'a [usize],
    /// Nonzeros of `C` in changed row `r` are `start[r]..start[r + 1]` of
    /// [`Structure::columns`] (and of the coefficients); `rows.len() + 1` entries.
    pub start: &'a [usize],
    /// Column of each nonzero of `C` in the changed rows, row by row.
    pub columns: &'a [usize],
    /// Positions `(i, j)`, `i <= j`, of the nonzeros of `Qd`'s upper triangle.
    pub noise: &'a [(usize, usize)],
}

impl Structure<'_> {
    /// Arithmetic operations of the four steps for `N` states (multiplies and
    /// adds, each counted once; one add per nonzero of `Qd`'s upper triangle).
    pub const fn ops(&self, n: usize) -> usize {
        let mut ops = 0;
        let d = self.rows.len();
        let mut r = 0;
        while r < d {
            let nnz = self.start[r + 1] - self.start[r];
            // Step 1: one multiply and one add per nonzero and column; without
            // the identity the first term needs no add.
            ops += 2 * nnz * n;
            if !self.identity && nnz > 0 {
                ops -= n;
            }
            // Step 3: pairs (r, s), s >= r, each nnz(s) multiply-adds.
            let mut s = r;
            while s < d {
                let nnz_s = self.start[s + 1] - self.start[s];
                ops += 2 * nnz_s;
                if !self.identity && nnz_s > 0 {
                    ops -= 1;
                }
                s += 1;
            }
            r += 1;
        }
        ops + self.noise.len()
    }
}

/// `P <- Phi P Phi^T + Qd` in place, the four steps over `structure`.
/// `coefficients` are the nonzeros of `C` in the order of
/// [`Structure::columns`], `noise` the values at [`Structure::noise`]; `D` is
/// the number of changed rows (the scratch `A` is `D x N` on the stack).
/// `P` must be symmetric (whole rows are read); the result is exactly
/// symmetric. The generator's structure is consistent by construction; an
/// inconsistent hand-made one panics on an index check, never reads out of
/// bounds.
/// Runs compiled for AVX where the CPU has it (bit-identical results).
#[inline]
pub fn propagate<T: Real, const N: usize, const D: usize>(
    cov: &mut SMatrix<T, N, N>,
    structure: &Structure<'_>,
    coefficients: &[T],
    noise: &[T],
) {
    propagate_kernel::<T, N, D>(cov, structure, coefficients, noise);
}

crate::dispatch::avx_dispatch! {
    /// The kernel of [`propagate`], compiled for AVX where the CPU has it.
    fn propagate_kernel<T: Real, const N: usize, const D: usize>(
        cov: &mut SMatrix<T, N, N>,
        structure: &Structure<'_>,
        coefficients: &[T],
        noise: &[T],
    ) => propagate_steps;
}

/// A structure known at compile time: a model's [`Structure`] as the
/// associated constant of a type (the generated model implements it).
/// [`propagate_static`] is compiled once per such type, so the tables are
/// constants inside the kernel wherever the caller's code is compiled.
pub trait StaticStructure {
    /// The structure of `Phi` and `Qd`.
    const STRUCTURE: Structure<'static>;
}

/// [`propagate`] over `S::STRUCTURE`: the same four steps and the same
/// results bit for bit, compiled for that one structure. The generated
/// models call this. Over a structure passed at run time, the kernel is
/// shared by every model of the same size in a crate, and whether the
/// compiler sees the tables as constants depends on how it partitions the
/// crate: the same 24-state model cost 3,896 or 4,822 instructions per
/// call by where it was declared (docs/performance.md).
#[inline]
pub fn propagate_static<
    T: Real,
    const N: usize,
    const D: usize,
    const C: usize,
    const Q: usize,
    S: StaticStructure,
>(
    cov: &mut SMatrix<T, N, N>,
    coefficients: &[T; C],
    noise: &[T; Q],
) {
    static_kernel::<T, N, D, C, Q, S>(cov, coefficients, noise);
}

crate::dispatch::avx_dispatch! {
    /// The kernel of [`propagate_static`], compiled for AVX where the CPU has it.
    fn static_kernel<T: Real, const N: usize, const D: usize, const C: usize, const Q: usize; S: StaticStructure>(
        cov: &mut SMatrix<T, N, N>,
        coefficients: &[T; C],
        noise: &[T; Q],
    ) => static_steps;
}

/// [`propagate_steps`] over `S::STRUCTURE`, with the lengths of the
/// coefficients and noise values known at compile time too.
#[inline(always)]
fn static_steps<
    T: Real,
    const N: usize,
    const D: usize,
    const C: usize,
    const Q: usize,
    S: StaticStructure,
    const AVX: bool,
    const FUSED: bool,
>(
    cov: &mut SMatrix<T, N, N>,
    coefficients: &[T; C],
    noise: &[T; Q],
) {
    propagate_steps::<T, N, D, AVX, FUSED>(cov, &S::STRUCTURE, coefficients, noise);
}

/// The four steps of [`propagate`].
#[inline(always)]
fn propagate_steps<T: Real, const N: usize, const D: usize, const AVX: bool, const FUSED: bool>(
    cov: &mut SMatrix<T, N, N>,
    structure: &Structure<'_>,
    coefficients: &[T],
    noise: &[T],
) {
    let s = structure;
    // Column-major storage of a symmetric P: column k is row k.
    let cols: &mut [[T; N]; N] = &mut cov.data.0;
    // The nonzeros of each changed row, as slices (no index arithmetic
    // below). A plain loop, not `array::from_fn`, for the reason given at
    // step 3.
    let mut terms: [(&[usize], &[T]); D] = [(&[], &[]); D];
    for (r, term) in terms.iter_mut().enumerate() {
        let range = s.start[r]..s.start[r + 1];
        *term = (&s.columns[range.clone()], &coefficients[range]);
    }
    // Step 1: A = (Phi P)[D, :], one row operation per nonzero, in column
    // blocks whose accumulators stay in registers across the nonzeros.
    let mut a = [[T::zero(); N]; D];
    for ((row, &i), &(columns, values)) in a.iter_mut().zip(s.rows).zip(&terms) {
        let base = if s.identity { Some(&cols[i]) } else { None };
        combine_rows::<T, N, AVX, FUSED>(row, base, columns, values, cols);
    }
    // Step 2: rows and columns D of P become those of A (the U entries are
    // final). Columns first, then rows: afterwards every column `k` holds
    // `A[:, k]` in the rows D, which step 3 reads as vectors.
    for (ar, &i) in a.iter().zip(s.rows) {
        cols[i].copy_from_slice(ar);
    }
    for (ar, &i) in a.iter().zip(s.rows) {
        for (col, &v) in cols.iter_mut().zip(ar) {
            col[i] = v;
        }
    }
    // Step 3: the D x D block, A Phi[D, :]^T, upper triangle kept and mirrored.
    if let Some(d0) = contiguous(s.rows) {
        // Column `s` of the block is a combination of the columns of A, each
        // `P[d0..d0 + D, k]` now: vectorized like step 1.
        // A plain loop rather than `array::from_fn`: the closure of the
        // latter is not inlined into the AVX build and costs ~15 % of the
        // kernel.
        let mut block = [[T::zero(); D]; D];
        for (r, (column, &(columns, values))) in block.iter_mut().zip(&terms).enumerate() {
            let base = if s.identity {
                Some(&cols[d0 + r])
            } else {
                None
            };
            *column = combination::<T, N, D, FUSED>(base, columns, values, cols, d0);
        }
        for (c, column) in block.iter().enumerate() {
            for (r, &v) in column.iter().enumerate().take(c + 1) {
                cols[d0 + c][d0 + r] = v;
                cols[d0 + r][d0 + c] = v;
            }
        }
    } else {
        for (r, (ar, &i)) in a.iter().zip(s.rows).enumerate() {
            for (&j, &(columns, values)) in s.rows[r..].iter().zip(&terms[r..]) {
                let mut v = if s.identity { ar[j] } else { T::zero() };
                for (&k, &c) in columns.iter().zip(values) {
                    v = v.plus_product::<FUSED>(c, ar[k]);
                }
                cols[j][i] = v;
                cols[i][j] = v;
            }
        }
    }
    // Step 4: Qd. P is exactly symmetric here, so an off-diagonal sum is
    // formed once and stored in both triangles.
    for (&(i, j), &q) in s.noise.iter().zip(noise) {
        let v = cols[j][i] + q;
        cols[j][i] = v;
        cols[i][j] = v;
    }
}

/// Columns per register block of step 1 (six SSE2 registers of accumulators).
const BLOCK: usize = 12;
/// Rows up to this length are one block: at most 8 SSE2 registers of
/// accumulators, or 7 AVX registers (a 25-state row), of the 16 there are.
const fn whole_row(avx: bool) -> usize {
    if avx {
        28
    } else {
        16
    }
}

/// `row = base + sum_e values[e] P[columns[e], :]`, the accumulators of a
/// block of columns kept in registers across the nonzeros. Rows longer than
/// [`whole_row`] are split into blocks of [`BLOCK`] columns; the last block
/// and the remainder are split evenly into two blocks of 6 to 12 columns, so
/// no column is left to a scalar loop (`N` is a constant: only one arm of
/// the `match` survives compilation).
#[inline(always)]
fn combine_rows<T: Real, const N: usize, const AVX: bool, const FUSED: bool>(
    row: &mut [T; N],
    base: Option<&[T; N]>,
    columns: &[usize],
    values: &[T],
    cols: &[[T; N]; N],
) {
    if N <= whole_row(AVX) {
        block::<T, N, N, FUSED>(row, base, columns, values, cols, 0);
        return;
    }
    let full = N / BLOCK - 1;
    for b in 0..full {
        block::<T, N, BLOCK, FUSED>(row, base, columns, values, cols, b * BLOCK);
    }
    let c0 = full * BLOCK;
    let args = (row, base, columns, values, cols);
    match N % BLOCK {
        0 => block::<T, N, 12, FUSED>(args.0, args.1, args.2, args.3, args.4, c0),
        r => {
            let (first, second) = split_remainder(r);
            let mid = c0 + first;
            match (first, second) {
                (6, 7) => pair::<T, N, 6, 7, FUSED>(args, c0, mid),
                (7, 7) => pair::<T, N, 7, 7, FUSED>(args, c0, mid),
                (7, 8) => pair::<T, N, 7, 8, FUSED>(args, c0, mid),
                (8, 8) => pair::<T, N, 8, 8, FUSED>(args, c0, mid),
                (8, 9) => pair::<T, N, 8, 9, FUSED>(args, c0, mid),
                (9, 9) => pair::<T, N, 9, 9, FUSED>(args, c0, mid),
                (9, 10) => pair::<T, N, 9, 10, FUSED>(args, c0, mid),
                (10, 10) => pair::<T, N, 10, 10, FUSED>(args, c0, mid),
                (10, 11) => pair::<T, N, 10, 11, FUSED>(args, c0, mid),
                (11, 11) => pair::<T, N, 11, 11, FUSED>(args, c0, mid),
                _ => pair::<T, N, 11, 12, FUSED>(args, c0, mid),
            }
        }
    }
}

/// The widths of the two last blocks when `remainder` columns (1 to 11)
/// follow the last full block: `BLOCK + remainder` split evenly.
const fn split_remainder(remainder: usize) -> (usize, usize) {
    let total = BLOCK + remainder;
    (total / 2, total - total / 2)
}

type RowArgs<'a, T, const N: usize> = (
    &'a mut [T; N],
    Option<&'a [T; N]>,
    &'a [usize],
    &'a [T],
    &'a [[T; N]; N],
);

/// Two consecutive blocks of `A` and `B` columns starting at `c0` and `c1`.
#[inline(always)]
fn pair<T: Real, const N: usize, const A: usize, const B: usize, const FUSED: bool>(
    (row, base, columns, values, cols): RowArgs<'_, T, N>,
    c0: usize,
    c1: usize,
) {
    block::<T, N, A, FUSED>(row, base, columns, values, cols, c0);
    block::<T, N, B, FUSED>(row, base, columns, values, cols, c1);
}

/// Columns `c0..c0 + B` of `row = base + sum_e values[e] P[columns[e], :]`.
#[inline(always)]
fn block<T: Real, const N: usize, const B: usize, const FUSED: bool>(
    row: &mut [T; N],
    base: Option<&[T; N]>,
    columns: &[usize],
    values: &[T],
    cols: &[[T; N]; N],
    c0: usize,
) {
    row[c0..c0 + B].copy_from_slice(&combination::<T, N, B, FUSED>(
        base, columns, values, cols, c0,
    ));
}

/// `base[c0..c0 + B] + sum_e values[e] P[columns[e], c0..c0 + B]` (rows of
/// the symmetric `P` are its columns), accumulated in registers.
#[inline(always)]
fn combination<T: Real, const N: usize, const B: usize, const FUSED: bool>(
    base: Option<&[T; N]>,
    columns: &[usize],
    values: &[T],
    cols: &[[T; N]; N],
    c0: usize,
) -> [T; B] {
    let mut acc = [T::zero(); B];
    if let Some(b) = base {
        acc.copy_from_slice(&b[c0..c0 + B]);
    }
    for (&k, &c) in columns.iter().zip(values) {
        for (x, &y) in acc.iter_mut().zip(&cols[k][c0..c0 + B]) {
            *x = x.plus_product::<FUSED>(c, y);
        }
    }
    acc
}

/// The first row if `rows` are consecutive (the usual error-state layout: the
/// navigation errors first).
#[inline(always)]
fn contiguous(rows: &[usize]) -> Option<usize> {
    let (&first, &last) = (rows.first()?, rows.last()?);
    (last - first + 1 == rows.len()).then_some(first)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SMatrix;

    /// A deterministic pseudo-random value in [-1, 1).
    fn value(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// Builds the tables of a random `C` whose nonzeros are in `rows`, runs
    /// [`propagate`] and compares with the dense product.
    fn check<const N: usize, const D: usize>(rows: [usize; D], identity: bool, seed: u64) {
        let mut seed = seed;
        let mut c = SMatrix::<f64, N, N>::zeros();
        let (mut start, mut columns, mut coefficients) = (vec![0], vec![], vec![]);
        for &i in &rows {
            for k in 0..N {
                if value(&mut seed) > 0.3 || (!identity && k == i) {
                    c[(i, k)] = value(&mut seed);
                    columns.push(k);
                    coefficients.push(c[(i, k)]);
                }
            }
            start.push(columns.len());
        }
        let mut qd = SMatrix::<f64, N, N>::zeros();
        let mut noise_at = vec![];
        let mut noise = vec![];
        for i in 0..N {
            for j in i..N {
                if value(&mut seed) > 0.6 {
                    let q = value(&mut seed);
                    qd[(i, j)] = q;
                    qd[(j, i)] = q;
                    noise_at.push((i, j));
                    noise.push(q);
                }
            }
        }
        let mut phi = if identity {
            SMatrix::<f64, N, N>::identity() + c
        } else {
            c
        };
        if !identity {
            for i in (0..N).filter(|i| !rows.contains(i)) {
                phi[(i, i)] = 1.0;
            }
        }
        let l = SMatrix::<f64, N, N>::from_fn(|_, _| value(&mut seed));
        let p = l * l.transpose() + SMatrix::<f64, N, N>::identity();
        let structure = Structure {
            identity,
            rows: &rows,
            start: &start,
            columns: &columns,
            noise: &noise_at,
        };
        let mut got = p;
        propagate::<f64, N, D>(&mut got, &structure, &coefficients, &noise);
        let want = phi * p * phi.transpose() + qd;
        let err = (got - want).amax() / want.amax();
        assert!(err < 1e-13, "relative error {err}");
        assert_eq!(got, got.transpose(), "result not exactly symmetric");
        // The vector width chosen at run time never changes a bit.
        let mut portable = p;
        propagate_steps::<f64, N, D, false, { crate::dispatch::FUSED }>(
            &mut portable,
            &structure,
            &coefficients,
            &noise,
        );
        assert!(
            got.iter()
                .zip(&portable)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "dispatched and portable results differ"
        );
        // Fused multiply-adds (the `fma` build) also equal the dense
        // product, and differ from the unfused kernel in the last bits only.
        let (mut fused, mut unfused) = (p, p);
        propagate_steps::<f64, N, D, false, true>(&mut fused, &structure, &coefficients, &noise);
        propagate_steps::<f64, N, D, false, false>(&mut unfused, &structure, &coefficients, &noise);
        let err = (fused - want).amax() / want.amax();
        assert!(err < 1e-13, "fused: relative error {err}");
        assert_eq!(
            fused,
            fused.transpose(),
            "fused result not exactly symmetric"
        );
        let apart = (fused - unfused).amax() / want.amax();
        assert!(apart < 1e-14, "fused and unfused {apart} apart");
        FUSED_DIFFERS.fetch_or(fused != unfused, core::sync::atomic::Ordering::Relaxed);
    }

    /// Two structures known at compile time: changed rows contiguous with
    /// `Phi = I + C`, and scattered with `Phi = C`.
    struct Contiguous;
    impl StaticStructure for Contiguous {
        const STRUCTURE: Structure<'static> = Structure {
            identity: true,
            rows: &[1, 2, 3],
            start: &[0, 3, 5, 8],
            columns: &[0, 2, 6, 1, 3, 0, 4, 6],
            noise: &[(1, 1), (1, 3), (3, 3), (5, 6)],
        };
    }
    struct Scattered;
    impl StaticStructure for Scattered {
        const STRUCTURE: Structure<'static> = Structure {
            identity: false,
            rows: &[0, 4, 6],
            start: &[0, 2, 5, 7],
            columns: &[0, 5, 1, 4, 6, 3, 6],
            noise: &[(0, 0), (0, 6), (2, 2), (6, 6)],
        };
    }

    /// [`propagate_static`] gives [`propagate`]'s result over the same
    /// structure, bit for bit.
    fn check_static<S: StaticStructure, const D: usize, const C: usize>(seed: u64) {
        let mut seed = seed;
        let coefficients: [f64; C] = core::array::from_fn(|_| value(&mut seed));
        let noise: [f64; 4] = core::array::from_fn(|_| value(&mut seed).abs());
        let l = SMatrix::<f64, 7, 7>::from_fn(|_, _| value(&mut seed));
        let p = l * l.transpose() + SMatrix::<f64, 7, 7>::identity();
        let mut at_run_time = p;
        propagate::<f64, 7, D>(&mut at_run_time, &S::STRUCTURE, &coefficients, &noise);
        let mut compiled = p;
        propagate_static::<f64, 7, D, C, 4, S>(&mut compiled, &coefficients, &noise);
        assert!(
            compiled
                .iter()
                .zip(&at_run_time)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "seed {seed}: static and run-time structures differ"
        );
        assert_ne!(compiled, p);
    }

    #[test]
    fn a_static_structure_gives_the_same_bits() {
        for seed in 0..10 {
            check_static::<Contiguous, 3, 8>(seed);
            check_static::<Scattered, 3, 7>(seed);
        }
    }

    /// Whether some case's fused result differed from the unfused one.
    static FUSED_DIFFERS: core::sync::atomic::AtomicBool =
        core::sync::atomic::AtomicBool::new(false);

    #[test]
    fn equals_the_dense_product() {
        for seed in 0..20 {
            check::<25, 9>([0, 1, 2, 3, 4, 5, 6, 7, 8], true, seed);
            check::<25, 4>([2, 7, 8, 20], true, seed);
            check::<9, 9>([0, 1, 2, 3, 4, 5, 6, 7, 8], false, seed);
            check::<6, 3>([0, 3, 5], false, seed);
            check::<17, 17>(core::array::from_fn(|i| i), true, seed);
            check::<24, 3>([0, 11, 23], true, seed);
            for_each_remainder(seed);
            check::<3, 0>([], true, seed);
        }
        // The fused kernel really fuses: its rounding is not the unfused one.
        assert!(FUSED_DIFFERS.load(core::sync::atomic::Ordering::Relaxed));
    }

    /// Every split of the last blocks (N = 25 to 35 covers remainders 1 to 11).
    fn for_each_remainder(seed: u64) {
        check::<25, 2>([1, 24], true, seed);
        check::<26, 2>([0, 25], false, seed);
        check::<27, 1>([13], true, seed);
        check::<28, 1>([27], true, seed);
        check::<29, 1>([5], true, seed);
        check::<30, 1>([5], false, seed);
        check::<31, 1>([30], true, seed);
        check::<32, 1>([0], true, seed);
        check::<33, 1>([16], true, seed);
        check::<34, 1>([1], true, seed);
        check::<35, 1>([34], true, seed);
        check::<36, 1>([35], true, seed);
    }

    #[test]
    fn remainders_split_into_two_blocks_of_six_to_twelve() {
        for r in 1..BLOCK {
            let (a, b) = split_remainder(r);
            assert_eq!(a + b, BLOCK + r);
            assert!(
                (6..=12).contains(&a) && (6..=12).contains(&b),
                "{r}: {a} + {b}"
            );
        }
    }

    #[test]
    fn op_count_of_a_known_structure() {
        // Two changed rows of N = 4 with 2 and 1 nonzeros; Qd diagonal (1, 1)
        // and off-diagonal (0, 1).
        let s = Structure {
            identity: true,
            rows: &[0, 1],
            start: &[0, 2, 3],
            columns: &[1, 3, 0],
            noise: &[(1, 1), (0, 1)],
        };
        // Step 1: 2*(2+1)*4 = 24; step 3: pairs (0,0) 4, (0,1) 2, (1,1) 2;
        // Qd one add per upper-triangle nonzero: 2.
        assert_eq!(s.ops(4), 24 + 8 + 2);
    }
}
