//! What a `[files.<sensor>]` section declares about a column, so that a
//! finding on mapped values names the declaration that may be wrong (the
//! values are judged after the mapping, exactly like the standard format).

use nav_runtime::log::{BodyFrame, LogMapping};

/// The unit `[files.<sensor>] units` declares for standard column `column`,
/// with its `meta.toml` key; `None` when the column is read in its standard
/// unit.
pub(super) fn unit(mapping: &LogMapping, sensor: &str, column: &str) -> Option<(String, String)> {
    let m = mapping.get(sensor)?;
    m.units
        .iter()
        .find(|(c, _)| c == column)
        .map(|(_, u)| (m.key("units"), u.clone()))
}

/// The body frame `[files.<sensor>] body_frame` declares (FRD when the
/// section does not say), and whether a section exists.
pub(super) fn body_frame(mapping: &LogMapping, sensor: &str) -> (BodyFrame, bool) {
    mapping
        .get(sensor)
        .map_or((BodyFrame::Frd, false), |m| (m.body_frame, m.declared))
}

/// The cause of values `factor` times what they should be (57.3: degrees
/// read as radians; 1/57.3: radians read as degrees) in column `column` of
/// `sensor`, whose standard unit is `standard` and whose degree unit is
/// `degrees`: the declaration when a unit was declared, the format otherwise.
pub(super) fn scale_cause(
    mapping: &LogMapping,
    sensor: &str,
    column: &str,
    standard: &str,
    degrees: &str,
    too_large: bool,
) -> String {
    match (unit(mapping, sensor, column), too_large) {
        (Some((key, u)), true) => {
            format!("{key} declares {u} for `{column}`: the values are in {degrees}?")
        }
        (Some((key, u)), false) => {
            format!("{key} declares {u} for `{column}`: the values are in {standard}?")
        }
        (None, true) => format!("{degrees}? the format is {standard}"),
        (None, false) => format!(
            "values 57.3 times too small: {standard} converted to {degrees} twice? the format \
             is {standard}"
        ),
    }
}
