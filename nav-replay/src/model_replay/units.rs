//! Units a `replay.toml` may give a column or a value in, and their factor to
//! the SI unit the declaration works in (`docs/model-replay.md`, "Units").
//!
//! Every conversion is a factor: the declared model sees `value * factor`.
//! A unit the table does not hold is an error listing the known ones; a
//! quantity in some other unit takes an explicit `scale` instead.

/// `(unit, factor to SI)`: what a value in that unit is multiplied by.
pub const UNITS: &[(&str, f64)] = &[
    // Dimensionless and SI units as they are.
    ("1", 1.0),
    ("s", 1.0),
    ("m", 1.0),
    ("rad", 1.0),
    ("rad/s", 1.0),
    ("m/s", 1.0),
    ("m/s^2", 1.0),
    ("rad/s^2", 1.0),
    // Time.
    ("ms", 1e-3),
    ("us", 1e-6),
    // Angle and angular rate.
    ("deg", std::f64::consts::PI / 180.0),
    ("deg/s", std::f64::consts::PI / 180.0),
    ("deg/h", std::f64::consts::PI / 180.0 / 3600.0),
    ("rpm", 2.0 * std::f64::consts::PI / 60.0),
    // Length.
    ("mm", 1e-3),
    ("cm", 1e-2),
    ("km", 1e3),
    ("ft", 0.3048),
    ("nmi", 1852.0),
    // Speed.
    ("km/h", 1.0 / 3.6),
    ("knot", 1852.0 / 3600.0),
    ("ft/s", 0.3048),
    // Acceleration (standard gravity, 9.80665 m/s^2).
    ("g", 9.80665),
    ("mg", 9.80665e-3),
    // Magnetic flux density, to gauss (the unit of the log format's mag.csv).
    ("gauss", 1.0),
    ("mgauss", 1e-3),
    ("uT", 1e-2),
    ("nT", 1e-5),
];

/// The factor of `unit` to SI, if the table holds it.
pub fn factor(unit: &str) -> Option<f64> {
    UNITS.iter().find(|(u, _)| *u == unit).map(|(_, f)| *f)
}

/// The known units, comma-separated, for an error message.
pub fn known() -> String {
    let names: Vec<&str> = UNITS.iter().map(|(u, _)| *u).collect();
    names.join(", ")
}

#[cfg(test)]
mod tests {
    use super::factor;

    /// Hand-computed values: one unit of each in SI.
    #[test]
    fn units_convert_to_hand_computed_values() {
        let cases = [
            ("deg", 180.0, std::f64::consts::PI),
            ("deg/s", 90.0, std::f64::consts::FRAC_PI_2),
            ("deg/h", 15.0, 7.272_205_216_643_04e-5),
            ("rpm", 60.0, 2.0 * std::f64::consts::PI),
            ("ft", 10.0, 3.048),
            ("knot", 1.0, 0.514_444_444_444_444_4),
            ("km/h", 36.0, 10.0),
            ("g", 2.0, 19.6133),
            ("mg", 1000.0, 9.80665),
            ("uT", 50.0, 0.5),
            ("nT", 50_000.0, 0.5),
            ("ms", 250.0, 0.25),
            ("m", 1.5, 1.5),
        ];
        for (unit, value, si) in cases {
            let f = factor(unit).unwrap_or_else(|| panic!("{unit} is not known"));
            assert!(
                (value * f - si).abs() <= 1e-12 * si.abs(),
                "{value} {unit} = {} SI, expected {si}",
                value * f
            );
        }
        assert_eq!(factor("furlong"), None);
        assert_eq!(
            factor("DEG"),
            None,
            "units are case-sensitive (mg is not Mg)"
        );
    }
}
