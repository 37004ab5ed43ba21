//! Op-count regression check: the arithmetic operations of every generated
//! function (the `OPS_*` constants) against the checked-in baseline
//! `models/perf/op_counts.toml`.
//!
//! - A count more than 10 % above its baseline fails the test.
//! - A count below its baseline is printed as an improvement (update the file).
//! - A function listed here but missing from the file, or the reverse, fails.
//! - `UPDATE_OP_COUNTS=1 cargo test -p models --test scenarios op_counts::` rewrites the file
//!   from the current counts (review the diff before keeping it).
//!
//! A second test prints the covariance propagation counts next to a dense
//! `Phi P Phi^T + Qd` and the minimum for each model's sparsity (see
//! docs/performance.md), and checks the generated count stays below dense.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

use models::leveling::model::{Leveling6, Leveling6Moving, Leveling6Stationary};
use models::marker::model::{
    Marker9, Marker9Depth, Marker9Dvl, Marker9MarkerFix, Marker9MarkerRelative,
};
use models::px4_ekf24::{Px4Ekf24, Px4Ekf24Single};
use models::sdins25::model::{
    Sdins25, Sdins25Compass, Sdins25CompassSmallAngle, Sdins25Depth, Sdins25Dvl, Sdins25Usbl,
};
use nav_runtime::model::{Model, Record};
use nav_runtime::nalgebra::SVector;

/// Allowed growth of a count before the test fails.
const TOLERANCE: f64 = 0.10;

type Counts = BTreeMap<String, BTreeMap<String, usize>>;

macro_rules! continuous_model {
    ($counts:ident, $ty:ident) => {
        $counts.insert(
            stringify!($ty).to_string(),
            BTreeMap::from([
                ("derivative".to_string(), $ty::OPS_DERIVATIVE),
                ("transition".to_string(), $ty::OPS_TRANSITION),
                ("jacobian".to_string(), $ty::OPS_JACOBIAN),
                ("noise_jacobian".to_string(), $ty::OPS_NOISE_JACOBIAN),
                ("process_noise".to_string(), $ty::OPS_PROCESS_NOISE),
                (
                    "propagate_covariance".to_string(),
                    $ty::OPS_PROPAGATE_COVARIANCE,
                ),
            ]),
        );
    };
}

macro_rules! discrete_model {
    ($counts:ident, $ty:ident) => {
        $counts.insert(
            stringify!($ty).to_string(),
            BTreeMap::from([
                ("transition".to_string(), $ty::OPS_TRANSITION),
                ("jacobian".to_string(), $ty::OPS_JACOBIAN),
                ("noise_jacobian".to_string(), $ty::OPS_NOISE_JACOBIAN),
                ("process_noise".to_string(), $ty::OPS_PROCESS_NOISE),
                (
                    "propagate_covariance".to_string(),
                    $ty::OPS_PROPAGATE_COVARIANCE,
                ),
            ]),
        );
    };
}

macro_rules! sensor {
    ($counts:ident, $ty:ident) => {
        $counts.insert(
            stringify!($ty).to_string(),
            BTreeMap::from([
                ("predict".to_string(), $ty::OPS_PREDICT),
                ("jacobian".to_string(), $ty::OPS_JACOBIAN),
                ("innovation_terms".to_string(), $ty::OPS_INNOVATION_TERMS),
            ]),
        );
    };
}

/// The current counts of every generated function covered by the baseline.
/// A new model or sensor is added here (and to the file, see the module docs).
fn current() -> Counts {
    let mut c = Counts::new();
    continuous_model!(c, Sdins25);
    sensor!(c, Sdins25Depth);
    sensor!(c, Sdins25Dvl);
    sensor!(c, Sdins25CompassSmallAngle);
    sensor!(c, Sdins25Compass);
    sensor!(c, Sdins25Usbl);
    continuous_model!(c, Leveling6);
    sensor!(c, Leveling6Moving);
    sensor!(c, Leveling6Stationary);
    discrete_model!(c, Marker9);
    sensor!(c, Marker9Dvl);
    sensor!(c, Marker9Depth);
    sensor!(c, Marker9MarkerFix);
    sensor!(c, Marker9MarkerRelative);
    discrete_model!(c, Px4Ekf24);
    discrete_model!(c, Px4Ekf24Single);
    c
}

fn baseline_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("perf/op_counts.toml")
}

fn render(counts: &Counts) -> String {
    let mut s = String::from(
        "# Arithmetic operations (+ - * /, negation, calls) of the code generated for\n\
         # each model and sensor: the OPS_* constants. Checked by models/tests/scenarios/op_counts.rs:\n\
         # a count more than 10 % above the value here fails `cargo test`.\n\
         # Regenerate with `UPDATE_OP_COUNTS=1 cargo test -p models --test scenarios op_counts::`.\n",
    );
    for (item, fns) in counts {
        let _ = write!(s, "\n[{item}]\n");
        for (f, n) in fns {
            let _ = writeln!(s, "{f} = {n}");
        }
    }
    s
}

fn read_baseline() -> Counts {
    let path = baseline_path();
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let table: toml::Table = text
        .parse()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut counts = Counts::new();
    for (item, fns) in table {
        let fns = fns
            .as_table()
            .unwrap_or_else(|| panic!("[{item}] is not a table"));
        let entry = counts.entry(item.clone()).or_default();
        for (f, n) in fns {
            let n = n
                .as_integer()
                .and_then(|n| usize::try_from(n).ok())
                .unwrap_or_else(|| panic!("{item}.{f} is not a count"));
            entry.insert(f.clone(), n);
        }
    }
    counts
}

#[test]
fn op_counts_do_not_regress() {
    let now = current();
    if std::env::var_os("UPDATE_OP_COUNTS").is_some() {
        std::fs::write(baseline_path(), render(&now)).expect("write the baseline");
        eprintln!("rewrote {}", baseline_path().display());
        return;
    }
    let base = read_baseline();
    let mut failures = Vec::new();
    for (item, fns) in &now {
        for (f, &n) in fns {
            match base.get(item).and_then(|b| b.get(f)) {
                None => failures.push(format!("{item}.{f} = {n} has no baseline entry")),
                Some(&b) => {
                    let change = (n as f64 - b as f64) / b.max(1) as f64;
                    if change > TOLERANCE {
                        failures.push(format!(
                            "{item}.{f}: {b} -> {n} ops (+{:.1} %, limit +{:.0} %)",
                            100.0 * change,
                            100.0 * TOLERANCE
                        ));
                    } else if n < b {
                        eprintln!(
                            "improved: {item}.{f}: {b} -> {n} ops ({:.1} %); update the baseline",
                            100.0 * change
                        );
                    } else if n > b {
                        eprintln!(
                            "note: {item}.{f}: {b} -> {n} ops (+{:.1} %, within tolerance)",
                            100.0 * change
                        );
                    }
                }
            }
        }
    }
    for (item, fns) in &base {
        for f in fns.keys() {
            if now.get(item).and_then(|c| c.get(f)).is_none() {
                failures.push(format!(
                    "baseline entry {item}.{f} is not measured by this test"
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "op-count check failed ({}):\n  {}\n(see the module docs of models/tests/scenarios/op_counts.rs)",
        baseline_path().display(),
        failures.join("\n  ")
    );
}

/// Operation counts of `P <- Phi P Phi^T + Qd` for a model with `N` states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct PropagationCounts {
    /// `Phi P` and `(Phi P) Phi^T` as full dense products, plus `+ Qd`:
    /// `2 N^2 (2N - 1) + N^2` (forming `Phi` not included).
    dense: usize,
    /// The multiply-adds that remain when `Phi`'s structure is used: unit rows of
    /// `Phi` cost nothing, unit coefficients need no multiply, only the entries of
    /// `A = Phi P` that the upper triangle of `A Phi^T` reads are formed, only the
    /// upper triangle of `A Phi^T` is formed, and `+ Qd` only at `Qd`'s nonzeros.
    /// Evaluating the entries of `F` and `Qd` is not included.
    minimum_product: usize,
    /// Forming the non-unit entries of `Phi` from `F` (`F dt`, `1 + F dt` on the
    /// diagonal) for continuous models; zero for discrete ones.
    form_phi: usize,
}

/// A generic point (every scalar in [-1, 1] or so, no accidental zeros).
fn generic<R: Record>(salt: u64) -> R {
    R::from_fn(|i| {
        let z = (i as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15)
            ^ salt.wrapping_mul(0xbf58_476d_1ce4_e5b9);
        0.3 + 0.6 * ((z >> 11) as f64 / (1u64 << 53) as f64)
    })
}

/// Counts from the structure of `Phi` (from `JACOBIAN_SPARSITY`, and for
/// discrete models which entries are exactly 1) and of `Qd` (nonzero pattern at
/// a generic point).
fn propagation_counts<Mo: Model<N>, const N: usize>() -> PropagationCounts {
    let x = SVector::<f64, N>::from_fn(|i, _| 0.1 + 0.01 * i as f64);
    let (u, p, q) = (
        generic::<Mo::Input>(1),
        generic::<Mo::Params>(2),
        generic::<Mo::Noise>(3),
    );
    let dt = 0.01;
    let jac = Mo::jacobian(&x, &u, &p, dt);
    let qd = Mo::process_noise(&x, &u, &p, &q, dt);
    let s = Mo::JACOBIAN_SPARSITY;
    // Structure of Phi: terms[i] = columns with a nonzero, unit[i][k] = coefficient exactly 1.
    let mut terms = vec![Vec::new(); N];
    let mut unit = vec![vec![false; N]; N];
    let mut form_phi = 0;
    for i in 0..N {
        for k in 0..N {
            let nonzero = if Mo::DISCRETE {
                s[i][k]
            } else {
                s[i][k] || i == k
            };
            if !nonzero {
                continue;
            }
            terms[i].push(k);
            unit[i][k] = if Mo::DISCRETE {
                jac[(i, k)] == 1.0
            } else {
                i == k && !s[i][i]
            };
            if !Mo::DISCRETE && s[i][k] {
                form_phi += if i == k { 2 } else { 1 };
            }
        }
    }
    let identity_row = |i: usize| terms[i] == [i] && unit[i][i];
    let row_cost = |i: usize| {
        if identity_row(i) {
            0
        } else {
            let mults = terms[i].iter().filter(|&&k| !unit[i][k]).count();
            mults + terms[i].len() - 1
        }
    };
    let mut minimum = 0;
    for i in 0..N {
        // Entries A[i][k] read by the upper triangle of A Phi^T: k in T_j, j >= i.
        let mut needed = vec![false; N];
        for row in &terms[i..] {
            for &k in row {
                needed[k] = true;
            }
        }
        minimum += row_cost(i) * needed.iter().filter(|&&b| b).count();
        for j in i..N {
            minimum += row_cost(j) + usize::from(qd[(i, j)] != 0.0);
        }
    }
    PropagationCounts {
        dense: 2 * N * N * (2 * N - 1) + N * N,
        minimum_product: minimum,
        form_phi,
    }
}

#[test]
fn propagation_counts_against_dense_and_minimum() {
    fn row<Mo: Model<N>, const N: usize>(out: &mut String, name: &str, process_noise_ops: usize) {
        let c = propagation_counts::<Mo, N>();
        let generated = Mo::OPS_PROPAGATE_COVARIANCE;
        let _ = writeln!(
            out,
            "{name:<10} N={N:<3} dense {:>6}  minimum {:>5} (+{} to form Phi)  generated {:>5}  \
             generated/dense {:.3}  generated/minimum {:.2}  (jacobian {}, process_noise {})",
            c.dense,
            c.minimum_product,
            c.form_phi,
            generated,
            generated as f64 / c.dense as f64,
            generated as f64 / c.minimum_product.max(1) as f64,
            Mo::OPS_JACOBIAN,
            process_noise_ops,
        );
        assert!(
            generated < c.dense,
            "{name}: generated {generated} >= dense {}",
            c.dense
        );
    }
    let mut out = String::new();
    row::<Sdins25, 25>(&mut out, "Sdins25", Sdins25::OPS_PROCESS_NOISE);
    row::<Leveling6, 6>(&mut out, "Leveling6", Leveling6::OPS_PROCESS_NOISE);
    row::<Marker9, 9>(&mut out, "Marker9", Marker9::OPS_PROCESS_NOISE);
    row::<Px4Ekf24, 24>(&mut out, "Px4Ekf24", Px4Ekf24::OPS_PROCESS_NOISE);
    eprintln!("{out}");
}
