use super::*;
use crate::ekf::Ekf;
use crate::error_state::ErrorStateFilter;
use crate::testmodels::{Cvb, CvbInput, CvbNoise, Gauss, Offset, Pos, PosVel, Toy};

type Filter = Ekf<Cvb, 3>;
type V3 = SVector<f64, 3>;

const DT: f64 = 0.01;
const NOISE: CvbNoise = CvbNoise {
    q_a: 1e-2,
    q_b: 1e-6,
};

fn p0() -> SMatrix<f64, 3, 3> {
    SMatrix::<f64, 3, 3>::from_diagonal(&V3::new(4.0, 0.25, 0.01))
}

fn filter() -> Filter {
    Ekf::new(V3::new(0.5, 0.1, 0.0), p0(), (), NOISE).unwrap()
}

/// Sensor kinds of the scenarios: registered in this order.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Pos,
    PosVel,
    PosVelSequential,
}

#[derive(Clone, Copy, Debug)]
struct Meas {
    kind: Kind,
    time: f64,
    z: [f64; 2],
}

struct Scenario {
    imu: Vec<(f64, CvbInput)>,
    meas: Vec<Meas>,
}

/// Truth of the toy at 100 Hz; position fixes at 1 Hz, position-velocity
/// at 2 Hz (batch) and 2 Hz (sequential), at times off the IMU grid and,
/// for one sensor, on it.
fn scenario(seconds: u32, seed: u64) -> Scenario {
    let mut g = Gauss::new(seed);
    let (mut p, mut v, b) = (0.0, 0.0, 0.03);
    let mut imu = Vec::new();
    let mut truth = Vec::new();
    for k in 1..=seconds * 100 {
        let t = f64::from(k) * DT;
        let a = (t * 0.3).sin();
        p += v * DT;
        v += a * DT;
        imu.push((
            t,
            CvbInput {
                a: a + b + 0.05 * g.normal(),
            },
        ));
        truth.push((t, p, v));
    }
    let at = |t: f64| {
        truth
            .iter()
            .rev()
            .find(|s| s.0 <= t)
            .map_or((0.0, 0.0), |s| (s.1, s.2))
    };
    let mut meas = Vec::new();
    for k in 0..seconds {
        let t = f64::from(k) + 0.0037;
        let (p, _) = at(t);
        meas.push(Meas {
            kind: Kind::Pos,
            time: t,
            z: [p + 0.5 * g.normal(), 0.0],
        });
    }
    for k in 1..seconds * 2 {
        let t = f64::from(k) * 0.5 + 0.0021;
        let (p, v) = at(t);
        meas.push(Meas {
            kind: Kind::PosVel,
            time: t,
            z: [p + 0.3 * g.normal(), v + 0.05 * g.normal()],
        });
        // On the IMU grid (k * 0.5 s is a multiple of DT up to rounding of
        // the grid itself: use the grid's own value).
        let t_grid = imu[(k * 50 - 1) as usize].0;
        let (p, v) = at(t_grid);
        meas.push(Meas {
            kind: Kind::PosVelSequential,
            time: t_grid,
            z: [p + 0.3 * g.normal(), v + 0.05 * g.normal()],
        });
    }
    meas.sort_by(|a, b| a.time.total_cmp(&b.time));
    Scenario { imu, meas }
}

fn boxed(m: &Meas) -> Box<dyn Measurement<Filter>> {
    match m.kind {
        Kind::Pos => Box::new(SensorUpdate::<Pos, 3, 1>::new(
            SVector::<f64, 1>::new(m.z[0]),
            SMatrix::<f64, 1, 1>::new(0.25),
            Offset::default(),
        )),
        Kind::PosVel => Box::new(SensorUpdate::<PosVel, 3, 2>::new(
            SVector::<f64, 2>::new(m.z[0], m.z[1]),
            SMatrix::<f64, 2, 2>::new(0.09, 0.001, 0.001, 0.0025),
            (),
        )),
        Kind::PosVelSequential => Box::new(SensorUpdate::<PosVel, 3, 2>::sequential(
            SVector::<f64, 2>::new(m.z[0], m.z[1]),
            SVector::<f64, 2>::new(0.09, 0.0025),
            (),
        )),
    }
}

fn scheduler(snapshot_every: usize) -> (Scheduler<Filter>, [SensorId; 3]) {
    let mut s = Scheduler::new(filter(), 0.0)
        .unwrap()
        .with_snapshot_every(snapshot_every);
    let ids = [
        s.add_sensor("pos", 1.0, 5.0).unwrap(),
        s.add_sensor("posvel", 2.0, 5.0).unwrap(),
        s.add_sensor("posvel-seq", 2.0, 5.0).unwrap(),
    ];
    (s, ids)
}

fn id_of(ids: &[SensorId; 3], kind: Kind) -> SensorId {
    match kind {
        Kind::Pos => ids[0],
        Kind::PosVel => ids[1],
        Kind::PosVelSequential => ids[2],
    }
}

/// Runs a scenario where measurement `i` arrives at `arrival[i]` (an IMU
/// sample at `t` arrives at `t`; measurements arriving at the same time as
/// an IMU sample come first). Ties between measurements keep list order.
fn run(sc: &Scenario, arrival: &[f64], snapshot_every: usize) -> Scheduler<Filter> {
    let (mut s, ids) = scheduler(snapshot_every);
    let mut order: Vec<usize> = (0..sc.meas.len()).collect();
    order.sort_by(|&a, &b| arrival[a].total_cmp(&arrival[b]));
    let mut next = 0;
    for &(t, u) in &sc.imu {
        while let Some(&i) = order.get(next) {
            if arrival[i] > t {
                break;
            }
            let m = &sc.meas[i];
            s.push_measurement(id_of(&ids, m.kind), m.time, boxed(m))
                .unwrap();
            next += 1;
        }
        s.push_imu(t, u).unwrap();
    }
    // Whatever arrives after the last IMU sample is still delivered.
    for &i in order.get(next..).unwrap_or(&[]) {
        let m = &sc.meas[i];
        s.push_measurement(id_of(&ids, m.kind), m.time, boxed(m))
            .unwrap();
    }
    s
}

fn on_time(sc: &Scenario) -> Vec<f64> {
    // Delivered before the IMU sample that covers them.
    sc.meas.iter().map(|m| m.time - DT).collect()
}

fn rel_diff(a: &Filter, b: &Filter) -> f64 {
    let dx = (a.state() - b.state()).amax() / (1.0 + a.state().amax());
    let dp = (a.covariance() - b.covariance()).amax() / a.covariance().amax();
    dx.max(dp)
}

fn bits(s: &Scheduler<Filter>) -> Vec<u64> {
    let f = s.filter();
    let mut v: Vec<u64> = f
        .state()
        .iter()
        .chain(f.covariance().iter())
        .map(|x| x.to_bits())
        .collect();
    v.push(f.input().a.to_bits());
    v.push(s.now().to_bits());
    v.push(s.history_len() as u64);
    v.push(s.queue.len() as u64);
    v
}

#[test]
fn delayed_fix_equals_the_same_fix_on_time() {
    let sc = scenario(20, 1);
    let reference = run(&sc, &on_time(&sc), 1);
    let mut arrival = on_time(&sc);
    let i = sc
        .meas
        .iter()
        .position(|m| m.kind == Kind::Pos && m.time > 10.0)
        .unwrap();
    arrival[i] = sc.meas[i].time + 4.0;
    let delayed = run(&sc, &arrival, 1);
    let d = rel_diff(reference.filter(), delayed.filter());
    assert!(d < 1e-9, "relative difference {d}");
    assert_eq!(delayed.stats().replays, 1);
    // The replay covers 4 s of IMU steps.
    assert!(
        (399..=401).contains(&delayed.stats().replayed_steps),
        "{:?}",
        delayed.stats()
    );
    // Without the fix the estimate differs: the test is not vacuous.
    let mut meas = sc.meas.clone();
    meas.remove(i);
    let less = Scenario {
        imu: sc.imu.clone(),
        meas,
    };
    let without = run(&less, &on_time(&less), 1);
    assert!(rel_diff(reference.filter(), without.filter()) > 1e-6);
}

#[test]
fn shuffled_arrival_within_the_history_equals_sorted_arrival() {
    let sc = scenario(30, 2);
    let reference = run(&sc, &on_time(&sc), 1);
    let mut g = Gauss::new(99);
    for snapshot_every in [1, 7] {
        // Random delays up to 3 s: arrival order is a random permutation
        // within a sliding 3 s window.
        let arrival: Vec<f64> = sc
            .meas
            .iter()
            .map(|m| m.time + 3.0 * g.normal().abs().min(1.0))
            .collect();
        let late = run(&sc, &arrival, snapshot_every);
        let d = rel_diff(reference.filter(), late.filter());
        assert!(d < 1e-12, "every {snapshot_every}: {d}");
        // Whole 2 s blocks delivered at once, shuffled.
        let mut arrival = vec![0.0; sc.meas.len()];
        let mut blocks: Vec<Vec<usize>> = vec![Vec::new(); 16];
        for (i, m) in sc.meas.iter().enumerate() {
            blocks[(m.time / 2.0) as usize].push(i);
        }
        for (b, block) in blocks.iter_mut().enumerate() {
            for k in (1..block.len()).rev() {
                block.swap(k, g.index(k + 1));
            }
            for (rank, &i) in block.iter().enumerate() {
                // Same arrival time for the block; `run` keeps list order
                // for ties, so give a tiny rank offset instead.
                arrival[i] = (b as f64 + 1.0) * 2.0 + 1e-6 * rank as f64;
            }
        }
        let shuffled = run(&sc, &arrival, snapshot_every);
        assert!(
            rel_diff(reference.filter(), shuffled.filter()) < 1e-12,
            "every {snapshot_every}"
        );
        for k in [Kind::Pos, Kind::PosVel, Kind::PosVelSequential] {
            let ids = [SensorId(0), SensorId(1), SensorId(2)];
            let a = reference.sensor_stats(id_of(&ids, k)).unwrap();
            let b = shuffled.sensor_stats(id_of(&ids, k)).unwrap();
            assert_eq!(
                (a.accepted, a.gated, a.failed),
                (b.accepted, b.gated, b.failed),
                "{k:?}"
            );
        }
    }
    let s = reference.sensor_stats(SensorId(0)).unwrap();
    assert_eq!(s.accepted + s.gated, 30);
}

#[test]
fn a_measurement_inside_an_imu_interval_splits_it() {
    let (mut s, ids) = scheduler(1);
    let u0 = CvbInput { a: 0.2 };
    let u1 = CvbInput { a: -0.4 };
    let z = SVector::<f64, 1>::new(0.9);
    let r = SMatrix::<f64, 1, 1>::new(0.25);
    s.push_imu(0.01, u0).unwrap();
    s.push_update::<Pos, 3, 1>(ids[0], 0.0137, z, r, Offset::default())
        .unwrap();
    let reports = s.push_imu(0.02, u1).unwrap();
    assert_eq!(reports.len(), 1);
    assert!(!reports[0].replay && reports[0].outcome.unwrap().accepted);
    let mut f = filter();
    f.predict(0.01, &u0).unwrap();
    f.predict(0.0137 - 0.01, &u1).unwrap();
    f.update::<Pos, 1>(&z, &r, &Offset::default()).unwrap();
    f.predict(0.02 - 0.0137, &u1).unwrap();
    assert_eq!(s.filter().state(), f.state());
    assert_eq!(s.filter().covariance(), f.covariance());
}

#[test]
fn simultaneous_measurements_apply_in_sensor_order_whatever_the_arrival() {
    let run_with = |pos_first: bool| {
        let (mut s, ids) = scheduler(1);
        s.push_imu(0.01, CvbInput { a: 0.1 }).unwrap();
        let a = Meas {
            kind: Kind::Pos,
            time: 0.015,
            z: [1.0, 0.0],
        };
        let b = Meas {
            kind: Kind::PosVel,
            time: 0.015,
            z: [0.7, 0.2],
        };
        let (first, second) = if pos_first { (a, b) } else { (b, a) };
        s.push_measurement(id_of(&ids, first.kind), first.time, boxed(&first))
            .unwrap();
        s.push_imu(0.02, CvbInput { a: 0.1 }).unwrap();
        // The second arrives late: rollback and replay.
        let reports = s
            .push_measurement(id_of(&ids, second.kind), second.time, boxed(&second))
            .unwrap();
        (bits(&s), reports)
    };
    let (a, ra) = run_with(true);
    let (b, rb) = run_with(false);
    assert_eq!(a, b);
    // Pos (sensor 0) before PosVel (sensor 1): when Pos arrives late the
    // PosVel update after it is re-applied and reported as a replay.
    assert_eq!(ra.len(), 1);
    assert_eq!(rb.len(), 2);
    assert!(!rb[0].replay && rb[1].replay);
}

#[test]
fn refused_events_leave_the_filter_bit_identical_and_are_counted() {
    let sc = scenario(12, 3);
    let mut s = run(&sc, &on_time(&sc), 1);
    let ids = [SensorId(0), SensorId(1), SensorId(2)];
    let now = s.now();
    // A pending measurement, to check that duplicates of queued ones are refused too.
    s.push_update::<Pos, 3, 1>(
        ids[0],
        now + 0.5,
        SVector::<f64, 1>::new(1.0),
        SMatrix::<f64, 1, 1>::new(1.0),
        Offset::default(),
    )
    .unwrap();
    let before = bits(&s);
    let z = SVector::<f64, 1>::new(1.0);
    let r = SMatrix::<f64, 1, 1>::new(1.0);
    let pos = |z: f64, r: f64, o: f64| -> Box<dyn Measurement<Filter>> {
        Box::new(SensorUpdate::<Pos, 3, 1>::new(
            SVector::<f64, 1>::new(z),
            SMatrix::<f64, 1, 1>::new(r),
            Offset { offset: o },
        ))
    };
    let existing = sc
        .meas
        .iter()
        .rev()
        .find(|m| m.kind == Kind::Pos)
        .unwrap()
        .time;
    let cases: Vec<(&str, Result<Vec<Report>, SchedulerError>)> = vec![
        ("imu backwards", s.push_imu(now - 0.5, CvbInput { a: 0.0 })),
        ("imu duplicate", s.push_imu(now, CvbInput { a: 0.0 })),
        ("imu NaN time", s.push_imu(f64::NAN, CvbInput { a: 0.0 })),
        (
            "imu NaN input",
            s.push_imu(now + DT, CvbInput { a: f64::NAN }),
        ),
        (
            "older than latency",
            s.push_measurement(ids[0], now - 5.5, pos(1.0, 1.0, 0.0)),
        ),
        (
            "older than history",
            s.push_measurement(ids[0], -1.0, pos(1.0, 1.0, 0.0)),
        ),
        (
            "duplicate applied",
            s.push_measurement(ids[0], existing, pos(1.0, 1.0, 0.0)),
        ),
        (
            "duplicate pending",
            s.push_measurement(ids[0], now + 0.5, pos(1.0, 1.0, 0.0)),
        ),
        (
            "NaN z",
            s.push_measurement(ids[0], now - 1.0, pos(f64::NAN, 1.0, 0.0)),
        ),
        (
            "inf R",
            s.push_measurement(ids[0], now - 1.0, pos(1.0, f64::INFINITY, 0.0)),
        ),
        (
            "NaN aux",
            s.push_measurement(ids[0], now - 1.0, pos(1.0, 1.0, f64::NAN)),
        ),
        (
            "NaN time",
            s.push_measurement(ids[0], f64::NAN, pos(1.0, 1.0, 0.0)),
        ),
        (
            "unknown sensor",
            s.push_update::<Pos, 3, 1>(SensorId(9), now - 1.0, z, r, Offset::default()),
        ),
    ];
    for (name, result) in &cases {
        assert!(result.is_err(), "{name} accepted");
        assert_eq!(bits(&s), before, "{name} changed the filter");
    }
    let st = s.sensor_stats(ids[0]).unwrap();
    assert_eq!(
        (st.too_old, st.duplicate, st.invalid, st.pending),
        (2, 2, 4, 1),
        "{st:?}"
    );
    assert_eq!(s.stats().imu_rejected, 4);
    assert!(matches!(
        cases[0].1,
        Err(SchedulerError::TimeWentBackwards { .. })
    ));
    assert!(matches!(cases[5].1, Err(SchedulerError::TooOld { .. })));
    // A measurement the filter itself refuses (singular S) is reported, not an error.
    let (mut s2, ids2) = scheduler(1);
    s2.push_imu(0.01, CvbInput { a: 0.0 }).unwrap();
    let rep = s2
        .push_measurement(ids2[0], 0.005, pos(0.0, 0.0, 0.0))
        .unwrap();
    assert!(rep[0].outcome.is_ok());
}

/// A frozen sensor: its repeats are refused with a typed error once the
/// run reaches the detector's limit, counted, and leave the filter
/// bit-identical; a changed value is taken again. Without a detector the
/// same values are applied.
#[test]
fn stuck_sensor_is_refused_until_its_value_changes() {
    let fix = |z: f64| -> Box<dyn Measurement<Filter>> {
        Box::new(SensorUpdate::<Pos, 3, 1>::new(
            SVector::<f64, 1>::new(z),
            SMatrix::<f64, 1, 1>::new(0.25),
            Offset::default(),
        ))
    };
    let drive = |detect: bool| {
        let (mut s, ids) = scheduler(1);
        if detect {
            s.set_stuck_detector(ids[0], StuckDetector::new(3)).unwrap();
        }
        let mut refused = Vec::new();
        for k in 1..=100 {
            let t = f64::from(k) * DT;
            s.push_imu(t, CvbInput { a: 0.0 }).unwrap();
            if k % 10 == 5 {
                // Fixes 0-2 vary, 3-7 are frozen at 0.7, 8-9 vary again.
                let i = k / 10;
                let z = if (3..=7).contains(&i) {
                    0.7
                } else {
                    0.1 * f64::from(i)
                };
                let before = bits(&s);
                match s.push_measurement(ids[0], t + 0.001, fix(z)) {
                    Err(SchedulerError::Stuck { run, .. }) => {
                        assert_eq!(bits(&s), before, "fix {i} changed the filter");
                        refused.push((i, run));
                    }
                    other => assert!(other.is_ok(), "fix {i}: {other:?}"),
                }
            }
        }
        (s, ids, refused)
    };
    let (mut s, ids, refused) = drive(true);
    // The third identical value and later ones are refused.
    assert_eq!(refused, vec![(5, 3), (6, 4), (7, 5)]);
    let st = s.sensor_stats(ids[0]).unwrap();
    assert_eq!((st.stuck, st.stuck_episodes), (3, 1), "{st:?}");
    assert_eq!(st.accepted + st.gated + st.pending, 7, "{st:?}");
    let (plain, ids, refused) = drive(false);
    assert!(refused.is_empty());
    let st = plain.sensor_stats(ids[0]).unwrap();
    assert_eq!((st.stuck, st.accepted + st.gated + st.pending), (0, 10));
    assert_ne!(bits(&plain), bits(&s));
    assert_eq!(
        s.set_stuck_detector(SensorId(9), StuckDetector::new(3)),
        Err(SchedulerError::UnknownSensor(SensorId(9)))
    );
}

#[test]
fn queue_is_bounded_and_history_is_trimmed() {
    let (s, ids) = scheduler(1);
    let mut s = s.with_max_pending(3);
    for k in 0..3 {
        s.push_update::<Pos, 3, 1>(
            ids[0],
            1.0 + f64::from(k),
            SVector::<f64, 1>::new(0.0),
            SMatrix::<f64, 1, 1>::new(1.0),
            Offset::default(),
        )
        .unwrap();
    }
    let full = s.push_update::<Pos, 3, 1>(
        ids[0],
        9.0,
        SVector::<f64, 1>::new(0.0),
        SMatrix::<f64, 1, 1>::new(1.0),
        Offset::default(),
    );
    assert_eq!(full, Err(SchedulerError::QueueFull { capacity: 3 }));
    for k in 1..=2000 {
        s.push_imu(f64::from(k) * DT, CvbInput { a: 0.0 }).unwrap();
    }
    // 5 s window at 100 Hz, plus the base checkpoint.
    assert!(
        (500..=502).contains(&s.history_len()),
        "{}",
        s.history_len()
    );
    assert!(s.oldest() < s.now() - 5.0);
    let st = s.sensor_stats(ids[0]).unwrap();
    assert_eq!(
        (st.accepted + st.gated, st.pending, st.queue_full),
        (3, 0, 1)
    );
    // Sensor 1 never reported; sensor 0 last at 3 s, 17 s ago (> 2 s + 5 s).
    assert!(s.is_stale(ids[1]) && s.is_stale(ids[0]));
    s.push_update::<Pos, 3, 1>(
        ids[0],
        19.0,
        SVector::<f64, 1>::new(0.0),
        SMatrix::<f64, 1, 1>::new(1.0),
        Offset::default(),
    )
    .unwrap();
    assert!(!s.is_stale(ids[0]));
}

/// An error-state filter driven by raw IMU samples through the scheduler,
/// its residuals formed from the nominal solution at the measurement time:
/// a delayed fix gives the on-time result, and both equal the full-state
/// filter.
#[test]
fn error_state_filter_is_scheduled_with_delayed_residuals() {
    type Esf = ErrorStateFilter<Cvb, Toy, 3>;
    let sc = scenario(15, 5);
    let fixes: Vec<&Meas> = sc.meas.iter().filter(|m| m.kind == Kind::Pos).collect();
    let make = |delay_index: Option<usize>| {
        let ekf = Ekf::<Cvb, 3>::new(V3::zeros(), p0(), (), NOISE).unwrap();
        let mut s = Scheduler::new(
            ErrorStateFilter::new(
                ekf,
                Toy {
                    p: 0.5,
                    v: 0.1,
                    b: 0.0,
                },
            ),
            0.0,
        )
        .unwrap();
        let id = s.add_sensor("pos", 1.0, 5.0).unwrap();
        let mut late = None;
        let mut next = 0;
        for &(t, u) in &sc.imu {
            while let Some(m) = fixes.get(next) {
                if m.time - DT > t {
                    break;
                }
                let z = m.z[0];
                let meas = FnMeasurement::new(&[z], move |f: &mut Esf| {
                    let residual = SVector::<f64, 1>::new(f.nominal().p - z);
                    f.update::<Pos, 1>(
                        &residual,
                        &SMatrix::<f64, 1, 1>::new(0.25),
                        &Offset::default(),
                    )
                    .map(|r| MeasurementOutcome::from(&r))
                });
                if Some(next) == delay_index {
                    late = Some((m.time, meas));
                } else {
                    s.push_measurement(id, m.time, Box::new(meas)).unwrap();
                }
                next += 1;
            }
            s.push_imu(t, u).unwrap();
            if let Some((tm, _)) = &late {
                if t >= tm + 4.0 {
                    let (tm, meas) = late.take().unwrap();
                    s.push_measurement(id, tm, Box::new(meas)).unwrap();
                }
            }
        }
        s
    };
    let timely = make(None);
    let delayed = make(Some(6));
    let (a, b) = (timely.filter().nominal(), delayed.filter().nominal());
    let diff = (a.p - b.p)
        .abs()
        .max((a.v - b.v).abs())
        .max((a.b - b.b).abs());
    assert!(diff < 1e-9 * (1.0 + a.p.abs()), "{a:?} vs {b:?}");
    assert_eq!(delayed.stats().replays, 1);
    // Full-state filter on the same data.
    let only_fixes = Scenario {
        imu: sc.imu.clone(),
        meas: fixes.iter().map(|m| **m).collect(),
    };
    let full = run(&only_fixes, &on_time(&only_fixes), 1);
    let x = full.filter().state();
    let got = V3::new(a.p, a.v, a.b);
    assert!((got - x).amax() < 1e-9 * (1.0 + x.amax()), "{got} vs {x}");
    assert!((timely.filter().covariance() - full.filter().covariance()).amax() < 1e-12);
}

/// `set_latency`: a longer latency keeps history from then on (a delayed
/// measurement within it is applied), a shorter one drops what is older;
/// a bad latency or sensor is refused.
#[test]
fn a_sensor_latency_changed_while_running_sets_the_history() {
    let mut s = Scheduler::new(filter(), 0.0).unwrap();
    let late = s.add_sensor("late", 1.0, 0.0).unwrap();
    let step = |s: &mut Scheduler<Filter>, from: u32, to: u32| {
        for k in from..=to {
            s.push_imu(f64::from(k) * DT, CvbInput { a: 0.0 }).unwrap();
        }
    };
    let fix = |s: &mut Scheduler<Filter>, t: f64| {
        s.push_update::<Pos, 3, 1>(
            late,
            t,
            SVector::<f64, 1>::new(0.0),
            SMatrix::<f64, 1, 1>::new(1.0),
            Offset::default(),
        )
    };
    step(&mut s, 1, 100);
    assert!(s.history_len() <= 2, "{}", s.history_len());
    assert!(fix(&mut s, 0.5).is_err(), "older than a latency of 0");
    s.set_latency(late, 2.0).unwrap();
    step(&mut s, 101, 400);
    assert!(s.oldest() <= s.now() - 2.0 && s.history_len() >= 200);
    let within = s.now() - 1.5;
    assert!(fix(&mut s, within).is_ok(), "within the new latency");
    s.set_latency(late, 0.0).unwrap();
    step(&mut s, 401, 402);
    assert!(s.history_len() <= 3, "{}", s.history_len());
    assert!(matches!(
        s.set_latency(late, f64::NAN),
        Err(SchedulerError::InvalidConfig(_))
    ));
    assert!(matches!(
        s.set_latency(SensorId(7), 1.0),
        Err(SchedulerError::UnknownSensor(_))
    ));
}
