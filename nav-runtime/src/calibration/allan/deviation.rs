//! The overlapping Allan deviation of one evenly sampled series, and the grid
//! of cluster sizes it is evaluated on (docs/allan.md, "Method").

/// Cluster sizes per decade of the grid: log-spaced, denser than octaves, so
/// that slopes are read from several points.
const PER_DECADE: f64 = 10.0;

/// Fewest non-overlapping clusters a point of the curve is computed from:
/// with 3 the relative confidence is 1 / sqrt(2 (3 - 1)) = 50 %.
pub const MIN_CLUSTERS: usize = 3;

/// One point of an Allan deviation curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AllanPoint {
    /// Cluster time `tau = m * period`, s.
    pub tau_s: f64,
    /// Cluster size `m`, samples.
    pub cluster_size: usize,
    /// Overlapping Allan deviation at `tau`, in the unit of the samples
    /// (rad/s for a gyro, m/s^2 for an accelerometer).
    pub deviation: f64,
    /// Number of non-overlapping clusters of `m` samples in the record,
    /// `K = floor(n / m)`.
    pub clusters: usize,
    /// Number of overlapping second differences summed, `n - 2m + 1`.
    pub terms: usize,
    /// 1-sigma relative confidence of `deviation`, `1 / sqrt(2 (K - 1))`
    /// (the usual approximation for the Allan deviation of `K`
    /// independent clusters; IEEE Std 952-1997, annex C). The error bar
    /// is `deviation * (1 +- relative_error)`.
    pub relative_error: f64,
}

/// Log-spaced cluster sizes `m` (ten per decade, rounded, distinct) from 1
/// while the record holds at least [`MIN_CLUSTERS`] clusters of `m`
/// samples.
pub fn cluster_sizes(samples: usize) -> Vec<usize> {
    let mut sizes: Vec<usize> = Vec::new();
    let mut k = 0u32;
    loop {
        let m = 10f64.powf(f64::from(k) / PER_DECADE).round() as usize;
        k += 1;
        if m == 0 || samples / m < MIN_CLUSTERS {
            break;
        }
        if sizes.last() != Some(&m) {
            sizes.push(m);
        }
    }
    sizes
}

/// The phase of a rate series: `x_0 = 0`, `x_k = period * sum_{i<k} (y_i -
/// mean)` (the mean removed first, which leaves the deviation unchanged and
/// keeps the second differences of a gyro with a large bias, or of an
/// accelerometer under gravity, free of cancellation).
pub fn phase(values: &[f64], period_s: f64) -> Vec<f64> {
    let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
    let mut x = Vec::with_capacity(values.len() + 1);
    x.push(0.0);
    let mut sum = 0.0;
    for v in values {
        sum += v - mean;
        x.push(sum * period_s);
    }
    x
}

/// The overlapping Allan deviation of the rate series whose [`phase`] is
/// `x`, at cluster size `m`:
/// `sigma^2 = sum_{i=0}^{n-2m} (x_{i+2m} - 2 x_{i+m} + x_i)^2 / (2 (n - 2m + 1) m^2 period^2)`
/// with `n = x.len() - 1` rate samples (IEEE Std 1139; the estimator of
/// the `allantools` package's `oadev`). `None` if `m` is zero or the record
/// is shorter than `2m` samples.
pub fn overlapping(x: &[f64], period_s: f64, m: usize) -> Option<AllanPoint> {
    let n = x.len().checked_sub(1)?;
    if m == 0 || n < 2 * m {
        return None;
    }
    let terms = n - 2 * m + 1;
    let sum: f64 = x
        .iter()
        .zip(&x[m..])
        .zip(&x[2 * m..])
        .map(|((a, b), c)| {
            let d = c - 2.0 * b + a;
            d * d
        })
        .sum();
    let tau = m as f64 * period_s;
    let clusters = n / m;
    Some(AllanPoint {
        tau_s: tau,
        cluster_size: m,
        deviation: (sum / (2.0 * terms as f64)).sqrt() / tau,
        clusters,
        terms,
        relative_error: 1.0 / (2.0 * (clusters.max(2) - 1) as f64).sqrt(),
    })
}

/// The curve of a rate series over [`cluster_sizes`].
pub fn curve(values: &[f64], period_s: f64) -> Vec<AllanPoint> {
    let x = phase(values, period_s);
    cluster_sizes(values.len())
        .into_iter()
        .filter_map(|m| overlapping(&x, period_s, m))
        .collect()
}
