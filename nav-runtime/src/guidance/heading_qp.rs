//! The constrained course correction: one convex program per guidance tick,
//! solved with clarabel (docs/guidance.md, "The constrained heading correction").
//!
//! Horizon `N` steps of `dt`; decision variables
//! `x = [u_0..u_{N-1}, chi_1..chi_N, e_1..e_N, sigma_1..sigma_N]`: course-rate
//! commands, ground courses, cross-track errors and keep-out slacks. Positions are
//! linearized about a nominal course sequence `chi_bar` (the previous solution
//! shifted by one tick):
//! `p_k = p_bar_k + sum_{j<=k} dt U_j t_j (chi_j - chi_bar_j)`,
//! `t_j = [-sin chi_bar_j, cos chi_bar_j]`, with `U_j` the scheduled ground speed.
//!
//! Cost: `sum w_chi (chi_k - chi_ref_k)^2 + w_e e_k^2 + lambda u_k^2
//! + mu (u_k - u_{k-1})^2 + rho sigma_k`, `chi_ref_k` the improved-LOS course at the
//! nominal predicted point (corners are previewed). clarabel's form is
//! `min 1/2 x'Px + q'x`, `Ax + s = b`, `s in K`; `P` is given as its upper triangle.
//!
//! Rows of `A`, in cone order:
//! 1. zero: `chi_{k+1} - chi_k - dt u_k = 0` (`chi_0` is the current command);
//! 2. zero: `e_k - n_k' (p_k - a_k) = 0`, the linearized cross-track error;
//! 3. nonnegative: `u_k <= r_max`, `-u_k <= r_max`;
//! 4. nonnegative: `|u_0 - u_last| <= a_max T_tick`, `|u_k - u_{k-1}| <= a_max dt`;
//! 5. nonnegative: keep-out half-space tangent to the nearest capsule,
//!    `m_k' (p_k - c_k) + sigma_k >= R_k + m_safe + m_lin` (a row of zeros with a
//!    large right-hand side when no capsule is near, so the pattern never changes);
//! 6. nonnegative: `sigma_k >= 0`;
//! 7. second-order cone: `||chi - chi_bar|| <= Delta_tr`, which bounds the
//!    linearization error of each position by `m_lin = U dt Delta_tr^2 / 2`.
//!
//! The problem is always feasible (a large `sigma` satisfies row 5, and the
//! nominal course sequence respects rows 3-4 up to the trust region), so a status
//! other than `Solved` is a numerical event: the tick falls back to the
//! rate-limited improved LOS and is counted.

use std::time::Instant;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{Vector2, Vector3};

use super::los::improved_los_course;
use super::structure::Structure;
use super::{unwrap_near, GuidanceConfig, Path, PathFollower};

/// Settings of the convex program.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QpConfig {
    /// Horizon steps `N`.
    pub horizon: usize,
    /// Step `dt`, s.
    pub dt: f64,
    /// Weight on `(chi - chi_ref)^2`, 1/rad^2.
    pub w_course: f64,
    /// Weight on `e^2`, 1/m^2.
    pub w_cross: f64,
    /// Weight on `u^2`, s^2/rad^2.
    pub lambda: f64,
    /// Weight on `(u_k - u_{k-1})^2`, s^2/rad^2.
    pub mu: f64,
    /// Weight on the keep-out slack, 1/m.
    pub rho: f64,
    /// Trust region `Delta_tr`, rad.
    pub trust_region: f64,
    /// Safety margin `m_safe` beyond capsule radius plus vehicle radius, m.
    pub margin: f64,
    /// Capsules farther than this from a predicted point are ignored, m.
    pub keep_out_range: f64,
}

impl Default for QpConfig {
    fn default() -> Self {
        Self {
            horizon: 10,
            dt: 0.5,
            w_course: 1.0,
            w_cross: 6.0,
            lambda: 0.05,
            mu: 0.5,
            rho: 200.0,
            trust_region: 0.5,
            margin: 0.1,
            keep_out_range: 1.5,
        }
    }
}

/// Counters and per-call times.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct QpStats {
    /// Ticks solved to `Solved`.
    pub solved: u64,
    /// Ticks that fell back to rate-limited LOS.
    pub fallbacks: u64,
    /// Wall time of each call (assembly, data update and solve), ms.
    pub times_ms: Vec<f64>,
    /// Interior-point iterations of each solved call.
    pub iterations: Vec<u32>,
}

/// Everything one tick needs.
#[derive(Clone, Copy, Debug)]
pub struct QpInput<'a> {
    /// The path.
    pub path: &'a Path,
    /// The follower (its active segment; copied for the preview).
    pub follower: PathFollower,
    /// Estimated position, m.
    pub position: Vector3<f64>,
    /// Shared guidance settings (limits, speeds, tick).
    pub guidance: &'a GuidanceConfig,
    /// The structure whose capsules are keep-outs.
    pub structure: &'a Structure,
    /// Vehicle radius added to each capsule radius, m.
    pub vehicle_radius: f64,
    /// Current horizontal speed command, m/s.
    pub speed: f64,
    /// Estimated horizontal ground speed, m/s: the prediction starts from it
    /// and converges to the command at the velocity-loop bandwidth.
    pub ground_speed: f64,
    /// Velocity-loop bandwidth of the vehicle, 1/s.
    pub velocity_bandwidth: f64,
}

/// One tick's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QpOutput {
    /// New course command (unwrapped), rad.
    pub course: f64,
    /// Course rate applied over the tick, rad/s.
    pub rate: f64,
    /// Whether the convex program was solved (false: fallback).
    pub solved: bool,
}

/// The linearized problem data of one tick (also used by the tests).
#[derive(Clone, Debug)]
pub struct QpProblem {
    /// Upper triangle of `P`.
    pub p: CscMatrix<f64>,
    /// Linear cost.
    pub q: Vec<f64>,
    /// Constraint matrix.
    pub a: CscMatrix<f64>,
    /// Right-hand side.
    pub b: Vec<f64>,
    /// Cones in row order.
    pub cones: Vec<SupportedConeT<f64>>,
    /// Nominal courses `chi_bar_1..N`.
    pub chi_bar: Vec<f64>,
    /// Course at the start of the horizon.
    pub chi0: f64,
    /// Previous rate command.
    pub u_last: f64,
}

/// The course-correction controller with its reusable solver.
pub struct CourseQp {
    cfg: QpConfig,
    solver: Option<DefaultSolver<f64>>,
    /// Previous solution `chi_1..N` (the nominal for the next tick).
    prev: Vec<f64>,
    course: f64,
    u_last: f64,
    /// Counters and times.
    pub stats: QpStats,
}

impl CourseQp {
    /// A controller starting with course command `course` (rad).
    pub fn new(cfg: QpConfig, course: f64) -> Self {
        Self {
            cfg,
            solver: None,
            prev: vec![course; cfg.horizon],
            course,
            u_last: 0.0,
            stats: QpStats::default(),
        }
    }

    /// Current course command (unwrapped), rad.
    pub fn course(&self) -> f64 {
        self.course
    }

    /// Settings.
    pub fn config(&self) -> &QpConfig {
        &self.cfg
    }

    /// The nominal course sequence for this tick: the previous solution shifted by
    /// one tick (linear interpolation, last value held).
    fn nominal(&self, tick: f64) -> Vec<f64> {
        let n = self.cfg.horizon;
        let at = |t: f64| -> f64 {
            // Samples: chi(0) = course, chi(k dt) = prev[k-1].
            let s = t / self.cfg.dt;
            let i = s.floor() as usize;
            let f = s - i as f64;
            let v = |j: usize| -> f64 {
                if j == 0 {
                    self.course
                } else {
                    self.prev[(j - 1).min(n - 1)]
                }
            };
            if i >= n {
                v(n)
            } else {
                v(i) * (1.0 - f) + v(i + 1) * f
            }
        };
        (1..=n).map(|k| at(tick + k as f64 * self.cfg.dt)).collect()
    }

    /// Builds the problem of one tick (no solving).
    pub fn build(&self, input: &QpInput<'_>) -> QpProblem {
        let c = &self.cfg;
        let g = input.guidance;
        let n = c.horizon;
        let dt = c.dt;
        let chi_bar = self.nominal(g.tick);
        let chi0 = self.course;
        // Nominal rollout.
        let mut f = input.follower;
        let mut p = Vector2::new(input.position.x, input.position.y);
        let mut speeds = Vec::with_capacity(n);
        let mut pbar = Vec::with_capacity(n);
        let mut errs = Vec::with_capacity(n);
        let mut u = input.speed;
        let mut lag = input.ground_speed - input.speed;
        let decay = (-input.velocity_bandwidth * dt).exp();
        for &chi in chi_bar.iter() {
            let e = f.update(input.path, &p, g);
            u = g.speed_command(input.path, &e, chi, u, dt);
            lag *= decay;
            let moving = (u + lag).max(0.0);
            speeds.push(moving);
            p += Vector2::new(chi.cos(), chi.sin()) * (moving * dt);
            pbar.push(p);
            errs.push(f.update(input.path, &p, g));
        }
        // g_kj = dt U_j t_j.
        let t: Vec<Vector2<f64>> = chi_bar
            .iter()
            .zip(&speeds)
            .map(|(&chi, &u)| Vector2::new(-chi.sin(), chi.cos()) * (dt * u))
            .collect();
        let iu = |k: usize| k;
        let ic = |k: usize| n + k - 1; // k = 1..=n
        let ie = |k: usize| 2 * n + k - 1;
        let is = |k: usize| 3 * n + k - 1;
        let nvar = 4 * n;

        // P (upper triangle) and q.
        let (mut pi, mut pj, mut pv) = (Vec::new(), Vec::new(), Vec::new());
        let mut q = vec![0.0; nvar];
        for k in 0..n {
            if k > 0 {
                pi.push(iu(k - 1));
                pj.push(iu(k));
                pv.push(-2.0 * c.mu);
            }
            let pairs = if k + 1 < n { 2.0 } else { 1.0 };
            pi.push(iu(k));
            pj.push(iu(k));
            pv.push(2.0 * c.lambda + 2.0 * c.mu * pairs);
        }
        q[iu(0)] = -2.0 * c.mu * self.u_last;
        let turning = g.turning_radius(g.cruise_speed);
        for k in 1..=n {
            let e = &errs[k - 1];
            let reference = unwrap_near(
                improved_los_course(e, g.los_radius, turning),
                chi_bar[k - 1],
            );
            pi.push(ic(k));
            pj.push(ic(k));
            pv.push(2.0 * c.w_course);
            q[ic(k)] = -2.0 * c.w_course * reference;
            pi.push(ie(k));
            pj.push(ie(k));
            pv.push(2.0 * c.w_cross);
            q[is(k)] = c.rho;
        }
        let p_mat = CscMatrix::new_from_triplets(nvar, nvar, pi, pj, pv);

        // A and b, rows in cone order.
        let (mut ai, mut aj, mut av) = (Vec::new(), Vec::new(), Vec::new());
        let mut b = Vec::new();
        let mut row = 0;
        let mut put = |r: usize, col: usize, v: f64| {
            ai.push(r);
            aj.push(col);
            av.push(v);
        };
        // 1. Course dynamics.
        for k in 0..n {
            put(row, ic(k + 1), 1.0);
            if k > 0 {
                put(row, ic(k), -1.0);
            }
            put(row, iu(k), -dt);
            b.push(if k == 0 { chi0 } else { 0.0 });
            row += 1;
        }
        // 2. Cross-track errors.
        for k in 1..=n {
            let e = &errs[k - 1];
            let nk = Vector2::new(-e.path_angle.sin(), e.path_angle.cos());
            let a = input.path.points[e.segment];
            let mut rhs = nk.dot(&(pbar[k - 1] - Vector2::new(a.x, a.y)));
            put(row, ie(k), 1.0);
            for j in 1..=k {
                let ckj = nk.dot(&t[j - 1]);
                put(row, ic(j), -ckj);
                rhs -= ckj * chi_bar[j - 1];
            }
            b.push(rhs);
            row += 1;
        }
        // 3. Rate limits.
        for k in 0..n {
            put(row, iu(k), 1.0);
            b.push(g.max_course_rate);
            row += 1;
            put(row, iu(k), -1.0);
            b.push(g.max_course_rate);
            row += 1;
        }
        // 4. Rate-change limits.
        for k in 0..n {
            let (lim, prev) = if k == 0 {
                (g.max_course_accel * g.tick, self.u_last)
            } else {
                (g.max_course_accel * dt, 0.0)
            };
            for sign in [1.0, -1.0] {
                put(row, iu(k), sign);
                if k > 0 {
                    put(row, iu(k - 1), -sign);
                }
                b.push(lim + sign * prev);
                row += 1;
            }
        }
        // 5. Keep-out half-spaces.
        let m_lin =
            speeds.iter().fold(0.0f64, |a, &b| a.max(b)) * dt * c.trust_region * c.trust_region
                / 2.0;
        for k in 1..=n {
            let pk = Vector3::new(pbar[k - 1].x, pbar[k - 1].y, errs[k - 1].depth);
            let half_space = keep_out(input.structure, &pk, input.vehicle_radius, c);
            put(row, is(k), -1.0);
            match half_space {
                Some((m, centre, radius)) => {
                    let m_xy = Vector2::new(m.x, m.y);
                    let mut rhs = m.dot(&(pk - centre)) - (radius + c.margin + m_lin);
                    for j in 1..=k {
                        let coef = m_xy.dot(&t[j - 1]);
                        put(row, ic(j), -coef);
                        rhs -= coef * chi_bar[j - 1];
                    }
                    b.push(rhs);
                }
                None => {
                    for j in 1..=k {
                        put(row, ic(j), 0.0);
                    }
                    b.push(1e3);
                }
            }
            row += 1;
        }
        // 6. Slacks nonnegative.
        for k in 1..=n {
            put(row, is(k), -1.0);
            b.push(0.0);
            row += 1;
        }
        // 7. Trust region cone: s = [Delta; chi - chi_bar].
        b.push(c.trust_region);
        row += 1;
        for k in 1..=n {
            put(row, ic(k), -1.0);
            b.push(-chi_bar[k - 1]);
            row += 1;
        }
        let a_mat = CscMatrix::new_from_triplets(row, nvar, ai, aj, av);
        let cones = vec![
            SupportedConeT::ZeroConeT(2 * n),
            SupportedConeT::NonnegativeConeT(6 * n),
            SupportedConeT::SecondOrderConeT(n + 1),
        ];
        QpProblem {
            p: p_mat,
            q,
            a: a_mat,
            b,
            cones,
            chi_bar,
            chi0,
            u_last: self.u_last,
        }
    }

    /// One guidance tick: solve, apply `u_0` over the tick, or fall back.
    pub fn step(&mut self, input: &QpInput<'_>) -> QpOutput {
        let start = Instant::now();
        let problem = self.build(input);
        let solution = self.solve(&problem);
        let g = input.guidance;
        let n = self.cfg.horizon;
        let out = match solution {
            Some((x, iterations)) => {
                self.stats.solved += 1;
                self.stats.iterations.push(iterations);
                let u0 = x[0].clamp(-g.max_course_rate, g.max_course_rate);
                self.prev.copy_from_slice(&x[n..2 * n]);
                self.u_last = u0;
                self.course += u0 * g.tick;
                QpOutput {
                    course: self.course,
                    rate: u0,
                    solved: true,
                }
            }
            None => {
                self.stats.fallbacks += 1;
                let rate = self.fallback_rate(input);
                self.u_last = rate;
                self.course += rate * g.tick;
                self.prev = vec![self.course; n];
                QpOutput {
                    course: self.course,
                    rate,
                    solved: false,
                }
            }
        };
        self.stats
            .times_ms
            .push(start.elapsed().as_secs_f64() * 1e3);
        out
    }

    /// Rate-limited improved LOS: the fallback when the program is not solved.
    pub fn fallback_rate(&self, input: &QpInput<'_>) -> f64 {
        let g = input.guidance;
        let mut f = input.follower;
        let e = f.update(
            input.path,
            &Vector2::new(input.position.x, input.position.y),
            g,
        );
        let target = improved_los_course(&e, g.los_radius, g.turning_radius(g.cruise_speed));
        let wanted = crate::math::wrap_angle(target - self.course) / g.tick;
        let accel = g.max_course_accel * g.tick;
        wanted
            .clamp(self.u_last - accel, self.u_last + accel)
            .clamp(-g.max_course_rate, g.max_course_rate)
    }

    /// Solves `problem`, reusing the solver (presolve off, structural zeros kept,
    /// so only `q`, `A` and `b` are updated). `None` unless the status is `Solved`.
    fn solve(&mut self, problem: &QpProblem) -> Option<(Vec<f64>, u32)> {
        let reused = match self.solver.as_mut() {
            Some(s) => {
                s.update_q(&problem.q).is_ok()
                    && s.update_A(&problem.a).is_ok()
                    && s.update_b(&problem.b).is_ok()
            }
            None => false,
        };
        if !reused {
            let solver = DefaultSolver::new(
                &problem.p,
                &problem.q,
                &problem.a,
                &problem.b,
                &problem.cones,
                settings(),
            )
            .ok()?;
            self.solver = Some(solver);
        }
        let solver = self.solver.as_mut()?;
        solver.solve();
        let sol = &solver.solution;
        if sol.status == SolverStatus::Solved && sol.x.iter().all(|v| v.is_finite()) {
            Some((sol.x.clone(), sol.iterations))
        } else {
            None
        }
    }

    /// Forces the next solves to report failure (tests of the fallback path).
    #[cfg(test)]
    fn break_solver(&mut self) {
        self.cfg.trust_region = -1.0;
    }
}

fn settings() -> DefaultSettings<f64> {
    DefaultSettingsBuilder::default()
        .verbose(false)
        .presolve_enable(false)
        .input_sparse_dropzeros(false)
        .max_iter(60)
        .build()
        .expect("valid settings")
}

/// The keep-out half-space for predicted point `p`: unit normal `m` (3-D, from the
/// nearest capsule axis point `c` toward `p`), `c`, and the keep-out radius
/// (capsule radius plus vehicle radius); `None` when no capsule is within range
/// or the normal is nearly vertical (the capsule is above or below, so a
/// horizontal course change cannot move away from it).
fn keep_out(
    s: &Structure,
    p: &Vector3<f64>,
    vehicle_radius: f64,
    cfg: &QpConfig,
) -> Option<(Vector3<f64>, Vector3<f64>, f64)> {
    let (dist, i) = s.nearest(p);
    if dist - vehicle_radius > cfg.keep_out_range {
        return None;
    }
    let cap = &s.capsules[i];
    let c = cap.closest_axis_point(p);
    let d = p - c;
    let len = d.norm();
    if len < 1e-6 {
        return None;
    }
    let m = d / len;
    if (m.x * m.x + m.y * m.y).sqrt() < 0.3 {
        return None;
    }
    Some((m, c, cap.radius + vehicle_radius))
}

#[cfg(test)]
mod tests {
    use super::super::structure::Capsule;
    use super::*;

    fn problem_world() -> (Path, Structure) {
        // A northbound leg passing 0.3 m west of a vertical pole whose keep-out
        // (pole radius plus vehicle radius) is 0.4 m: the straight leg collides.
        let path = Path::new(vec![
            Vector3::new(0.0, 0.0, 15.0),
            Vector3::new(8.0, 0.0, 15.0),
            Vector3::new(8.0, 6.0, 15.0),
        ]);
        let mut s = Structure::test_jacket();
        s.capsules = vec![Capsule::new(
            Vector3::new(3.0, 0.3, 10.0),
            Vector3::new(3.0, 0.3, 20.0),
            0.1,
        )];
        s.markers.clear();
        s.bounds.min = Vector3::new(-10.0, -10.0, 0.0);
        s.bounds.max = Vector3::new(20.0, 20.0, 30.0);
        (path, s)
    }

    /// Checks every constraint of the solved program at its solution.
    fn check_constraints(p: &QpProblem, x: &[f64], g: &GuidanceConfig, c: &QpConfig) {
        let n = c.horizon;
        let tol = 1e-6;
        // A x + s = b with s in the cones.
        let mut ax = vec![0.0; p.b.len()];
        for (col, xc) in x.iter().enumerate().take(p.a.n) {
            for idx in p.a.colptr[col]..p.a.colptr[col + 1] {
                ax[p.a.rowval[idx]] += p.a.nzval[idx] * xc;
            }
        }
        let s: Vec<f64> = p.b.iter().zip(&ax).map(|(b, a)| b - a).collect();
        for (i, v) in s.iter().enumerate().take(2 * n) {
            assert!(v.abs() < tol, "zero row {i}: {v}");
        }
        for (i, v) in s.iter().enumerate().skip(2 * n).take(6 * n) {
            assert!(*v > -tol, "nonnegative row {i}: {v}");
        }
        let soc = &s[8 * n..];
        let tail: f64 = soc[1..].iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(soc[0] >= tail - tol, "cone: {} < {tail}", soc[0]);
        // The same limits read directly off the variables.
        let mut prev = p.u_last;
        for (k, &u) in x.iter().enumerate().take(n) {
            assert!(u.abs() <= g.max_course_rate + tol);
            let lim = if k == 0 {
                g.max_course_accel * g.tick
            } else {
                g.max_course_accel * c.dt
            };
            assert!((u - prev).abs() <= lim + tol, "step {k}");
            prev = u;
        }
        let mut chi = p.chi0;
        for (k, u) in x.iter().enumerate().take(n) {
            chi += c.dt * u;
            assert!((x[n + k] - chi).abs() < tol);
            assert!(x[3 * n + k] > -tol);
        }
        let dev: f64 = (0..n)
            .map(|k| (x[n + k] - p.chi_bar[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(dev <= c.trust_region + tol);
    }

    #[test]
    fn solution_satisfies_every_constraint_and_clears_the_pole() {
        let (path, s) = problem_world();
        let g = GuidanceConfig::default();
        let cfg = QpConfig::default();
        let mut qp = CourseQp::new(cfg, 0.0);
        let follower = PathFollower::new();
        let mut pos = Vector3::new(0.0, 0.0, 15.0);
        let mut min_clear = f64::INFINITY;
        for _ in 0..400 {
            let input = QpInput {
                path: &path,
                follower,
                position: pos,
                guidance: &g,
                structure: &s,
                vehicle_radius: 0.3,
                speed: 0.3,
                ground_speed: 0.3,
                velocity_bandwidth: 1.2,
            };
            let problem = qp.build(&input);
            let out = qp.step(&input);
            assert!(out.solved);
            let x = qp.solver.as_ref().unwrap().solution.x.clone();
            check_constraints(&problem, &x, &g, &cfg);
            // Kinematic vehicle flying the command along the first leg.
            let e = path.errors(0, &Vector2::new(pos.x, pos.y));
            let u = g.speed(&path, 0, e.along).max(0.1);
            pos += Vector3::new(out.course.cos(), out.course.sin(), 0.0) * (u * g.tick);
            min_clear = min_clear.min(s.nearest(&pos).0 - 0.3);
            if pos.x > 6.0 {
                break;
            }
        }
        assert_eq!(qp.stats.fallbacks, 0);
        assert!(pos.x > 6.0, "made progress: {pos}");
        // The straight leg would enter the inflated pole by 0.1 m; the program
        // steers around it.
        assert!(min_clear > 0.0, "clearance {min_clear}");
        // Every call is timed (the figure is reported by the scenario; a wall-clock
        // limit in a test would fail on a loaded machine, not on slow code).
        assert!(qp.stats.times_ms.iter().all(|t| t.is_finite() && *t >= 0.0));
    }

    #[test]
    fn fallback_is_counted_and_rate_limited() {
        let (path, s) = problem_world();
        let g = GuidanceConfig::default();
        let mut qp = CourseQp::new(QpConfig::default(), 1.0);
        qp.break_solver();
        let input = QpInput {
            path: &path,
            follower: PathFollower::new(),
            position: Vector3::new(0.0, 0.0, 15.0),
            guidance: &g,
            structure: &s,
            vehicle_radius: 0.3,
            speed: 0.2,
            ground_speed: 0.2,
            velocity_bandwidth: 1.2,
        };
        let mut last = qp.course();
        for i in 0..5 {
            let out = qp.step(&input);
            assert!(!out.solved);
            assert_eq!(qp.stats.fallbacks, i + 1);
            assert!((out.course - last).abs() <= g.max_course_rate * g.tick + 1e-12);
            assert!(out.course < last, "turns toward the path course 0");
            last = out.course;
        }
        assert_eq!(qp.stats.solved, 0);
        assert_eq!(qp.stats.times_ms.len(), 5);
    }
}
