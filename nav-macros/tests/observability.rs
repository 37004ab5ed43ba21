//! Structural observability (`docs/language.md`, "Structural observability"):
//! the generated const data against a linear model whose observability
//! matrix `[H; H F; ..; H F^(n-1)]` is written by hand, sensor set by sensor
//! set. The structural answer must equal the rank answer wherever sparsity
//! decides it, and may only say "not excluded" where it does not (two biases
//! seen through their sum).

use nav_runtime::nalgebra::{DMatrix, SMatrix};

nav_runtime::model! {
    /// A chain `x1' = x2, x2' = x3 + w`, a random constant `x3`, a decaying
    /// `x4' = -x4`, and two biases `b1`, `b2` measured only as their sum.
    pub model Chain {
        states { x1, x2, x3, x4, b1, b2 }
        noise { w }
        continuous {
            d/dt x1 = x2;
            d/dt x2 = x3 + w;
            d/dt x4 = -x4;
        }
        sensor A: 1 { h = x1; }
        sensor B: 1 { h = x4; }
        sensor C: 1 { h = x3; }
        sensor D: 1 { h = b1 + b2; }
        runs_with { [A, B, D], [C, D] }
        allow_unused { x1, x2, x4 }
    }
}

const N: usize = 6;

/// `F` by hand (rows: derivatives of x1, x2, x3, x4, b1, b2).
fn f_by_hand() -> SMatrix<f64, N, N> {
    let mut f = SMatrix::<f64, N, N>::zeros();
    f[(0, 1)] = 1.0;
    f[(1, 2)] = 1.0;
    f[(3, 3)] = -1.0;
    f
}

/// The `H` row of each sensor by hand, in declaration order A, B, C, D.
fn h_by_hand() -> [[f64; N]; 4] {
    [
        [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 1.0, 1.0],
    ]
}

/// Per state: observable in the linear sense with the sensors marked, i.e. the
/// unobservable subspace (null space of the observability matrix) has no
/// component along the state.
fn observable_by_rank(sensors: &[bool; 4]) -> [bool; N] {
    let (f, h) = (f_by_hand(), h_by_hand());
    let rows: Vec<[f64; N]> = (0..4).filter(|&s| sensors[s]).map(|s| h[s]).collect();
    if rows.is_empty() {
        return [false; N];
    }
    let mut o = DMatrix::<f64>::zeros(rows.len() * N, N);
    for (r, row) in rows.iter().enumerate() {
        let mut hfk = SMatrix::<f64, 1, N>::from_row_slice(row);
        for k in 0..N {
            o.row_mut(k * rows.len() + r).copy_from(&hfk);
            hfk *= f;
        }
    }
    // O^T = U S V^T (N x N U, as O has at least N rows): the columns of U
    // with (near) zero singular values span the null space of O.
    let svd = o.transpose().svd(true, false);
    let u = svd.u.expect("U requested");
    let mut observable = [true; N];
    for (k, &sv) in svd.singular_values.iter().enumerate() {
        if sv < 1e-9 {
            for (i, obs) in observable.iter_mut().enumerate() {
                if u[(i, k)].abs() > 1e-9 {
                    *obs = false;
                }
            }
        }
    }
    observable
}

/// (sensors A B C D, structural answer written by hand, rank answer written by hand).
const CASES: [([bool; 4], [bool; N], [bool; N]); 6] = [
    // A sees x1, and x2, x3 through the chain; nothing else.
    (
        [true, false, false, false],
        [true, true, true, false, false, false],
        [true, true, true, false, false, false],
    ),
    // B sees x4 alone.
    (
        [false, true, false, false],
        [false, false, false, true, false, false],
        [false, false, false, true, false, false],
    ),
    // C sees x3 only: x3 influences x2, not the other way round.
    (
        [false, false, true, false],
        [false, false, true, false, false, false],
        [false, false, true, false, false, false],
    ),
    // D reaches both biases, yet only their sum is observable: structural
    // observability is necessary, not sufficient.
    (
        [false, false, false, true],
        [false, false, false, false, true, true],
        [false, false, false, false, false, false],
    ),
    (
        [true, true, false, true],
        [true, true, true, true, true, true],
        [true, true, true, true, false, false],
    ),
    ([false; 4], [false; N], [false; N]),
];

#[test]
fn structural_observability_matches_the_hand_written_table() {
    for (sensors, structural, rank) in CASES {
        assert_eq!(
            Chain::structurally_observable(&sensors),
            structural,
            "structural, sensors {sensors:?}"
        );
        assert_eq!(
            observable_by_rank(&sensors),
            rank,
            "rank, sensors {sensors:?}"
        );
        // Wherever the rank test says observable, the structural one must too.
        for i in 0..N {
            assert!(!rank[i] || structural[i], "state {i}, sensors {sensors:?}");
        }
    }
}

#[test]
fn generated_const_data() {
    assert_eq!(Chain::SENSORS, ["A", "B", "C", "D"]);
    assert_eq!(
        [ChainA::INDEX, ChainB::INDEX, ChainC::INDEX, ChainD::INDEX],
        [0, 1, 2, 3]
    );
    assert_eq!(Chain::sensor_index("C"), Some(2));
    assert_eq!(Chain::sensor_index("E"), None);
    for (s, row) in h_by_hand().iter().enumerate() {
        let direct: [bool; N] = row.map(|v| v != 0.0);
        assert_eq!(Chain::SENSOR_DEPENDS[s], direct, "sensor {s}");
    }
    let alone = |s: usize| {
        let mut on = [false; 4];
        on[s] = true;
        Chain::structurally_observable(&on)
    };
    assert_eq!(ChainA::OBSERVES, alone(0));
    assert_eq!(ChainB::OBSERVES, alone(1));
    assert_eq!(ChainC::OBSERVES, alone(2));
    assert_eq!(ChainD::OBSERVES, alone(3));
    // The declared sets and the answer for each.
    assert_eq!(Chain::RUNS_WITH, [&[0usize, 1, 3][..], &[2, 3][..]]);
    assert_eq!(
        Chain::RUNS_WITH_OBSERVABLE,
        [[true; N], [false, false, true, false, true, true]]
    );
    // All sensors leave nothing unused.
    assert!(Chain::UNUSED_STATES.is_empty());
    // Usable in const context.
    const WITH_C: [bool; N] = Chain::structurally_observable(&[false, false, true, false]);
    assert_eq!(WITH_C, [false, false, true, false, false, false]);
}
