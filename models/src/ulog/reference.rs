//! Scoring a replay of an imported PX4 log against PX4's own estimate
//! (`reference.csv`): `attitude_difference_rms_deg` (`{"roll","pitch","yaw"}`)
//! and `horizontal_difference_rms_m`, over the reference rows inside the
//! estimate's time span (`scored_seconds`). These are differences to another
//! filter, not errors: PX4's EKF2 is not the truth.

use std::path::Path;

use nav_runtime::earth::{meridian_radius, transverse_radius};

use nav_runtime::log::{CsvProblem, LogError};

/// The header of `reference.csv` as the import writes it: `t` and, when
/// present, the position and attitude groups are read.
const HEADER: &str = "t,lat,lon,height,vn,ve,vd,roll,pitch,yaw";

/// `reference.csv` as read back: times and the columns the file has.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Reference {
    /// Time, s.
    pub t: Vec<f64>,
    /// Latitude, longitude (rad) and height (m), when the file has them.
    pub position: Option<Vec<[f64; 3]>>,
    /// Roll, pitch, yaw (rad), when the file has them.
    pub attitude: Option<Vec<[f64; 3]>>,
}

/// One estimate sample of a replay.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EstimatePoint {
    /// Time, s.
    pub t: f64,
    /// Roll, pitch, yaw, rad.
    pub attitude: [f64; 3],
    /// Latitude, longitude (rad), height (m), for models that estimate them.
    pub position: Option<[f64; 3]>,
}

/// RMS differences of a replay to the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceDifference {
    /// Roll, pitch, yaw RMS difference, degrees (angles wrapped to +-180).
    pub attitude_rms_deg: Option<[f64; 3]>,
    /// Horizontal position RMS difference, m.
    pub horizontal_rms_m: Option<f64>,
    /// Reference rows compared.
    pub samples: usize,
    /// Time between the first and the last row compared, s.
    pub scored_seconds: f64,
}

impl ReferenceDifference {
    /// The JSON keys `attitude_difference_rms_deg`, `horizontal_difference_rms_m`
    /// (when known), `reference_samples` and `reference_scored_seconds`.
    pub fn json(&self) -> serde_json::Value {
        let mut v = serde_json::json!({
            "reference_samples": self.samples,
            "reference_scored_seconds": self.scored_seconds,
        });
        if let Some([r, p, y]) = self.attitude_rms_deg {
            v["attitude_difference_rms_deg"] = serde_json::json!({"roll": r, "pitch": p, "yaw": y});
        }
        if let Some(h) = self.horizontal_rms_m {
            v["horizontal_difference_rms_m"] = serde_json::json!(h);
        }
        v
    }
}

impl Reference {
    /// Reads `reference.csv`; `Ok(None)` when the file does not exist.
    ///
    /// # Errors
    /// [`LogError::Io`], or [`LogError::Csv`] naming the line and column.
    pub fn read(path: &Path) -> Result<Option<Reference>, LogError> {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => {
                return Err(LogError::Io {
                    path: path.to_path_buf(),
                    source,
                })
            }
        };
        Reference::parse(&path.display().to_string(), &text).map(Some)
    }

    /// Parses the text of a `reference.csv` named `file`.
    ///
    /// # Errors
    /// [`LogError::EmptyFile`], or [`LogError::Csv`] naming the line and
    /// column.
    pub fn parse(file: &str, text: &str) -> Result<Reference, LogError> {
        let bad = |line: usize, column: &str, problem: CsvProblem| LogError::Csv {
            file: file.to_string(),
            line: line as u64,
            column: column.to_string(),
            problem,
        };
        let mut lines = text.lines().enumerate();
        let Some((_, header)) = lines.next() else {
            return Err(LogError::EmptyFile {
                file: file.to_string(),
                expected: HEADER.into(),
            });
        };
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        let col = |n: &str| names.iter().position(|c| *c == n);
        let t_col = col("t").ok_or_else(|| {
            let problem = CsvProblem::WrongHeader {
                expected: HEADER.into(),
                found: names.first().unwrap_or(&"").to_string(),
            };
            bad(1, "t", problem)
        })?;
        let pos_cols = [col("lat"), col("lon"), col("height")];
        let att_cols = [col("roll"), col("pitch"), col("yaw")];
        let all = |c: &[Option<usize>; 3]| match c {
            [Some(a), Some(b), Some(d)] => Some([*a, *b, *d]),
            _ => None,
        };
        let (pos_cols, att_cols) = (all(&pos_cols), all(&att_cols));
        let mut r = Reference {
            position: pos_cols.map(|_| Vec::new()),
            attitude: att_cols.map(|_| Vec::new()),
            ..Reference::default()
        };
        for (i, line) in lines {
            let line_no = i + 1;
            if line.trim().is_empty() {
                continue;
            }
            let cells: Vec<&str> = line.split(',').collect();
            let value = |c: usize| -> Result<f64, LogError> {
                let cell = cells.get(c).map(|s| s.trim()).unwrap_or("");
                let text = cell.to_string();
                match cell.parse::<f64>() {
                    Ok(v) if v.is_finite() => Ok(v),
                    Ok(_) => Err(bad(line_no, names[c], CsvProblem::NonFinite { text })),
                    Err(_) if cell.is_empty() => Err(bad(line_no, names[c], CsvProblem::EmptyCell)),
                    Err(_) => Err(bad(line_no, names[c], CsvProblem::NotANumber { text })),
                }
            };
            let t = value(t_col)?;
            match r.t.last() {
                Some(&previous) if t < previous => {
                    let problem = CsvProblem::TimeBackwards { previous, t };
                    return Err(bad(line_no, "t", problem));
                }
                Some(&previous) if t == previous => {
                    return Err(bad(line_no, "t", CsvProblem::DuplicateTime { t }));
                }
                _ => {}
            }
            r.t.push(t);
            // A group whose cells are all empty is one the file does not have
            // (the importer's fixed schema): it is not compared.
            let empty = |c: &[usize; 3]| {
                c.iter()
                    .all(|&i| cells.get(i).is_some_and(|s| s.trim().is_empty()))
            };
            match pos_cols {
                Some(c) if empty(&c) => r.position = None,
                Some(c) => {
                    let p = [value(c[0])?, value(c[1])?, value(c[2])?];
                    if let Some(v) = r.position.as_mut() {
                        v.push(p);
                    }
                }
                None => {}
            }
            match att_cols {
                Some(c) if empty(&c) => r.attitude = None,
                Some(c) => {
                    let a = [value(c[0])?, value(c[1])?, value(c[2])?];
                    if let Some(v) = r.attitude.as_mut() {
                        v.push(a);
                    }
                }
                None => {}
            }
        }
        Ok(r)
    }

    /// RMS differences of `estimate` (in time order) to the reference rows
    /// inside its span; the estimate is interpolated linearly to each
    /// reference time (angles along the shorter arc).
    pub fn difference(&self, estimate: &[EstimatePoint]) -> ReferenceDifference {
        let mut att = [0.0f64; 3];
        let mut horizontal = 0.0;
        let mut n_att = 0usize;
        let mut n_pos = 0usize;
        let mut first = None;
        let mut last = 0.0;
        let mut j = 0usize;
        for (i, &t) in self.t.iter().enumerate() {
            while j + 1 < estimate.len() && estimate[j + 1].t < t {
                j += 1;
            }
            let (Some(a), Some(b)) = (estimate.get(j), estimate.get(j + 1)) else {
                continue;
            };
            if t < a.t || t > b.t {
                continue;
            }
            let s = if b.t > a.t {
                (t - a.t) / (b.t - a.t)
            } else {
                0.0
            };
            first.get_or_insert(t);
            last = t;
            if let Some(reference) = &self.attitude {
                for k in 0..3 {
                    let e = a.attitude[k] + s * wrap(b.attitude[k] - a.attitude[k]);
                    att[k] += wrap(e - reference[i][k]).powi(2);
                }
                n_att += 1;
            }
            if let (Some(reference), Some(pa), Some(pb)) = (&self.position, a.position, b.position)
            {
                let lat = pa[0] + s * (pb[0] - pa[0]);
                let lon = pa[1] + s * (pb[1] - pa[1]);
                let [rlat, rlon, rh] = reference[i];
                let north = (lat - rlat) * (meridian_radius(rlat) + rh);
                let east = (lon - rlon) * (transverse_radius(rlat) + rh) * rlat.cos();
                horizontal += north * north + east * east;
                n_pos += 1;
            }
        }
        let rms = |sum: f64, n: usize| (sum / n as f64).sqrt();
        ReferenceDifference {
            attitude_rms_deg: (n_att > 0).then(|| att.map(|s| rms(s, n_att).to_degrees())),
            horizontal_rms_m: (n_pos > 0).then(|| rms(horizontal, n_pos)),
            samples: n_att.max(n_pos),
            scored_seconds: first.map_or(0.0, |f| last - f),
        }
    }
}

/// `a` wrapped to (-pi, pi].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// Writes `dir/truth.csv` from `dir/reference.csv` (PX4's estimate, height
/// turned into depth), so that an imported log is scored with the truth keys
/// against PX4's estimate: how the tests exercise every truth score of a
/// real flight that has no truth.
///
/// # Errors
/// A file cannot be read or written, or a reference row has no number for
/// its height (naming the line).
pub fn write_reference_as_truth(dir: &Path) -> std::io::Result<()> {
    let reference = std::fs::read_to_string(dir.join("reference.csv"))?;
    let mut truth = String::from("t,lat,lon,depth,vn,ve,vd,roll,pitch,yaw\n");
    for (i, line) in reference.lines().enumerate().skip(1) {
        let c: Vec<&str> = line.split(',').collect();
        let height = c.get(3).and_then(|h| h.parse::<f64>().ok());
        let (Some(height), true) = (height, c.len() == 10) else {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!(
                    "reference.csv line {}: expected 10 columns with a height",
                    i + 1
                ),
            ));
        };
        let depth = -height;
        truth.push_str(&format!(
            "{},{},{},{depth},{}\n",
            c[0],
            c[1],
            c[2],
            c[4..].join(",")
        ));
    }
    std::fs::write(dir.join("truth.csv"), truth)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// PX4's estimate as truth: the height becomes a depth; a reference
    /// without velocities, or with a height that is not a number, is an
    /// error naming its line, not a truth file with columns shifted.
    #[test]
    fn the_reference_is_written_as_truth_or_refused() {
        let header = "t,lat,lon,height,vn,ve,vd,roll,pitch,yaw\n";
        // (reference rows, expected truth rows or the error's words)
        let cases: [(&str, Result<&str, &str>); 3] = [
            (
                "1.5,0.8,0.1,487.5,0.1,0.2,0.3,0.01,0.02,0.03\n",
                Ok("1.5,0.8,0.1,-487.5,0.1,0.2,0.3,0.01,0.02,0.03\n"),
            ),
            ("1.5,0.8,0.1,487.5,0.01,0.02,0.03\n", Err("line 2")),
            (
                "1.5,0.8,0.1,high,0.1,0.2,0.3,0.01,0.02,0.03\n",
                Err("line 2"),
            ),
        ];
        for (k, (rows, expected)) in cases.into_iter().enumerate() {
            let dir = crate::harness::TempDir::new(&format!("reference-as-truth-{k}"));
            std::fs::write(dir.0.join("reference.csv"), format!("{header}{rows}")).unwrap();
            let written = write_reference_as_truth(&dir.0);
            match expected {
                Ok(truth) => {
                    written.expect("written");
                    let text = std::fs::read_to_string(dir.0.join("truth.csv")).unwrap();
                    assert_eq!(
                        text,
                        format!("t,lat,lon,depth,vn,ve,vd,roll,pitch,yaw\n{truth}")
                    );
                }
                Err(words) => {
                    let e = written.expect_err(rows).to_string();
                    assert!(e.contains(words), "{e}");
                    assert!(!dir.0.join("truth.csv").exists());
                }
            }
        }
    }

    const CSV: &str = "t,lat,lon,height,roll,pitch,yaw\n\
        1.0,0.0,0.0,0.0,0.0,0.0,3.1241393610698497\n\
        2.0,0.0,0.0,0.0,0.0,0.0,3.1241393610698497\n\
        3.0,0.0,0.0,0.0,0.0,0.0,3.1241393610698497\n";

    fn point(t: f64, roll_deg: f64, yaw_deg: f64, lat: f64) -> EstimatePoint {
        EstimatePoint {
            t,
            attitude: [roll_deg.to_radians(), 0.0, yaw_deg.to_radians()],
            position: Some([lat, 0.0, 0.0]),
        }
    }

    /// Reference yaw 179 deg, estimate -179 deg: 2 deg apart across the wrap;
    /// roll 1 deg off; latitude 1e-6 rad off at the equator = 1e-6 a (1 - e^2).
    #[test]
    fn differences_by_hand() {
        let r = Reference::parse("reference.csv", CSV).expect("parses");
        let estimate = [point(0.5, 1.0, -179.0, 1e-6), point(3.5, 1.0, -179.0, 1e-6)];
        let d = r.difference(&estimate);
        let [roll, pitch, yaw] = d.attitude_rms_deg.expect("attitude");
        assert!((roll - 1.0).abs() < 1e-9, "{roll}");
        assert!(pitch.abs() < 1e-12);
        assert!((yaw - 2.0).abs() < 1e-9, "{yaw}");
        let expected = 1e-6 * 6_378_137.0 * (1.0 - 0.006_694_379_990_141_3);
        let h = d.horizontal_rms_m.expect("horizontal");
        assert!((h - expected).abs() < 1e-6, "{h} vs {expected}");
        assert_eq!(d.samples, 3);
        assert!((d.scored_seconds - 2.0).abs() < 1e-12);
    }

    /// Reference rows outside the estimate's span are not scored.
    #[test]
    fn only_the_overlap_is_scored() {
        let r = Reference::parse("reference.csv", CSV).expect("parses");
        let d = r.difference(&[point(1.5, 0.0, 179.0, 0.0), point(2.5, 0.0, 179.0, 0.0)]);
        assert_eq!(d.samples, 1);
        assert_eq!(d.scored_seconds, 0.0);
    }

    /// The importer's fixed schema: a group left empty is not compared.
    #[test]
    fn empty_groups_are_absent() {
        let text = "t,lat,lon,height,vn,ve,vd,roll,pitch,yaw\n\
            1.0,,,,0,0,0,0.1,0.2,0.3\n\
            2.0,,,,0,0,0,0.1,0.2,0.3\n";
        let r = Reference::parse("reference.csv", text).expect("parses");
        assert_eq!(r.position, None);
        assert_eq!(r.attitude.as_deref(), Some(&[[0.1, 0.2, 0.3]; 2][..]));
        let e = Reference::parse(
            "reference.csv",
            "t,lat,lon,height,roll,pitch,yaw\n1.0,0.1,,0,0,0,0\n",
        )
        .expect_err("half a position")
        .to_string();
        assert!(
            e.contains("reference.csv:2: column `lon`: empty cell"),
            "{e}"
        );
    }

    #[test]
    fn bad_rows_name_line_and_column() {
        let cases = [
            (
                "t,roll,pitch,yaw\n1.0,x,0,0\n",
                "reference.csv:2: column `roll`: `x` is not a number",
            ),
            (
                "t,roll,pitch,yaw\n1.0,0,0,0\n1.0,0,0,0\n",
                "reference.csv:3: column `t`: duplicate timestamp t = 1",
            ),
            (
                "t,roll,pitch,yaw\n2.0,0,0,0\n1.0,0,0,0\n",
                "reference.csv:3: column `t`: time goes backwards",
            ),
            (
                "roll\n0\n",
                "reference.csv:1: column `t`: wrong header: found `roll`, expected header `t,lat,lon,height",
            ),
            (
                "t,roll,pitch,yaw\n1.0\n",
                "reference.csv:2: column `roll`: empty cell",
            ),
        ];
        for (text, expected) in cases {
            let e = Reference::parse("reference.csv", text)
                .expect_err(text)
                .to_string();
            assert!(e.contains(expected), "{e}");
        }
    }
}
