//! Health counts of a run, typed and integer: per sensor, and the filter's
//! own (covariance repairs, scheduler replays, IMU gaps); their totals over
//! the runs of a scenario and the JSON `health` object built from them.

use std::ops::AddAssign;

use serde::{Deserialize, Serialize};
use serde_json::{json, Map, Value};

/// Counts of one aiding sensor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SensorHealth {
    /// Rows in the log.
    pub rows: u64,
    /// Applied.
    pub accepted: u64,
    /// Refused by the innovation gate.
    pub gated: u64,
    /// Refused by the filter or the scheduler (error, too old, duplicate, invalid).
    pub rejected: u64,
    /// Not used: no bottom lock, above the DVL range, or before the start.
    pub skipped: u64,
    /// Refused as frozen values (the sensor repeated one value more often than
    /// its noise and resolution explain; [`StuckDetector`](nav_runtime::stuck::StuckDetector)).
    pub stuck: u64,
}

impl AddAssign for SensorHealth {
    fn add_assign(&mut self, o: SensorHealth) {
        self.rows += o.rows;
        self.accepted += o.accepted;
        self.gated += o.gated;
        self.rejected += o.rejected;
        self.skipped += o.skipped;
        self.stuck += o.stuck;
    }
}

impl SensorHealth {
    /// `{"rows", "accepted", "gated", "rejected", "skipped", "stuck"}`.
    pub fn json(&self) -> Value {
        json!({
            "rows": self.rows,
            "accepted": self.accepted,
            "gated": self.gated,
            "rejected": self.rejected,
            "skipped": self.skipped,
            "stuck": self.stuck,
        })
    }
}

/// The health of a run (or the totals over runs): each sensor's counts, in
/// the model's order, and the filter's counts. A count a model does not keep
/// is `None` and left out of the JSON.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunHealth {
    /// `(sensor name, counts)`.
    pub sensors: Vec<(String, SensorHealth)>,
    /// Covariance repairs (symmetrisation, eigenvalue floor) of the filter.
    pub covariance_repairs: u64,
    /// Re-propagations of the scheduler for late measurements.
    pub replays: Option<u64>,
    /// IMU intervals longer than the model's gap limit.
    pub imu_gaps: Option<u64>,
    /// Lock-outs of a sensor released by inflating the covariance (eq. L4
    /// of docs/lockout.md), as the final filter counts them (a late
    /// reading's re-propagation does not count one twice). Each release
    /// moves the states through the correlations the filter holds; many of
    /// them say that its model does not fit the log.
    #[serde(default)]
    pub lockout_releases: Option<u64>,
}

impl RunHealth {
    /// Counts of `sensor`, if the run has it.
    pub fn sensor(&self, sensor: &str) -> Option<&SensorHealth> {
        self.sensors
            .iter()
            .find(|(name, _)| name == sensor)
            .map(|(_, h)| h)
    }

    /// Adds the counts of `other`: its sensors to the same-named ones (a new
    /// one at the end), its filter counts to these.
    pub fn add(&mut self, other: &RunHealth) {
        for (name, h) in &other.sensors {
            match self.sensors.iter_mut().find(|(n, _)| n == name) {
                Some((_, mine)) => *mine += *h,
                None => self.sensors.push((name.clone(), *h)),
            }
        }
        self.covariance_repairs += other.covariance_repairs;
        let add = |a: Option<u64>, b: Option<u64>| match (a, b) {
            (None, None) => None,
            (a, b) => Some(a.unwrap_or(0) + b.unwrap_or(0)),
        };
        self.replays = add(self.replays, other.replays);
        self.imu_gaps = add(self.imu_gaps, other.imu_gaps);
        self.lockout_releases = add(self.lockout_releases, other.lockout_releases);
    }

    /// The totals over `runs`.
    pub fn total<'a>(runs: impl IntoIterator<Item = &'a RunHealth>) -> RunHealth {
        let mut sum = RunHealth::default();
        for r in runs {
            sum.add(r);
        }
        sum
    }

    /// The JSON `health` object: one `{"rows", "accepted", ...}` object per
    /// sensor, then `covariance_repairs` and the other counts the model
    /// keeps, all integers.
    pub fn json(&self) -> Value {
        let mut m = Map::new();
        for (name, h) in &self.sensors {
            m.insert(name.clone(), h.json());
        }
        m.insert(
            "covariance_repairs".into(),
            Value::from(self.covariance_repairs),
        );
        if let Some(n) = self.replays {
            m.insert("replays".into(), Value::from(n));
        }
        if let Some(n) = self.imu_gaps {
            m.insert("imu_gaps".into(), Value::from(n));
        }
        if let Some(n) = self.lockout_releases {
            m.insert("lockout_releases".into(), Value::from(n));
        }
        Value::Object(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(k: u64) -> SensorHealth {
        SensorHealth {
            rows: 10 * k,
            accepted: 8 * k,
            gated: k,
            rejected: k,
            skipped: 0,
            stuck: 0,
        }
    }

    /// Totals add sensors by name (a sensor of one run only is kept) and
    /// the filter's counts; a count no run keeps stays out of the JSON.
    #[test]
    fn totals_add_by_sensor_name_and_stay_integers() {
        let a = RunHealth {
            sensors: vec![("depth".into(), counts(1)), ("dvl".into(), counts(2))],
            covariance_repairs: 1,
            replays: Some(3),
            imu_gaps: None,
            lockout_releases: Some(2),
        };
        let b = RunHealth {
            sensors: vec![("dvl".into(), counts(1)), ("usbl".into(), counts(5))],
            covariance_repairs: 0,
            replays: Some(1),
            imu_gaps: None,
            lockout_releases: None,
        };
        let t = RunHealth::total([&a, &b]);
        let names: Vec<&str> = t.sensors.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["depth", "dvl", "usbl"]);
        assert_eq!(*t.sensor("dvl").unwrap(), counts(3));
        assert_eq!(t.covariance_repairs, 1);
        assert_eq!(t.replays, Some(4));
        let v = t.json();
        assert_eq!(v["dvl"]["accepted"], json!(24));
        assert!(v["dvl"]["accepted"].is_u64());
        assert_eq!(v["replays"], json!(4));
        assert_eq!(v["lockout_releases"], json!(2));
        assert!(v.get("imu_gaps").is_none());
        assert_eq!(
            RunHealth::total([]).json(),
            json!({"covariance_repairs": 0})
        );
    }
}
