//! The DVL's body axes against the depth meter: the depth rate is the down
//! component of the DVL velocity rotated by the vehicle's roll and pitch
//! (from the accelerometers' mean), each averaged over a few seconds. When the lateral and
//! vertical components carry the motion, FLU axes (y and z negated) give
//! them the sign opposite to the depth rate.

use nav_runtime::log::{BodyFrame, DvlRow, ImuRow, LogDir, LogMapping, Row, Warning, WarningKind};

use super::{declared, Report};

/// Half-width of the window the depth rate is taken over, s.
const RATE_HALF_WINDOW: f64 = 2.0;

/// Fewest DVL rows compared.
const MIN_ROWS: usize = 20;

/// Standard errors a negative slope must lie below zero.
const SIGMAS: f64 = 5.0;

/// Mean square of the y and z part of the predicted depth rate below which
/// they carry no motion to judge, (m/s)^2.
const MIN_PART: f64 = 0.05 * 0.05;

/// Depth at `t` by linear interpolation of `rows`, if `t` is inside them.
fn depth_at(rows: &[nav_runtime::log::DepthRow], t: f64) -> Option<f64> {
    let i = rows.partition_point(|r| r.t < t);
    if i == 0 || i >= rows.len() {
        return None;
    }
    let (a, b) = (&rows[i - 1], &rows[i]);
    let s = (t - a.t) / (b.t - a.t);
    Some(a.depth + s * (b.depth - a.depth))
}

/// Roll and pitch from the mean specific force over `t +- RATE_HALF_WINDOW`.
fn tilt(imu: &[ImuRow], t: f64) -> Option<(f64, f64)> {
    let a = imu.partition_point(|r| r.t < t - RATE_HALF_WINDOW);
    let b = imu.partition_point(|r| r.t <= t + RATE_HALF_WINDOW);
    if b <= a {
        return None;
    }
    let mut f = [0.0; 3];
    for r in &imu[a..b] {
        f[0] += r.ax;
        f[1] += r.ay;
        f[2] += r.az;
    }
    let pitch = f[0].atan2((f[1] * f[1] + f[2] * f[2]).sqrt());
    let roll = (-f[1]).atan2(-f[2]);
    Some((roll, pitch))
}

/// Over the head of the log, for each DVL row: the depth rate over
/// `t +- RATE_HALF_WINDOW` less the part of the mean DVL velocity (same
/// window) that `vx` gives at the mean roll and pitch, regressed on the part
/// `vy` and `vz` give. FRD axes give a slope near +1, FLU axes near -1; a
/// negative slope beyond [`SIGMAS`] standard errors is an error naming `[files.dvl] body_frame`
/// (declared FRD, or not declared: the format is FRD), or the declared FLU
/// of values that were FRD.
pub(super) fn check(log: &LogDir, mapping: &LogMapping, report: &mut Report) {
    let (Some(dvl), Some(depth)) = (&log.dvl, &log.depth) else {
        return;
    };
    let mut pairs: Vec<(f64, f64)> = Vec::new();
    for r in dvl {
        if r.velocity().is_none() {
            continue;
        }
        let (Some(before), Some(after)) = (
            depth_at(depth, r.t - RATE_HALF_WINDOW),
            depth_at(depth, r.t + RATE_HALF_WINDOW),
        ) else {
            continue;
        };
        let Some((roll, pitch)) = tilt(&log.imu, r.t) else {
            continue;
        };
        let a = dvl.partition_point(|d| d.t < r.t - RATE_HALF_WINDOW);
        let b = dvl.partition_point(|d| d.t <= r.t + RATE_HALF_WINDOW);
        let (mut v, mut m) = ([0.0; 3], 0.0);
        for d in dvl[a..b].iter().filter_map(DvlRow::velocity) {
            for k in 0..3 {
                v[k] += d[k];
            }
            m += 1.0;
        }
        let v = v.map(|x| x / m);
        let rate = (after - before) / (2.0 * RATE_HALF_WINDOW);
        let forward = -pitch.sin() * v[0];
        let part = roll.sin() * pitch.cos() * v[1] + roll.cos() * pitch.cos() * v[2];
        pairs.push((rate - forward, part));
    }
    let n = pairs.len();
    let parts: f64 = pairs.iter().map(|(_, p)| p * p).sum();
    if n < MIN_ROWS || parts / (n as f64) < MIN_PART {
        return;
    }
    let slope = pairs.iter().map(|(r, p)| r * p).sum::<f64>() / parts;
    let residual: f64 = pairs.iter().map(|(r, p)| (r - slope * p).powi(2)).sum();
    let standard_error = (residual / (n as f64 - 1.0)).sqrt() / parts.sqrt();
    if slope >= 0.0 || -slope < SIGMAS * standard_error {
        return;
    }
    let (frame, declared) = declared::body_frame(mapping, "dvl");
    let key = "files.dvl.body_frame";
    let cause = match (frame, declared) {
        (BodyFrame::Flu, _) => format!("{key} = \"FLU\" declared for FRD values?"),
        (BodyFrame::Frd, true) => {
            format!("FLU axes (y left, z up)? {key} declares FRD (the default)")
        }
        (BodyFrame::Frd, false) => format!(
            "FLU axes (y left, z up)? the format is FRD (x forward, y right, z down); declare \
             {key} = \"FLU\""
        ),
    };
    report.error(
        Warning::about(
            WarningKind::Suspicious,
            DvlRow::FILE,
            format!(
                "the depth rate of depth.csv follows the down velocity of vy, vz with slope \
                 {slope:.2} (standard error {standard_error:.2}) over {n} rows, where FRD axes \
                 give +1: {cause}"
            ),
        )
        .with_key("vy,vz"),
    );
}
