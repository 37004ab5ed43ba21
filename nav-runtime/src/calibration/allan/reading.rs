//! Noise coefficients read from the slopes of an Allan deviation curve
//! (docs/allan.md, "Reading the curve"): white noise on the slope -1/2
//! read at 1 s, bias instability at the flat bottom divided by 0.664, rate
//! random walk on the slope +1/2 read at 3 s.

use super::deviation::AllanPoint;

/// `sqrt(2 ln 2 / pi)`: the Allan deviation of flicker (1/f) rate noise of
/// coefficient `B` is flat at `0.664 B` (IEEE Std 952-1997, annex C).
pub const FLICKER_FLOOR: f64 = 0.664;

/// A local slope within this of the nominal one counts as that noise
/// term. Wider than the slope's own scatter at the long cluster times of
/// a record of an hour or more (about 0.1 over two octaves), narrow enough
/// to keep the slopes -1/2, 0 and +1/2 apart.
pub const SLOPE_TOLERANCE: f64 = 0.2;

/// A region of one slope must span at least this ratio of cluster times
/// (two octaves) before a coefficient is read from it.
pub const MIN_SPAN: f64 = 4.0;

/// A coefficient read from the curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coefficient {
    /// The value, in the unit given by the report (see [`super::SensorKind::units`]).
    pub value: f64,
    /// 1-sigma relative confidence: that of the point of the region nearest
    /// the cluster time the coefficient is read at (1 s, 3 s, the bottom).
    /// The points of an overlapping curve share their data, so the fit is
    /// credited no better than the curve where it is read; crediting it with
    /// its best point (the shortest cluster time) proved optimistic: a white
    /// noise read 0.42 % high where the shortest point claimed 0.12 %.
    pub relative_error: f64,
    /// Cluster times of the region read, s (first, last).
    pub tau_range_s: (f64, f64),
    /// Points of the curve in the region.
    pub points: usize,
}

/// What the curve says of one noise term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reading {
    /// Read from a region of the expected slope.
    Found(Coefficient),
    /// The curve has no region of the expected slope: the record is too
    /// short for it, or another term dominates there (the reason says which).
    NotReached(&'static str),
}

impl Reading {
    /// The value, if found.
    pub fn value(&self) -> Option<f64> {
        match self {
            Reading::Found(c) => Some(c.value),
            Reading::NotReached(_) => None,
        }
    }
}

/// The local log-log slope at each point: the least-squares slope of
/// `ln sigma` against `ln tau` over the points within a factor 2 of its
/// cluster time (two octaves; one-sided at the ends).
pub fn local_slopes(curve: &[AllanPoint]) -> Vec<f64> {
    curve
        .iter()
        .map(|p| {
            let (lo, hi) = (p.tau_s / 2.0, p.tau_s * 2.0);
            let (mut n, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for q in curve.iter().filter(|q| q.tau_s >= lo && q.tau_s <= hi) {
                let (x, y) = (q.tau_s.ln(), q.deviation.max(f64::MIN_POSITIVE).ln());
                n += 1.0;
                sx += x;
                sy += y;
                sxx += x * x;
                sxy += x * y;
            }
            let den = n * sxx - sx * sx;
            if n < 2.0 || den <= 0.0 {
                f64::NAN
            } else {
                (n * sxy - sx * sy) / den
            }
        })
        .collect()
}

/// The longest run of consecutive points whose local slope is within
/// [`SLOPE_TOLERANCE`] of `slope`, as an index range; `None` if no run
/// spans [`MIN_SPAN`].
fn region(curve: &[AllanPoint], slopes: &[f64], slope: f64) -> Option<(usize, usize)> {
    let mut best: Option<(usize, usize)> = None;
    let mut start = None;
    for i in 0..=curve.len() {
        let inside = slopes
            .get(i)
            .is_some_and(|s| (s - slope).abs() <= SLOPE_TOLERANCE);
        match (inside, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                let span = curve[i - 1].tau_s / curve[s].tau_s;
                let better = best.is_none_or(|(a, b)| span > curve[b].tau_s / curve[a].tau_s);
                if span >= MIN_SPAN && better {
                    best = Some((s, i - 1));
                }
                start = None;
            }
            _ => {}
        }
    }
    best
}

/// A line of fixed log-log `slope` through the region `[a, b]`, weighted by
/// each point's confidence, evaluated at `tau_read`.
fn read_line(
    curve: &[AllanPoint],
    (a, b): (usize, usize),
    slope: f64,
    tau_read: f64,
) -> Coefficient {
    let (mut sw, mut swy) = (0.0, 0.0);
    for p in &curve[a..=b] {
        let w = 1.0 / (p.relative_error * p.relative_error);
        sw += w;
        swy += w * (p.deviation.ln() - slope * p.tau_s.ln());
    }
    let intercept = swy / sw;
    Coefficient {
        value: (intercept + slope * tau_read.ln()).exp(),
        relative_error: curve[a..=b]
            .iter()
            .min_by(|p, q| {
                let d = |t: f64| (t / tau_read).ln().abs();
                d(p.tau_s).total_cmp(&d(q.tau_s))
            })
            .map_or(f64::INFINITY, |p| p.relative_error),
        tau_range_s: (curve[a].tau_s, curve[b].tau_s),
        points: b - a + 1,
    }
}

/// White noise of the rate (angle or velocity random walk): the slope
/// -1/2 line read at `tau = 1 s`, in unit/sqrt(s) (= unit/sqrt(Hz)).
pub fn white(curve: &[AllanPoint], slopes: &[f64]) -> Reading {
    match region(curve, slopes, -0.5) {
        Some(r) => Reading::Found(read_line(curve, r, -0.5, 1.0)),
        None => Reading::NotReached("no stretch of slope -1/2 over two octaves"),
    }
}

/// Rate random walk: the slope +1/2 line read at `tau = 3 s`, in
/// unit/s^(1/2) per second (rad/s^(3/2) for a gyro, m/s^(5/2) for an
/// accelerometer): the white noise of the rate's derivative.
pub fn random_walk(curve: &[AllanPoint], slopes: &[f64]) -> Reading {
    match region(curve, slopes, 0.5) {
        Some(r) => Reading::Found(read_line(curve, r, 0.5, 3.0)),
        None => Reading::NotReached(
            "no stretch of slope +1/2 over two octaves (record too short for the rate random walk)",
        ),
    }
}

/// Bias instability: the bottom of a flat stretch (local slope within
/// [`SLOPE_TOLERANCE`] of 0 over at least [`MIN_SPAN`]) divided by
/// [`FLICKER_FLOOR`]. Without such a stretch (a curve still falling at the
/// end of the record, or white noise handing over to the rate random walk
/// with no flat part between) it is not reached.
pub fn bias_instability(curve: &[AllanPoint], slopes: &[f64]) -> Reading {
    let Some((a, b)) = region(curve, slopes, 0.0) else {
        return Reading::NotReached(
            "no flat stretch over two octaves (record too short for the flat part, or none between the slopes)",
        );
    };
    let Some(bottom) = curve[a..=b]
        .iter()
        .min_by(|p, q| p.deviation.total_cmp(&q.deviation))
    else {
        return Reading::NotReached("empty curve");
    };
    Reading::Found(Coefficient {
        value: bottom.deviation / FLICKER_FLOOR,
        relative_error: bottom.relative_error,
        tau_range_s: (curve[a].tau_s, curve[b].tau_s),
        points: b - a + 1,
    })
}

/// A stretch of slope +1 over two octaves: a rate ramp (temperature drift,
/// slow motion), as `(mean local slope, first cluster time s)`.
pub fn ramp(curve: &[AllanPoint], slopes: &[f64]) -> Option<(f64, f64)> {
    let (a, b) = region(curve, slopes, 1.0)?;
    let mean = slopes[a..=b].iter().sum::<f64>() / (b - a + 1) as f64;
    Some((mean, curve[a].tau_s))
}
