//! The outputs of every generated function as nodes of the model's graph:
//! `F`/`Phi` and `G` by differentiation, `Qd`, and the covariance algebra
//! (`Phi P Phi^T + Qd`, `P H^T`, `H P H^T`) built symbolically over covariance
//! symbols, so structural zeros and unit entries vanish before any code exists.

use std::collections::HashMap;

use super::diff::Diff;
use super::expr::{Graph, Id, Sym};
use super::lowered::{Lowered, ProcessKind};

/// Everything the emitter needs, as node ids of `graph`.
pub struct Derived {
    pub graph: Graph,
    pub kind: ProcessKind,
    pub n: usize,
    pub nw: usize,
    /// `f` with noise `w`.
    pub f_noisy: Vec<Id>,
    /// `f` at `w = 0`.
    pub f: Vec<Id>,
    /// `x + f dt` (continuous) or `f` (discrete).
    pub transition: Vec<Id>,
    /// The same step with noise `w`: `x + f(x, u, p, w) dt` (continuous) or
    /// `f(x, u, p, dt, w)` (discrete).
    pub step_noisy: Vec<Id>,
    /// `F` (continuous) or `Phi` (discrete), row-major N x N.
    pub jacobian: Vec<Id>,
    /// `G = df/dw` at `w = 0`, row-major N x NW.
    pub noise_jacobian: Vec<Id>,
    /// `Qd`, row-major N x N (upper triangle meaningful, lower mirrored ids).
    pub process_noise: Vec<Id>,
    /// The structure and coefficients of `Phi P Phi^T + Qd`.
    pub propagation: Propagation,
    pub sensors: Vec<DerivedSensor>,
    /// The transition maps the zero state to itself for every input and
    /// parameter (symbolically: every entry simplifies to 0 at `x = 0`), as
    /// an error-state model does between feedbacks.
    pub zero_is_fixed: bool,
}

/// `P <- Phi P Phi^T + Qd` as the runtime's structured kernel takes it
/// (`nav_runtime::propagation`): `Phi = I + C` (continuous, `C = F dt`; or
/// discrete with a unit diagonal in every changed row, `C = Phi - I`) or
/// `Phi = C` (other discrete models), only the rows of `Phi` that are not
/// unit rows.
pub struct Propagation {
    pub identity: bool,
    /// Changed rows (not unit rows of `Phi`), ascending.
    pub rows: Vec<usize>,
    /// Per changed row, `(column, coefficient)` of its nonzeros in `C`.
    pub entries: Vec<Vec<(usize, Id)>>,
    /// Nonzeros of the upper triangle of `Qd`.
    pub noise: Vec<(usize, usize, Id)>,
    /// For small models, `Phi P Phi^T + Qd` entry by entry over the upper
    /// triangle of `P` as `(i, j, id)`: straight-line scalar code beats the
    /// row kernel when everything fits in registers.
    pub unrolled: Option<Vec<(usize, usize, Id)>>,
}

/// Models up to this many states get the unrolled scalar propagation.
pub const UNROLL_MAX_STATES: usize = 12;

/// `sum_l row[l] P[l][k]` over the structural nonzeros `l` of a coefficient
/// row (of `Phi` or `H`), as a node over the covariance symbols.
fn row_times_cov(g: &mut Graph, row: &[Id], nonzero: &[usize], k: usize) -> Id {
    let terms: Vec<Id> = nonzero
        .iter()
        .map(|&l| {
            let plk = g.sym(Sym::cov(l, k));
            g.mul(row[l], plk)
        })
        .collect();
    g.sum(terms)
}

/// One sensor's outputs.
pub struct DerivedSensor {
    pub m: usize,
    pub h: Vec<Id>,
    /// `H`, row-major M x N.
    pub jacobian: Vec<Id>,
    /// `P H^T`, row-major N x M.
    pub pht: Vec<Id>,
    /// `H P H^T`, upper triangle as (i, j, id).
    pub hpht: Vec<(usize, usize, Id)>,
}

/// Differentiates and assembles all outputs.
pub fn derive(lowered: Lowered, nw: usize) -> Derived {
    let Lowered {
        mut graph,
        kind,
        f: f_noisy,
        sensors,
    } = lowered;
    let g = &mut graph;
    let n = f_noisy.len();
    let mut d = Diff::new();

    let is_noise = |s: Sym| matches!(s, Sym::Noise(_));
    let mut memo = HashMap::new();
    let f: Vec<Id> = f_noisy
        .iter()
        .map(|&e| g.substitute_zero(e, &is_noise, &mut memo))
        .collect();

    let dt = g.sym(Sym::Dt);
    let transition: Vec<Id> = match kind {
        ProcessKind::Continuous => (0..n)
            .map(|i| {
                let x = g.sym(Sym::State(i as u32));
                let step = g.mul(f[i], dt);
                g.add(x, step)
            })
            .collect(),
        ProcessKind::Discrete => f.clone(),
    };
    let step_noisy: Vec<Id> = match kind {
        ProcessKind::Continuous => (0..n)
            .map(|i| {
                let x = g.sym(Sym::State(i as u32));
                let step = g.mul(f_noisy[i], dt);
                g.add(x, step)
            })
            .collect(),
        ProcessKind::Discrete => f_noisy.clone(),
    };

    let mut jacobian = Vec::with_capacity(n * n);
    for &fi in &f {
        for j in 0..n {
            jacobian.push(d.diff(g, fi, Sym::State(j as u32)));
        }
    }
    let mut noise_jacobian = Vec::with_capacity(n * nw);
    for &fi in &f_noisy {
        for k in 0..nw {
            let gk = d.diff(g, fi, Sym::Noise(k as u32));
            noise_jacobian.push(g.substitute_zero(gk, &is_noise, &mut memo));
        }
    }

    // Qd = G Q G^T (times dt if continuous); Q = diag(q).
    let q: Vec<Id> = (0..nw)
        .map(|k| g.sym(Sym::NoiseIntensity(k as u32)))
        .collect();
    let gq: Vec<Id> = (0..n * nw)
        .map(|ik| g.mul(noise_jacobian[ik], q[ik % nw.max(1)]))
        .collect();
    let mut process_noise = vec![Graph::ZERO; n * n];
    for i in 0..n {
        for j in i..n {
            let terms: Vec<Id> = (0..nw)
                .map(|k| g.mul(gq[i * nw + k], noise_jacobian[j * nw + k]))
                .collect();
            let s = g.sum(terms);
            let s = if kind == ProcessKind::Continuous {
                g.mul(s, dt)
            } else {
                s
            };
            process_noise[i * n + j] = s;
            process_noise[j * n + i] = s;
        }
    }

    // Phi = I + C with C = F dt (continuous) or Phi = C = df/dx (discrete);
    // a discrete row equal to e_i is a unit row, as is a zero row of F.
    let identity = kind == ProcessKind::Continuous;
    let mut rows = Vec::new();
    let mut entries: Vec<Vec<(usize, Id)>> = Vec::new();
    for i in 0..n {
        let row = &jacobian[i * n..(i + 1) * n];
        let unit = if identity {
            row.iter().all(|&e| g.is_zero(e))
        } else {
            row.iter().enumerate().all(|(k, &e)| {
                if k == i {
                    e == Graph::ONE
                } else {
                    g.is_zero(e)
                }
            })
        };
        if unit {
            continue;
        }
        rows.push(i);
        let nonzero: Vec<(usize, Id)> = row
            .iter()
            .enumerate()
            .filter(|(_, &e)| !g.is_zero(e))
            .map(|(k, &e)| (k, e))
            .collect();
        entries.push(
            nonzero
                .into_iter()
                .map(|(k, e)| (k, if identity { g.mul(e, dt) } else { e }))
                .collect(),
        );
    }
    // A discrete `Phi` whose changed rows all hold exactly 1 on the diagonal
    // (an increment `x + ..` in every row, as in PX4's model) is `I + C` as
    // well: the kernel then starts each row of `Phi P` from the row of `P` and
    // spends no multiply on the diagonal.
    let identity = identity
        || (!rows.is_empty()
            && rows
                .iter()
                .zip(&entries)
                .all(|(&i, row)| row.iter().any(|&(k, e)| k == i && e == Graph::ONE)));
    if identity && kind == ProcessKind::Discrete {
        for (&i, row) in rows.iter().zip(entries.iter_mut()) {
            row.retain(|&(k, _)| k != i);
        }
    }
    let noise = (0..n)
        .flat_map(|i| (i..n).map(move |j| (i, j)))
        .map(|(i, j)| (i, j, process_noise[i * n + j]))
        .filter(|&(_, _, e)| !g.is_zero(e))
        .collect();
    let unrolled = (n <= UNROLL_MAX_STATES).then(|| {
        // A = Phi P; result_ij = sum_k A_ik Phi_jk + Qd_ij for i <= j.
        let phi: Vec<Id> = (0..n * n)
            .map(|ij| match kind {
                ProcessKind::Continuous => {
                    let fdt = g.mul(jacobian[ij], dt);
                    if ij / n == ij % n {
                        g.add(Graph::ONE, fdt)
                    } else {
                        fdt
                    }
                }
                ProcessKind::Discrete => jacobian[ij],
            })
            .collect();
        let nonzero_cols: Vec<Vec<usize>> = (0..n)
            .map(|i| (0..n).filter(|&k| !g.is_zero(phi[i * n + k])).collect())
            .collect();
        let mut a = vec![Graph::ZERO; n * n];
        for i in 0..n {
            for k in 0..n {
                a[i * n + k] = row_times_cov(g, &phi[i * n..(i + 1) * n], &nonzero_cols[i], k);
            }
        }
        let mut out = Vec::with_capacity(n * (n + 1) / 2);
        for i in 0..n {
            for j in i..n {
                let terms: Vec<Id> = nonzero_cols[j]
                    .iter()
                    .map(|&k| g.mul(a[i * n + k], phi[j * n + k]))
                    .collect();
                let s = g.sum(terms);
                out.push((i, j, g.add(s, process_noise[i * n + j])));
            }
        }
        out
    });
    let propagation = Propagation {
        identity,
        rows,
        entries,
        noise,
        unrolled,
    };

    let sensors = sensors
        .into_iter()
        .map(|h| {
            let m = h.len();
            let mut hj = Vec::with_capacity(m * n);
            for &hi in &h {
                for j in 0..n {
                    hj.push(d.diff(g, hi, Sym::State(j as u32)));
                }
            }
            let nonzero: Vec<Vec<usize>> = (0..m)
                .map(|r| (0..n).filter(|&k| !g.is_zero(hj[r * n + k])).collect())
                .collect();
            let mut pht = vec![Graph::ZERO; n * m];
            for i in 0..n {
                for r in 0..m {
                    pht[i * m + r] = row_times_cov(g, &hj[r * n..(r + 1) * n], &nonzero[r], i);
                }
            }
            let mut hpht = Vec::new();
            for r in 0..m {
                for c in r..m {
                    let terms: Vec<Id> = nonzero[r]
                        .iter()
                        .map(|&k| g.mul(hj[r * n + k], pht[k * m + c]))
                        .collect();
                    hpht.push((r, c, g.sum(terms)));
                }
            }
            DerivedSensor {
                m,
                h,
                jacobian: hj,
                pht,
                hpht,
            }
        })
        .collect();

    let is_state = |s: Sym| matches!(s, Sym::State(_));
    let mut memo = HashMap::new();
    let zero_is_fixed = transition
        .iter()
        .all(|&t| g.substitute_zero(t, &is_state, &mut memo) == Graph::ZERO);
    Derived {
        zero_is_fixed,
        graph,
        kind,
        n,
        nw,
        f_noisy,
        f,
        transition,
        step_noisy,
        jacobian,
        noise_jacobian,
        process_noise,
        propagation,
        sensors,
    }
}

impl Derived {
    /// Per state scalar: does some sensor depend on it, directly (a structural
    /// nonzero of a sensor's `H`) or through the dynamics (a nonzero `F[i][j]`,
    /// `i != j`, of a state `i` that is used)? An unused state can never be
    /// corrected by a measurement nor influence one.
    pub fn used_states(&self) -> Vec<bool> {
        self.observable_with(&vec![true; self.sensors.len()])
    }

    /// Per sensor and state scalar: does the sensor's `h` depend on the state
    /// directly (a structural nonzero in some row of its `H`)?
    pub fn sensor_depends(&self) -> Vec<Vec<bool>> {
        let n = self.n;
        self.sensors
            .iter()
            .map(|s| {
                let mut dep = vec![false; n];
                for (k, &id) in s.jacobian.iter().enumerate() {
                    dep[k % n] |= !self.graph.is_zero(id);
                }
                dep
            })
            .collect()
    }

    /// Per state scalar, with only the sensors marked in `sensors`: is there a
    /// path from the state to a measurement, i.e. does an enabled sensor depend
    /// on it directly, or the derivative (discrete: the step) of a reached
    /// state depend on it (`F[i][j] != 0`, `i != j`)? Structural: a `false` is
    /// "can never be corrected", a `true` only "not excluded by sparsity".
    pub fn observable_with(&self, sensors: &[bool]) -> Vec<bool> {
        let n = self.n;
        let mut used = vec![false; n];
        let mut work = Vec::new();
        for (dep, _) in self
            .sensor_depends()
            .iter()
            .zip(sensors)
            .filter(|(_, &on)| on)
        {
            for (j, &d) in dep.iter().enumerate() {
                if d && !used[j] {
                    used[j] = true;
                    work.push(j);
                }
            }
        }
        while let Some(i) = work.pop() {
            for (j, u) in used.iter_mut().enumerate() {
                if j != i && !*u && !self.graph.is_zero(self.jacobian[i * n + j]) {
                    *u = true;
                    work.push(j);
                }
            }
        }
        used
    }
}
