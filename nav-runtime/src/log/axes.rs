//! `[files.<sensor>] axes`: a sign or permutation of the axes of a file's
//! body-frame vectors (docs/log-format.md, "Axes"), for a sensor mounted or
//! logged with axes other than forward-right-down that `body_frame = "FLU"`
//! does not describe (a flipped y axis, a sensor turned 90 degrees).

use super::meta::Cx;
use super::LogError;

/// Where each standard axis (x, y, z of the forward-right-down body frame)
/// is read from: `(file axis 0..3, sign)`. The identity reads x from x, y
/// from y, z from z.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Axes(pub [(usize, i8); 3]);

impl Default for Axes {
    fn default() -> Self {
        Axes([(0, 1), (1, 1), (2, 1)])
    }
}

const AXIS_NAMES: [&str; 3] = ["x", "y", "z"];

impl Axes {
    /// Whether every axis is read as it is.
    pub fn is_identity(&self) -> bool {
        *self == Axes::default()
    }

    /// For the standard column `column` of a body-frame vector (`gy`,
    /// `dv_z`, `vx`, `my`, ...): the column of the file it is read from and
    /// the sign it takes; `None` for a column that is not a vector axis.
    pub fn source(&self, column: &str) -> Option<(String, f64)> {
        let (stem, axis) = split_axis(column)?;
        let (from, sign) = self.0[axis];
        Some((format!("{stem}{}", AXIS_NAMES[from]), f64::from(sign)))
    }

    /// Reads `key` (`["x", "-y", "z"]`): three of `x`, `y`, `z`, each once,
    /// each with an optional `+` or `-`.
    pub(super) fn parse(cx: &Cx<'_>, key: &str, v: &toml::Value) -> Result<Axes, LogError> {
        const EXPECTED: &str =
            "expected three axes of the file, each of x, y, z once with an optional sign, e.g. [\"x\", \"-y\", \"z\"]";
        let toml::Value::Array(items) = v else {
            return Err(cx.err(key, format!("{EXPECTED}; found {}", v.type_str())));
        };
        if items.len() != 3 {
            return Err(cx.err(key, format!("{EXPECTED}; found {} items", items.len())));
        }
        let mut out = [(0usize, 1i8); 3];
        let mut seen = [false; 3];
        for (i, item) in items.iter().enumerate() {
            let toml::Value::String(s) = item else {
                return Err(cx.err(key, format!("{EXPECTED}; found {}", item.type_str())));
            };
            let s = s.trim();
            let (sign, name) = match s.strip_prefix('-') {
                Some(rest) => (-1, rest),
                None => (1, s.strip_prefix('+').unwrap_or(s)),
            };
            let Some(axis) = AXIS_NAMES.iter().position(|a| *a == name) else {
                return Err(cx.err(key, format!("unknown axis `{s}`; {EXPECTED}")));
            };
            if seen[axis] {
                return Err(cx.err(key, format!("axis `{name}` is given twice; {EXPECTED}")));
            }
            seen[axis] = true;
            out[i] = (axis, sign);
        }
        Ok(Axes(out))
    }
}

/// `gy` -> (`g`, 1), `dtheta_z` -> (`dtheta_`, 2), `vx` -> (`v`, 0), `mz`
/// -> (`m`, 2): the stems of the body-frame vectors of the mapped files.
fn split_axis(column: &str) -> Option<(&str, usize)> {
    const STEMS: &[&str] = &["g", "a", "dtheta_", "dv_", "v", "m"];
    let (stem, last) = column.split_at(column.len().checked_sub(1)?);
    if !STEMS.contains(&stem) {
        return None;
    }
    let axis = AXIS_NAMES.iter().position(|a| *a == last)?;
    Some((stem, axis))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sources_of_standard_columns() {
        let flip_y = Axes([(0, 1), (1, -1), (2, 1)]);
        let turned = Axes([(1, 1), (0, -1), (2, 1)]);
        // (axes, standard column, expected source)
        type Case<'a> = (Axes, &'a str, Option<(&'a str, f64)>);
        let cases: [Case; 8] = [
            (Axes::default(), "gx", Some(("gx", 1.0))),
            (flip_y, "gy", Some(("gy", -1.0))),
            (flip_y, "ay", Some(("ay", -1.0))),
            (flip_y, "t", None),
            (turned, "vx", Some(("vy", 1.0))),
            (turned, "dtheta_y", Some(("dtheta_x", -1.0))),
            (turned, "mz", Some(("mz", 1.0))),
            (turned, "depth", None),
        ];
        for (axes, column, want) in cases {
            let got = axes.source(column);
            assert_eq!(
                got.as_ref().map(|(c, s)| (c.as_str(), *s)),
                want,
                "{column}"
            );
        }
    }
}
