//! What the `ahrs` and `gnss-ins` replays share: per-sensor counts, the
//! magnetic declination taken from the log, the comparison with
//! `reference.csv` (PX4's own estimate) and the scoring against `truth.csv`.

use nav_runtime::ekf::{FilterError, UpdateReport};
use nav_runtime::log::{LogDir, MagRow, ReferenceRow, TruthRow, Warning, WarningKind};
use serde_json::{json, Map, Value};

use super::reference::{EstimatePoint, Reference};
use super::running_score::{REFERENCE_COLUMNS, TRUTH_COLUMNS};
use crate::harness::RunTable;
use nav_ins::SensorHealth;

pub use nav_ins::heading::DECLINATION_WINDOW_S;

/// Counts of one sensor, updated from each update's outcome.
pub fn count<const M: usize>(
    h: &mut SensorHealth,
    result: Result<UpdateReport<M>, FilterError>,
) -> bool {
    match result {
        Ok(r) if r.accepted => {
            h.accepted += 1;
            true
        }
        Ok(_) => {
            h.gated += 1;
            false
        }
        Err(_) => {
            h.rejected += 1;
            false
        }
    }
}

/// [`nav_ins::heading::mean_declination`] of the magnetometer rows `mag`.
pub fn declination(mag: &[MagRow], t0: f64, attitude: [f64; 3]) -> Option<(f64, usize)> {
    nav_ins::heading::mean_declination(mag.iter().map(|m| (m.t, [m.mx, m.my, m.mz])), t0, attitude)
}

/// `reference.csv` of `log` as a [`Reference`]: a group (position,
/// attitude) is compared when every row has it.
pub fn reference(rows: &[ReferenceRow]) -> Reference {
    let position: Option<Vec<[f64; 3]>> = rows.iter().map(ReferenceRow::position).collect();
    let attitude: Option<Vec<[f64; 3]>> = rows.iter().map(ReferenceRow::attitude).collect();
    Reference {
        t: rows.iter().map(|r| r.t).collect(),
        position: position.filter(|p| !p.is_empty()),
        attitude: attitude.filter(|a| !a.is_empty()),
    }
}

/// `a` wrapped to (-pi, pi].
pub fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// The estimate at time `t`, interpolated linearly (angles along the
/// shorter arc) between the points around it; `None` outside their span.
/// `j` is a cursor for calls in increasing `t`.
pub fn at(points: &[EstimatePoint], t: f64, j: &mut usize) -> Option<EstimatePoint> {
    while *j + 1 < points.len() && points[*j + 1].t < t {
        *j += 1;
    }
    let (a, b) = (points.get(*j)?, points.get(*j + 1)?);
    if t < a.t || t > b.t {
        return None;
    }
    let s = if b.t > a.t {
        (t - a.t) / (b.t - a.t)
    } else {
        0.0
    };
    let attitude =
        std::array::from_fn(|k| wrap(a.attitude[k] + s * wrap(b.attitude[k] - a.attitude[k])));
    let position = match (a.position, b.position) {
        (Some(pa), Some(pb)) => Some(std::array::from_fn(|k| pa[k] + s * (pb[k] - pa[k]))),
        _ => None,
    };
    Some(EstimatePoint {
        t,
        attitude,
        position,
    })
}

/// The differences to PX4's estimate at every reference row inside the
/// estimate's span: `t`, estimate and reference roll/pitch/yaw (deg), their
/// wrapped differences (deg) and, with positions, the north and east
/// differences (m).
pub fn difference_table(reference: &Reference, points: &[EstimatePoint]) -> RunTable {
    let mut table = RunTable::new("reference_difference", &REFERENCE_COLUMNS);
    let mut j = 0;
    for (i, &t) in reference.t.iter().enumerate() {
        let Some(e) = at(points, t, &mut j) else {
            continue;
        };
        let mut row = vec![t];
        row.extend(e.attitude.map(f64::to_degrees));
        let r = reference.attitude.as_ref().map(|a| a[i]);
        row.extend(r.map_or([f64::NAN; 3], |r| r.map(f64::to_degrees)));
        row.extend(r.map_or([f64::NAN; 3], |r| {
            std::array::from_fn::<f64, 3, _>(|k| wrap(e.attitude[k] - r[k]).to_degrees())
        }));
        let ne = match (e.position, reference.position.as_ref().map(|p| p[i])) {
            (Some(p), Some(rp)) => {
                let d = nav_runtime::earth::geodetic_error_to_ned(
                    rp[0],
                    rp[2],
                    p[0] - rp[0],
                    p[1] - rp[1],
                    0.0,
                );
                [d.x, d.y]
            }
            _ => [f64::NAN; 2],
        };
        row.extend(ne);
        table.push(&row);
    }
    table
}

/// Attitude errors against `truth.csv` (RMS of the wrapped roll, pitch and
/// yaw errors, deg) at every truth row inside the estimate's span, with the
/// table `attitude_errors` (`t`, error roll/pitch/yaw in deg) and the
/// seconds scored. `None` when no row is inside.
pub fn attitude_errors(
    truth: &[TruthRow],
    points: &[EstimatePoint],
) -> Option<([f64; 3], f64, RunTable)> {
    let mut table = RunTable::new("attitude_errors", &TRUTH_COLUMNS);
    let mut sum = [0.0; 3];
    let mut j = 0;
    let (mut first, mut last, mut n) = (None, 0.0, 0usize);
    for r in truth {
        let Some(e) = at(points, r.t, &mut j) else {
            continue;
        };
        let err = [
            wrap(e.attitude[0] - r.roll),
            wrap(e.attitude[1] - r.pitch),
            wrap(e.attitude[2] - r.yaw),
        ];
        for k in 0..3 {
            sum[k] += err[k] * err[k];
        }
        first.get_or_insert(r.t);
        last = r.t;
        n += 1;
        table.push(&[
            r.t,
            err[0].to_degrees(),
            err[1].to_degrees(),
            err[2].to_degrees(),
        ]);
    }
    let first = first?;
    Some((
        sum.map(|s| (s / n as f64).sqrt().to_degrees()),
        last - first,
        table,
    ))
}

/// `{"roll","pitch","yaw"}`.
pub fn rpy_json(v: [f64; 3]) -> Value {
    json!({"roll": v[0], "pitch": v[1], "yaw": v[2]})
}

/// The reference keys of the replay JSON (`attitude_difference_rms_deg`,
/// `horizontal_difference_rms_m` when both sides have positions,
/// `reference_samples`, `reference_scored_seconds`) and the difference
/// table; nothing without `reference.csv`. The replays score as their
/// estimates come ([`super::running_score`]); this is the form over a whole
/// series in memory that they are checked against.
pub fn reference_metrics(
    log: &LogDir,
    points: &[EstimatePoint],
    metrics: &mut Map<String, Value>,
    warnings: &mut Vec<Warning>,
) -> Option<RunTable> {
    let rows = log.reference.as_deref()?;
    let reference = reference(rows);
    let d = reference.difference(points);
    if let Value::Object(m) = d.json() {
        metrics.extend(m);
    }
    if reference.attitude.is_none() {
        warnings.push(Warning::about(
            WarningKind::Model,
            "reference.csv",
            "reference.csv has no attitude: no attitude difference",
        ));
    }
    if reference.position.is_none() && points.iter().any(|p| p.position.is_some()) {
        warnings.push(Warning::about(
            WarningKind::Model,
            "reference.csv",
            "reference.csv has no position (the log has no vehicle_global_position): \
             no horizontal difference",
        ));
    }
    Some(difference_table(&reference, points))
}
