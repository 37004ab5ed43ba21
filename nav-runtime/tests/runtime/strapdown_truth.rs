//! The strapdown mechanization driven by error-free synthesized IMU data must
//! reproduce the kinematic truth: this checks the Earth model, the truth
//! generator, the IMU synthesis and the strapdown algorithms against each other.
//! Figures are printed (run with `--nocapture`).
#![cfg(feature = "std")]

use nav_runtime::earth::Geodetic;
use nav_runtime::imu::{increments, rates};
use nav_runtime::strapdown::{NavState, Strapdown};
use nav_runtime::trajectory::{scenarios, ManeuverLimits, Trajectory, TrajectorySpec, TruthSource};

/// Largest errors over a run, sampled every second.
#[derive(Debug, Default, Clone, Copy)]
struct Worst {
    horizontal: f64,
    vertical: f64,
    velocity: f64,
    attitude: f64,
}

impl Worst {
    fn add(&mut self, nav: &NavState, truth: &NavState) {
        let e = nav.error_from(truth);
        let p = e.position_ned(truth.lat, truth.h);
        self.horizontal = self.horizontal.max((p[0] * p[0] + p[1] * p[1]).sqrt());
        self.vertical = self.vertical.max(p[2].abs());
        self.velocity = self.velocity.max(e.dv_n.norm());
        self.attitude = self.attitude.max(e.phi.norm());
    }
    fn position(&self) -> f64 {
        (self.horizontal * self.horizontal + self.vertical * self.vertical).sqrt()
    }
}

/// Increments over [0, 0.01], [0.01, 0.02], ...; the first one primes the
/// coning/sculling history and the navigation starts from the truth at 0.01 s.
fn run_increments(tr: &Trajectory, t_end: f64, compensate: bool) -> Worst {
    let mut it = increments(tr, 100.0, t_end);
    let first = it.next().unwrap();
    let mut nav = Strapdown::new(tr.truth(first.t).nav_state());
    nav.prime_increments(&first.dtheta, &first.dv);
    nav.compensate = compensate;
    let mut w = Worst::default();
    for s in it {
        nav.update_increments(&s.dtheta, &s.dv, s.dt);
        if (s.t * 100.0).round() as i64 % 100 == 0 {
            w.add(&nav.state, &tr.truth(s.t).nav_state());
        }
    }
    w
}

/// Rate samples at t = 0, 0.01, ...; the samples at 0, 0.01 and 0.02 s prime
/// the rate model and the navigation starts from the truth at 0.02 s.
fn run_rates(tr: &Trajectory, t_end: f64) -> Worst {
    let mut it = rates(tr, 100.0, t_end);
    let mut nav = Strapdown::new(tr.truth(0.02).nav_state());
    for s in it.by_ref().take(3) {
        nav.prime_rates(&s.w_ib_b, &s.f_b, 0.01);
    }
    let mut w = Worst::default();
    for s in it {
        nav.update_rates(&s.w_ib_b, &s.f_b, 0.01);
        if (s.t * 100.0).round() as i64 % 100 == 0 {
            w.add(&nav.state, &tr.truth(s.t).nav_state());
        }
    }
    w
}

/// A 900 s track that turns, dives, changes speed and rolls (a 0.5 Hz, 5 deg
/// roll oscillation and a pitch oscillation make the rotation genuinely
/// three-dimensional, so coning and sculling are present).
fn turning_diving() -> TrajectorySpec {
    let start = Geodetic::from_degrees(36.4, 127.36, -20.0);
    let mut s = TrajectorySpec::new(start, 30f64.to_radians(), 2.0);
    s.limits = ManeuverLimits {
        max_turn_rate: 10f64.to_radians(),
        turn_ramp: 2.0,
        max_down_velocity: 0.4,
        dive_ramp: 3.0,
    };
    for (t, deg) in [
        (20.0, 120.0),
        (80.0, -200.0),
        (150.0, 45.0),
        (210.0, 360.0),
        (400.0, -90.0),
        (520.0, 150.0),
        (700.0, -75.0),
        (820.0, 30.0),
    ] {
        s.turn(t, f64::to_radians(deg));
    }
    for (t, dd) in [
        (40.0, 30.0),
        (130.0, -20.0),
        (300.0, 50.0),
        (480.0, -40.0),
        (650.0, 25.0),
        (800.0, -10.0),
    ] {
        s.change_depth(t, dd);
    }
    s.change_speed(250.0, 20.0, 1.0);
    s.change_speed(600.0, 30.0, -1.5);
    s.roll
        .add_sine(5f64.to_radians(), std::f64::consts::PI, 0.0);
    s.pitch_offset.add_sine(2f64.to_radians(), 0.6, 0.4);
    s
}

#[test]
fn lawn_mower_500_s_reproduces_truth() {
    let tr = scenarios::sdins25_lawn_mower().build(500.0);
    let inc = run_increments(&tr, 500.0, true);
    let rat = run_rates(&tr, 500.0);
    println!("lawn-mower 500 s, increments: {inc:?}");
    println!("lawn-mower 500 s, rates:      {rat:?}");
    assert!(inc.position() < 0.05, "{inc:?}");
    assert!(rat.position() < 0.05, "{rat:?}");
}

#[test]
fn turning_diving_900_s_reproduces_truth() {
    let tr = turning_diving().build(900.0);
    let inc = run_increments(&tr, 900.0, true);
    let raw = run_increments(&tr, 900.0, false);
    let rat = run_rates(&tr, 900.0);
    println!("turning/diving 900 s, increments:             {inc:?}");
    println!("turning/diving 900 s, no coning/sculling:     {raw:?}");
    println!("turning/diving 900 s, rates:                  {rat:?}");
    assert!(inc.position() < 0.01, "{inc:?}");
    assert!(rat.position() < 0.05, "{rat:?}");
    // The coning and sculling corrections matter on this motion.
    assert!(raw.attitude > 10.0 * inc.attitude, "{raw:?} vs {inc:?}");
}
