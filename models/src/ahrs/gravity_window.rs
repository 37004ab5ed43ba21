//! The gravity measurement's window: the specific force averaged over
//! [`GRAVITY_PERIOD_S`] of IMU samples, so that vibration and short
//! accelerations average out before the accelerometer is read as gravity.

use nav_runtime::nalgebra::Vector3;

/// Interval of the gravity measurement (mean specific force), s.
pub const GRAVITY_PERIOD_S: f64 = 0.1;

/// The running sum of one window.
#[derive(Debug, Clone, Copy)]
pub struct GravityWindow {
    start: f64,
    sum: Vector3<f64>,
    samples: usize,
}

/// A closed window: its mean specific force and the samples averaged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeanForce {
    /// Mean specific force (body), m/s^2.
    pub force: Vector3<f64>,
    /// Samples averaged.
    pub samples: usize,
}

impl GravityWindow {
    /// An empty window starting at `t`.
    pub fn starting_at(t: f64) -> Self {
        GravityWindow {
            start: t,
            sum: Vector3::zeros(),
            samples: 0,
        }
    }

    /// Adds the sample that ends its interval at `t`; once the window spans
    /// [`GRAVITY_PERIOD_S`], returns its mean and starts the next one at `t`.
    pub fn add(&mut self, t: f64, accel: Vector3<f64>) -> Option<MeanForce> {
        self.sum += accel;
        self.samples += 1;
        if t - self.start < GRAVITY_PERIOD_S - 1e-9 {
            return None;
        }
        let mean = MeanForce {
            force: self.sum / self.samples as f64,
            samples: self.samples,
        };
        *self = GravityWindow::starting_at(t);
        Some(mean)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_closes_after_its_period_with_the_mean() {
        let mut w = GravityWindow::starting_at(0.0);
        let mut closed = Vec::new();
        for k in 1..=25 {
            let t = k as f64 * 0.01;
            if let Some(m) = w.add(t, Vector3::new(k as f64, 0.0, -9.8)) {
                closed.push((t, m));
            }
        }
        assert_eq!(closed.len(), 2);
        let (t, m) = closed[0];
        assert!((t - 0.1).abs() < 1e-12);
        assert_eq!(m.samples, 10);
        assert!((m.force.x - 5.5).abs() < 1e-12 && (m.force.z + 9.8).abs() < 1e-12);
        assert_eq!(closed[1].1.samples, 10);
    }
}
