//! Declared log mappings (`[files.<sensor>]` of meta.toml): header names in
//! any order, units, frames, IMU increments, other files; and their errors.
//! Every conversion is checked against a value computed by hand.

use crate::common;

use common::TempDir;
use nav_runtime::log::*;

const INITIAL: &str = "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n";
const IMU: &str = "t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,-9.8\n0.01,0,0,0,0,0,-9.8\n";

/// A log directory with `meta.toml` = `[initial]` + `sections` and the given
/// files (a standard `imu.csv` unless one is given or mapped).
fn log_dir(sections: &str, files: &[(&str, &str)]) -> TempDir {
    let dir = TempDir::new("mapping");
    std::fs::write(dir.path().join("meta.toml"), format!("{INITIAL}{sections}")).unwrap();
    if !files.iter().any(|(f, _)| *f == "imu.csv") && !sections.contains("[files.imu]") {
        std::fs::write(dir.path().join("imu.csv"), IMU).unwrap();
    }
    for (name, text) in files {
        let p = dir.path().join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).unwrap();
        }
        std::fs::write(p, text).unwrap();
    }
    dir
}

/// The cells of the first row of `sensor`'s rows in a log read strictly.
fn first_cells(log: &LogDir, sensor: &str) -> Vec<Option<f64>> {
    fn first<R: Row>(rows: Option<&Vec<R>>) -> Vec<Option<f64>> {
        rows.and_then(|r| r.first())
            .map(|r| r.to_cells())
            .unwrap_or_default()
    }
    match sensor {
        "imu" => first(Some(&log.imu)),
        "dvl" => first(log.dvl.as_ref()),
        "depth" => first(log.depth.as_ref()),
        "heading" => first(log.heading.as_ref()),
        "usbl" => first(log.usbl.as_ref()),
        "speed" => first(log.speed.as_ref()),
        "rpm" => first(log.rpm.as_ref()),
        "altitude" => first(log.altitude.as_ref()),
        "mag" => first(log.mag.as_ref()),
        _ => first(log.truth.as_ref()),
    }
}

const D: f64 = std::f64::consts::PI / 180.0;
const G: f64 = 9.80665;
const FT: f64 = 0.3048;
const KN: f64 = 1852.0 / 3600.0;

/// (case, meta.toml sections, file name, file text, sensor, first row as
/// read, in standard units and frames: hand-computed).
type Conversion = (
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    Vec<f64>,
);

fn conversions() -> Vec<Conversion> {
    vec![
        ("standard columns in another order", "", "imu.csv",
            "az,t,gz,gy,gx,ay,ax\n-9.8,0.5,3,2,1,5,4\n", "imu",
            vec![0.5, 1.0, 2.0, 3.0, 4.0, 5.0, -9.8]),
        ("imu in deg/s and g",
            "[files.imu]\nunits = { rate = \"deg/s\", specific_force = \"g\" }\n", "imu.csv",
            "t,gx,gy,gz,ax,ay,az\n0.5,90,180,-45,1,0,-1\n", "imu",
            vec![0.5, 90.0 * D, 180.0 * D, -45.0 * D, G, 0.0, -G]),
        ("a column's own unit beats its quantity's",
            "[files.imu]\nunits = { rate = \"deg/s\", gz = \"rad/s\" }\n", "imu.csv",
            "t,gx,gy,gz,ax,ay,az\n0.5,90,0,0.25,0,0,-9.8\n", "imu",
            vec![0.5, 90.0 * D, 0.0, 0.25, 0.0, 0.0, -9.8]),
        ("imu in FLU", "[files.imu]\nbody_frame = \"FLU\"\n", "imu.csv",
            "t,gx,gy,gz,ax,ay,az\n0.5,0.1,0.2,0.3,1,2,9.8\n", "imu",
            vec![0.5, 0.1, -0.2, -0.3, 1.0, -2.0, -9.8]),
        ("imu of another file, renamed, reordered, with ignored columns",
            "[files.imu]\nfile = \"raw/xsens.csv\"\nignore = [\"temp\", \"status\"]\n\
             columns = { t = \"time\", gx = \"wx\", gy = \"wy\", gz = \"wz\", ax = \"fx\", ay = \"fy\", az = \"fz\" }\n",
            "raw/xsens.csv",
            "status,time,wz,wy,wx,temp,fz,fy,fx\nOK,0.5,3,2,1,21.5,-9.8,5,4\n", "imu",
            vec![0.5, 1.0, 2.0, 3.0, 4.0, 5.0, -9.8]),
        ("imu increments (first row: the second row's interval)", "", "imu.csv",
            "t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z\n0.5,0.001,0.002,0.003,0.01,0.02,-0.098\n0.52,0,0,0,0,0,0\n",
            "imu", vec![0.5, 0.05, 0.1, 0.15, 0.5, 1.0, -4.9]),
        ("imu increments in deg and FLU, renamed",
            "[files.imu]\nbody_frame = \"FLU\"\nunits = { dtheta_x = \"deg\", dtheta_y = \"deg\", dtheta_z = \"deg\" }\n\
             columns = { dtheta_x = \"dax\", dtheta_y = \"day\", dtheta_z = \"daz\", dv_x = \"dvx\", dv_y = \"dvy\", dv_z = \"dvz\" }\n",
            "imu.csv",
            "t,dax,day,daz,dvx,dvy,dvz\n1,0.1,0.2,0.3,0.01,0.02,0.098\n1.01,0,0,0,0,0,0\n", "imu",
            vec![1.0, 10.0 * D, -20.0 * D, -30.0 * D, 1.0, -2.0, -9.8]),
        ("dvl in knots, FLU, empty cells kept", "[files.dvl]\nunits = { speed = \"kn\" }\nbody_frame = \"FLU\"\n",
            "dvl.csv", "t,vx,vy,vz\n0.5,1,2,3\n", "dvl", vec![0.5, KN, -2.0 * KN, -3.0 * KN]),
        ("depth in feet", "[files.depth]\nunits = { depth = \"ft\" }\n", "depth.csv",
            "t,depth\n0.5,10\n", "depth", vec![0.5, 10.0 * FT]),
        ("altitude in feet (length)", "[files.altitude]\nunits = { length = \"ft\" }\n",
            "altitude.csv", "t,altitude\n0.5,100\n", "altitude", vec![0.5, 100.0 * FT]),
        ("heading in degrees", "[files.heading]\nunits = { heading = \"deg\" }\n", "heading.csv",
            "t,heading\n0.5,270\n", "heading", vec![0.5, 270.0 * D]),
        ("usbl in degrees and feet", "[files.usbl]\nunits = { angle = \"deg\", depth = \"ft\" }\n",
            "usbl.csv", "t,lat,lon,depth\n0.5,45,-120,33\n", "usbl",
            vec![0.5, 45.0 * D, -120.0 * D, 33.0 * FT]),
        ("speed in knots", "[files.speed]\nunits = { speed = \"kn\" }\n", "speed.csv",
            "t,speed\n0.5,3\n", "speed", vec![0.5, 3.0 * KN]),
        ("imu y axis of the wrong sign",
            "[files.imu]\naxes = [\"x\", \"-y\", \"z\"]\n", "imu.csv",
            "t,gx,gy,gz,ax,ay,az\n0.5,0.1,0.2,0.3,1,2,-9.8\n", "imu",
            vec![0.5, 0.1, -0.2, 0.3, 1.0, -2.0, -9.8]),
        ("imu turned 90 deg about z, renamed and in deg/s",
            "[files.imu]\naxes = [\"y\", \"-x\", \"z\"]\nunits = { gx = \"deg/s\" }\n\
             columns = { gx = \"wx\", gy = \"wy\" }\n", "imu.csv",
            "t,wx,wy,gz,ax,ay,az\n0.5,90,0.2,0.3,1,2,-9.8\n", "imu",
            vec![0.5, 0.2, -90.0 * D, 0.3, 2.0, -1.0, -9.8]),
        ("imu increments with a flipped z",
            "[files.imu]\naxes = [\"x\", \"y\", \"-z\"]\n", "imu.csv",
            "t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z\n1,0.1,0.2,0.3,0.01,0.02,0.098\n1.01,0,0,0,0,0,0\n", "imu",
            vec![1.0, 10.0, 20.0, -30.0, 1.0, 2.0, -9.8]),
        ("dvl with x and y swapped", "[files.dvl]\naxes = [\"+y\", \"x\", \"z\"]\n",
            "dvl.csv", "t,vx,vy,vz\n0.5,1,2,3\n", "dvl", vec![0.5, 2.0, 1.0, 3.0]),
        ("magnetometer in microtesla, FLU", "[files.mag]\nunits = { magnetic_field = \"uT\" }\nbody_frame = \"FLU\"\n",
            "mag.csv", "t,mx,my,mz\n0.5,20,5,-40\n", "mag", vec![0.5, 0.2, -0.05, 0.4]),
        ("magnetometer of another file with a flipped y", "[files.mag]\nfile = \"compass/mag.csv\"\naxes = [\"x\", \"-y\", \"z\"]\n",
            "compass/mag.csv", "t,mx,my,mz\n0.5,0.2,0.05,0.4\n", "mag", vec![0.5, 0.2, -0.05, 0.4]),
        ("truth in ENU and degrees",
            "[files.truth]\nnav_frame = \"ENU\"\nunits = { angle = \"deg\" }\n\
             columns = { vn = \"v_north\", ve = \"v_east\", vd = \"v_up\" }\n",
            "truth.csv", "t,lat,lon,depth,v_east,v_north,v_up,roll,pitch,yaw\n0.5,10,20,5,1,2,0.5,3,-4,90\n",
            "truth",
            vec![0.5, 10.0 * D, 20.0 * D, 5.0, 2.0, 1.0, -0.5, 3.0 * D, -4.0 * D, 90.0 * D]),
        // Heading east, the point 2 m ahead of the IMU and 0.5 m below it:
        // the IMU is 2 m west and 0.5 m shallower (the first row has no
        // turn rate: its velocity is as read).
        ("truth of a point ahead of the IMU",
            "[files.truth]\nlever_arm = [2.0, 0.0, 0.5]\n",
            "truth.csv", "t,lat,lon,depth,vn,ve,vd,roll,pitch,yaw\n0.5,0.2,0.3,5,1,2,0.5,0,0,1.5707963267948966\n",
            "truth",
            vec![
                0.5,
                0.2,
                0.3 - 2.0 / ((nav_runtime::earth::transverse_radius(0.2) - 5.0) * 0.2f64.cos()),
                4.5,
                1.0,
                2.0,
                0.5,
                0.0,
                0.0,
                std::f64::consts::FRAC_PI_2,
            ]),
    ]
}

#[test]
fn conversions_match_hand_computed_values() {
    for (name, sections, file, text, sensor, want) in conversions() {
        let dir = log_dir(sections, &[(file, text)]);
        let log =
            LogDir::read(dir.path(), Strictness::Strict).unwrap_or_else(|e| panic!("{name}: {e}"));
        let got = first_cells(&log, sensor);
        assert_eq!(got.len(), want.len(), "{name}: {got:?}");
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            let g = g.unwrap_or(f64::NAN);
            assert!(
                (g - w).abs() <= 1e-12 * w.abs().max(1.0),
                "{name}: cell {i}: read {g}, hand-computed {w}"
            );
        }
        let increments = text.starts_with("t,dtheta") || sections.contains("dtheta");
        let form = if increments {
            ImuForm::Increments
        } else {
            ImuForm::Rates
        };
        assert_eq!(log.imu_form, form, "{name}");
        assert!(
            log.unknown_files.is_empty(),
            "{name}: {:?}",
            log.unknown_files
        );
    }
}

/// What an error case expects.
enum Expect {
    /// A meta.toml error on this key, its message containing the text.
    Meta(&'static str, &'static str),
    /// A CSV error in this file and column, the message containing the text.
    Csv(&'static str, &'static str, &'static str),
    /// A declared file that is missing.
    Missing(&'static str),
    /// An I/O error on a path ending in this file name.
    Io(&'static str),
}

/// (case, meta.toml sections, files, expectation).
type ErrorCase = (
    &'static str,
    &'static str,
    Vec<(&'static str, &'static str)>,
    Expect,
);

fn errors() -> Vec<ErrorCase> {
    use Expect::*;
    vec![
        (
            "unknown unit",
            "[files.imu]\nunits = { rate = \"rpm\" }\n",
            vec![],
            Meta("files.imu.units.rate", "unknown unit `rpm`"),
        ),
        (
            "unit of another quantity",
            "[files.depth]\nunits = { depth = \"deg\" }\n",
            vec![],
            Meta("files.depth.units.depth", "expected one of: m, ft"),
        ),
        (
            "unknown unit key",
            "[files.depth]\nunits = { gx = \"deg/s\" }\n",
            vec![],
            Meta("files.depth.units.gx", "unknown key"),
        ),
        // A column read and ignored at once: `ignore` was not looked at,
        // and the column read all the same.
        (
            "a read column ignored",
            "[files.depth]\nignore = [\"depth\"]\n",
            vec![("depth.csv", "t,depth\n0.5,1\n")],
            Meta("files.depth.ignore", "`depth` is a column the file's mapping reads"),
        ),
        (
            "the time column ignored while times come from it",
            "[files.depth]\nignore = [\"t\"]\n",
            vec![("depth.csv", "t,depth\n0.5,1\n")],
            Meta("files.depth.ignore", "`t` is a column the file's mapping reads"),
        ),
        (
            "unknown body frame",
            "[files.imu]\nbody_frame = \"NWU\"\n",
            vec![],
            Meta("files.imu.body_frame", "unknown body frame `NWU`"),
        ),
        (
            "unknown navigation frame",
            "[files.truth]\nnav_frame = \"NWU\"\n",
            vec![],
            Meta("files.truth.nav_frame", "expected one of: NED, ENU"),
        ),
        (
            "truth lever arm of two numbers",
            "[files.truth]\nlever_arm = [1.0, 2.0]\n",
            vec![],
            Meta("files.truth.lever_arm", "expected an array of 3 numbers"),
        ),
        (
            "lever arm on another file",
            "[files.dvl]\nlever_arm = [1.0, 0.0, 0.0]\n",
            vec![],
            Meta("files.dvl.lever_arm", "unknown key"),
        ),
        (
            "frame on a sensor without vectors",
            "[files.depth]\nbody_frame = \"FLU\"\n",
            vec![],
            Meta("files.depth.body_frame", "unknown key"),
        ),
        (
            "unknown IMU form",
            "[files.imu]\nform = \"deltas\"\n",
            vec![],
            Meta("files.imu.form", "rates, increments"),
        ),
        (
            "rate and increment columns mixed",
            "[files.imu]\ncolumns = { gx = \"a\", dtheta_y = \"b\" }\n",
            vec![],
            Meta("files.imu.columns.gx", "cannot be mixed"),
        ),
        (
            "unknown sensor",
            "[files.sonar]\nfile = \"sonar.csv\"\n",
            vec![],
            Meta("files.sonar", "expected one of: imu"),
        ),
        (
            "unknown standard column",
            "[files.dvl]\ncolumns = { vy = \"v1\", vq = \"v2\" }\n",
            vec![],
            Meta("files.dvl.columns.vq", "unknown key"),
        ),
        (
            "one header name for two columns",
            "[files.dvl]\ncolumns = { vx = \"v\", vy = \"v\" }\n",
            vec![],
            Meta("files.dvl.columns.vy", "already names `vx`"),
        ),
        (
            "parent directory",
            "[files.imu]\nfile = \"../imu.csv\"\n",
            vec![],
            Meta("files.imu.file", "would leave the log directory"),
        ),
        (
            "absolute path",
            "[files.imu]\nfile = \"/etc/imu.csv\"\n",
            vec![],
            Meta("files.imu.file", "absolute path"),
        ),
        (
            "two sensors, one file",
            "[files.depth]\nfile = \"x.csv\"\n[files.altitude]\nfile = \"x.csv\"\n",
            vec![],
            Meta("files.altitude.file", "already read by `files.depth`"),
        ),
        (
            "another sensor's standard file",
            "[files.depth]\nfile = \"dvl.csv\"\n",
            vec![],
            Meta("files.depth.file", "standard file of `dvl`"),
        ),
        (
            "mapped column missing from the header",
            "[files.depth]\ncolumns = { depth = \"Depth_m\" }\n",
            vec![("depth.csv", "t,depth\n0.5,1\n")],
            Csv(
                "depth.csv",
                "Depth_m",
                "named by `files.depth.columns.depth`",
            ),
        ),
        (
            "unknown column of a mapped file",
            "[files.depth]\nfile = \"ctd.csv\"\n",
            vec![("ctd.csv", "t,depth,temp,salinity\n0.5,1,4,35\n")],
            Csv("ctd.csv", "temp", "unknown columns `temp`, `salinity`"),
        ),
        (
            "unknown column of a standard file",
            "",
            vec![("depth.csv", "t,quality,depth\n0.5,1,1\n")],
            Csv("depth.csv", "<column 2>", "found `quality`"),
        ),
        (
            "declared file missing",
            "[files.depth]\nfile = \"ctd.csv\"\n",
            vec![],
            Missing("ctd.csv"),
        ),
        (
            // The stray file is likely the one the section meant: the
            // missing file is the error, not the unknown one.
            "declared file missing, another file there",
            "[files.depth]\nfile = \"ctd.csv\"\n",
            vec![("ctd_old.csv", "t,depth\n0.5,1\n")],
            Missing("ctd.csv"),
        ),
        (
            "a single increment row",
            "",
            vec![(
                "imu.csv",
                "t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z\n0.5,0,0,0,0,0,0\n",
            )],
            Csv("imu.csv", "t", "single increment row"),
        ),
        (
            "time from the index and a time column",
            "[files.imu]\ncolumns = { t = \"Time\" }\ntime = { from_index = true, period_s = 0.01 }\n",
            vec![],
            Meta("files.imu.columns.t", "contradicts `files.imu.time.from_index`"),
        ),
        (
            "time from the index without a period",
            "[files.dvl]\ntime = { from_index = true }\n",
            vec![],
            Meta("files.dvl.time.from_index", "needs `files.dvl.time.period_s`"),
        ),
        (
            "a start time without the index",
            "[files.dvl]\ntime = { start_s = 3.0 }\n",
            vec![],
            Meta("files.dvl.time.start_s", "from_index = true"),
        ),
        (
            "a period that nothing uses",
            "[files.depth]\ntime = { period_s = 1.0 }\n",
            vec![],
            Meta("files.depth.time.period_s", "neither is given"),
        ),
        (
            "a start stamp without a period",
            "[files.imu]\ntime = { stamp = \"start\" }\n",
            vec![],
            Meta("files.imu.time.stamp", "needs `files.imu.time.period_s`"),
        ),
        (
            "an unknown stamp",
            "[files.imu]\ntime = { stamp = \"centre\", period_s = 0.01 }\n",
            vec![],
            Meta("files.imu.time.stamp", "expected one of: start, middle, end"),
        ),
        (
            "a stamp on a sensor that is not a rate",
            "[files.dvl]\ntime = { stamp = \"start\", period_s = 1 }\n",
            vec![],
            Meta("files.dvl.time.stamp", "unknown key"),
        ),
        (
            "a misspelled time key",
            "[files.dvl]\ntime = { offest_s = -0.3 }\n",
            vec![],
            Meta("files.dvl.time.offest_s", "did you mean `offset_s`?"),
        ),
        (
            "a zero period",
            "[files.imu]\ntime = { from_index = true, period_s = 0 }\n",
            vec![],
            Meta("files.imu.time.period_s", "positive seconds"),
        ),
        (
            // An exponent slip: the whole file would sit at one instant.
            // Printed as an exponent, not three hundred digits.
            "a period far below a microsecond",
            "[files.imu]\ntime = { from_index = true, period_s = 1e-300 }\n",
            vec![],
            Meta("files.imu.time.period_s", "value 1e-300 out of range (expected positive seconds, at least 1e-6"),
        ),
        (
            "an offset in milliseconds since an epoch",
            "[files.dvl]\ntime = { offset_s = 1.7e12 }\n",
            vec![],
            Meta("files.dvl.time.offset_s", "milliseconds?"),
        ),
        (
            "an offset that is text",
            "[files.dvl]\ntime = { offset_s = \"-0.3\" }\n",
            vec![],
            Meta("files.dvl.time.offset_s", "expected a number of seconds, found string"),
        ),
        (
            "from_index not a boolean",
            "[files.imu]\ntime = { from_index = 1, period_s = 0.01 }\n",
            vec![],
            Meta("files.imu.time.from_index", "expected true or false"),
        ),
        (
            "time not a table",
            "[files.imu]\ntime = 0.01\n",
            vec![],
            Meta("files.imu.time", "expected a table"),
        ),
        (
            "axes and body frame together",
            "[files.imu]\nbody_frame = \"FLU\"\naxes = [\"x\", \"-y\", \"z\"]\n",
            vec![],
            Meta("files.imu.axes", "contradicts `files.imu.body_frame`"),
        ),
        (
            "an axis twice",
            "[files.dvl]\naxes = [\"x\", \"-x\", \"z\"]\n",
            vec![],
            Meta("files.dvl.axes", "axis `x` is given twice"),
        ),
        (
            "two axes",
            "[files.dvl]\naxes = [\"x\", \"y\"]\n",
            vec![],
            Meta("files.dvl.axes", "found 2 items"),
        ),
        (
            "an unknown axis",
            "[files.mag]\naxes = [\"x\", \"y\", \"up\"]\n",
            vec![],
            Meta("files.mag.axes", "unknown axis `up`"),
        ),
        (
            "axes of a sensor without vectors",
            "[files.depth]\naxes = [\"x\", \"y\", \"z\"]\n",
            vec![],
            Meta("files.depth.axes", "unknown key"),
        ),
        (
            "a time column left in the header with from_index",
            "[files.dvl]\ntime = { from_index = true, period_s = 1 }\n",
            vec![("dvl.csv", "Time,vx,vy,vz\n0,1,0,0\n")],
            Csv("dvl.csv", "Time", "list them in `files.dvl.ignore`"),
        ),
        (
            "a gzip file that is not gzip",
            "[files.depth]\nfile = \"depth.csv.gz\"\n",
            vec![("depth.csv.gz", "t,depth\n0.5,1\n")],
            Io("depth.csv.gz"),
        ),
        (
            "increments declared, rates given",
            "[files.imu]\nform = \"increments\"\n",
            vec![("imu.csv", IMU)],
            Csv("imu.csv", "dtheta_x", "expected header `t,dtheta_x"),
        ),
    ]
}

#[test]
fn bad_mappings_name_file_and_key() {
    for (name, sections, files, expect) in errors() {
        let dir = log_dir(sections, &files);
        let err = match LogDir::read(dir.path(), Strictness::Strict) {
            Ok(_) => panic!("{name}: accepted"),
            Err(e) => e,
        };
        let msg = err.to_string();
        assert!(!msg.contains('\n'), "{name}: {msg}");
        match expect {
            Expect::Meta(key, text) => {
                assert!(matches!(err, LogError::Meta { .. }), "{name}: {err:?}");
                assert_eq!(err.column(), Some(key), "{name}: {msg}");
                assert!(msg.contains(text), "{name}: {msg}");
            }
            Expect::Csv(file, column, text) => {
                assert!(matches!(err, LogError::Csv { .. }), "{name}: {err:?}");
                assert_eq!(err.file(), Some(file), "{name}: {msg}");
                assert_eq!(err.column(), Some(column), "{name}: {msg}");
                assert!(msg.contains(text), "{name}: {msg}");
            }
            Expect::Missing(file) => {
                assert!(
                    matches!(err, LogError::MissingFile { .. }),
                    "{name}: {err:?}"
                );
                assert_eq!(err.file(), Some(file), "{name}: {msg}");
                // The key that declares it is named (it was not).
                assert_eq!(err.column(), Some("files.depth.file"), "{name}: {msg}");
                assert!(
                    msg.contains("(named by `files.depth.file`)"),
                    "{name}: {msg}"
                );
            }
            Expect::Io(file) => {
                assert!(matches!(err, LogError::Io { .. }), "{name}: {err:?}");
                assert!(msg.contains(file), "{name}: {msg}");
            }
        }
    }
}

#[test]
fn a_mapped_file_is_no_unknown_file_and_streams() {
    let dir = log_dir(
        "[files.depth]\nfile = \"ctd.csv\"\ncolumns = { depth = \"pressure_depth\" }\n",
        &[
            ("ctd.csv", "t,pressure_depth\n0.5,1\n0.7,2\n"),
            ("depth.csv", "t,depth\n0.5,9\n"),
        ],
    );
    let files = LogFiles::open(dir.path(), Strictness::Strict).unwrap();
    assert!(files.unknown_files().is_empty());
    assert_eq!(
        unknown_csv_files(dir.path(), files.mapping()).unwrap(),
        Vec::<String>::new()
    );
    assert_eq!(
        unknown_csv_files(dir.path(), &LogMapping::default()).unwrap(),
        vec!["ctd.csv".to_string()]
    );
    // The standard file the section replaces is not read, and said so.
    assert!(
        files
            .warnings()
            .iter()
            .any(|w| w.file.as_deref() == Some("depth.csv")
                && w.message.contains("files.depth.file")),
        "{:?}",
        files.warnings()
    );
    let mut rows = files.rows::<DepthRow>().unwrap().unwrap();
    assert_eq!(rows.file(), "ctd.csv");
    assert_eq!(rows.next_row().unwrap(), Some((2, DepthRow::new(0.5, 1.0))));
    assert_eq!(rows.next_row().unwrap(), Some((3, DepthRow::new(0.7, 2.0))));
    assert_eq!(rows.next_row().unwrap(), None);
    let mut events = EventStream::open(&files).unwrap();
    let mut depths = 0;
    while let Some(e) = events.next_event().unwrap() {
        depths += usize::from(matches!(e.event, Event::Depth(_)));
    }
    assert_eq!(depths, 2);
}

/// Increments: each row is divided by its own interval; after a skipped row
/// (lenient) by the previous interval; errors name the increment columns.
#[test]
fn increments_are_divided_by_their_interval() {
    let text = "t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z\n\
                1.00,0.01,0,0,0.1,0,0\n\
                1.01,0.01,0,0,0.1,0,0\n\
                1.03,0.04,0,0,0.4,0,0\n\
                1.04,bad,0,0,0.1,0,0\n\
                1.05,0.03,0,0,0.3,0,0\n";
    let rows = |strictness| parse_csv::<ImuRow>(text.as_bytes(), strictness);
    let err = rows(Strictness::Strict).unwrap_err();
    assert_eq!(
        (err.line(), err.column()),
        (Some(5), Some("dtheta_x")),
        "{err}"
    );
    let table = rows(Strictness::Lenient).unwrap();
    let gx: Vec<f64> = table.rows.iter().map(|r| r.gx).collect();
    // 0.01/0.01, 0.01/0.01, 0.04/0.02, then 0.03 over the previous 0.02 s.
    let want = [1.0, 1.0, 2.0, 1.5];
    assert_eq!(gx.len(), want.len());
    for (g, w) in gx.iter().zip(want) {
        assert!((g - w).abs() < 1e-12, "{gx:?}");
    }
    assert!((table.rows[2].ax - 20.0).abs() < 1e-12);
    let mut reader = RowReader::<ImuRow, _>::new(text.as_bytes(), Strictness::Lenient).unwrap();
    assert_eq!(reader.form(), ImuForm::Increments);
    assert_eq!(reader.next_row().unwrap().map(|(l, _)| l), Some(2));
    assert_eq!(reader.accepted(), 1);
}

#[test]
fn mountings_are_parsed_and_checked() {
    let meta = Meta::parse(&format!(
        "{INITIAL}[sensors.dvl]\nnoise_sigma = 0.01\nlever_arm = [1.5, -0.2, 0.3]\n\
         [sensors.usbl]\nnoise_sigma = 1\nmisalignment = [0, 0.01, -0.02]\nmisalignment_sigma = 0.001\n"
    ))
    .unwrap();
    let dvl = meta.sensors.mounting("dvl").unwrap();
    assert_eq!(dvl.lever_arm, [1.5, -0.2, 0.3]);
    assert_eq!(dvl.misalignment, [0.0; 3]);
    let usbl = meta.sensors.mounting("usbl").unwrap();
    assert_eq!(usbl.misalignment, [0.0, 0.01, -0.02]);
    assert_eq!(meta.sensors.usbl_misalignment_sigma, Some(0.001));
    assert!(meta.sensors.mounting("depth").is_none());
    assert_eq!(Meta::parse(&meta.to_toml()).unwrap(), meta);
    // The imported-log sensors: a GNSS antenna lever arm and a magnetometer
    // misalignment, written back the same.
    let px4 = Meta::parse(&format!(
        "{INITIAL}[sensors.gnss]\nnoise_sigma = 0.5\nlever_arm = [0.1, 0, -0.2]\n\
         [sensors.mag]\nnoise_sigma = 0.05\nmisalignment = [0, 0, 0.01]\n\
         [sensors.baro]\nnoise_sigma = 3.5\n"
    ))
    .unwrap();
    assert_eq!(
        px4.sensors.mounting("gnss").unwrap().lever_arm,
        [0.1, 0.0, -0.2]
    );
    assert_eq!(
        px4.sensors.mounting("mag").unwrap().misalignment,
        [0.0, 0.0, 0.01]
    );
    assert!(px4.sensors.mounting("baro").is_none());
    assert_eq!(Meta::parse(&px4.to_toml()).unwrap(), px4);
    for (text, key, problem) in [
        (
            "[sensors.dvl]\nnoise_sigma = 1\nlever_arm = [1, 2]\n",
            "sensors.dvl.lever_arm",
            "3 numbers",
        ),
        (
            "[sensors.dvl]\nnoise_sigma = 1\nlever_arm = [1, 2, \"x\"]\n",
            "sensors.dvl.lever_arm",
            "numbers",
        ),
        (
            "[sensors.dvl]\nnoise_sigma = 1\nlever_arm = [1500, 0, 0]\n",
            "sensors.dvl.lever_arm",
            "metres",
        ),
        (
            "[sensors.usbl]\nnoise_sigma = 1\nmisalignment = [0, 0, 90]\n",
            "sensors.usbl.misalignment",
            "out of range",
        ),
        (
            "[sensors.rpm]\nnoise_sigma = 1\nlever_arm = [0, 0, 0]\n",
            "sensors.rpm.lever_arm",
            "unknown key",
        ),
    ] {
        let err = Meta::parse(&format!("{INITIAL}{text}")).unwrap_err();
        assert_eq!(err.column(), Some(key), "{err}");
        assert!(err.to_string().contains(problem), "{err}");
    }
}

/// (case, meta.toml sections, file, file text, sensor, every time as read:
/// hand-computed).
type TimeCase = (
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    Vec<f64>,
);

fn times() -> Vec<TimeCase> {
    vec![
        ("synthetic IMU times replaced by the index, start-stamped",
            "[files.imu]\nignore = [\"Time\"]\ntime = { from_index = true, period_s = 0.01, stamp = \"start\" }\n",
            "imu.csv", "Time,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,-9.8\n0.0100004,0,0,0,0,0,-9.8\n0.0200008,0,0,0,0,0,-9.8\n",
            "imu", vec![0.01, 0.02, 0.03]),
        ("IMU from the index with a start time, end-stamped",
            "[files.imu]\ntime = { from_index = true, period_s = 0.005, start_s = 100 }\n",
            "imu.csv", "gx,gy,gz,ax,ay,az\n0,0,0,0,0,-9.8\n0,0,0,0,0,-9.8\n",
            "imu", vec![100.0, 100.005]),
        ("DVL from the index with an offset",
            "[files.dvl]\nignore = [\"Time\"]\ntime = { from_index = true, period_s = 1.0, offset_s = -0.3 }\n",
            "dvl.csv", "Time,vx,vy,vz\n0,1,0,0\n1.003,1,0,0\n2.006,1,0,0\n",
            "dvl", vec![-0.3, 0.7, 1.7]),
        ("DVL time column with an offset", "[files.dvl]\ntime = { offset_s = 0.5 }\n",
            "dvl.csv", "t,vx,vy,vz\n1,1,0,0\n2,1,0,0\n", "dvl", vec![1.5, 2.5]),
        ("IMU stamped in the middle of its interval",
            "[files.imu]\ntime = { stamp = \"middle\", period_s = 0.02 }\n",
            "imu.csv", "t,gx,gy,gz,ax,ay,az\n1,0,0,0,0,0,-9.8\n1.02,0,0,0,0,0,-9.8\n",
            "imu", vec![1.01, 1.03]),
        ("rows after a skipped row keep their index",
            "[files.depth]\ntime = { from_index = true, period_s = 0.5 }\n",
            "depth.csv", "depth\n1\n\n2\n1e300\n3\n", "depth", vec![0.0, 0.5, 1.5]),
        ("increments from the index: divided by the period",
            "[files.imu]\ntime = { from_index = true, period_s = 0.01 }\n",
            "imu.csv", "dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z\n0.001,0,0,0,0,-0.098\n0.002,0,0,0,0,-0.098\n",
            "imu", vec![0.0, 0.01]),
    ]
}

/// The times of every row of `sensor` in `log`.
fn all_times(log: &LogDir, sensor: &str) -> Vec<f64> {
    fn ts<R: Row>(rows: Option<&Vec<R>>) -> Vec<f64> {
        rows.map(|r| r.iter().map(Row::t).collect())
            .unwrap_or_default()
    }
    match sensor {
        "imu" => ts(Some(&log.imu)),
        "dvl" => ts(log.dvl.as_ref()),
        _ => ts(log.depth.as_ref()),
    }
}

#[test]
fn times_from_the_index_offsets_and_stamps() {
    for (name, sections, file, text, sensor, want) in times() {
        let dir = log_dir(sections, &[(file, text)]);
        // A glitch row is rejected, and counts for the index.
        let log = LogDir::read_with(dir.path(), Strictness::Strict, NonPhysical::Rejected)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let got = all_times(&log, sensor);
        assert_eq!(got.len(), want.len(), "{name}: {got:?}");
        for (g, w) in got.iter().zip(&want) {
            assert!(
                (g - w).abs() <= 1e-12,
                "{name}: read {got:?}, hand-computed {want:?}"
            );
        }
    }
    // Increments over an index period: 0.001 rad over 0.01 s.
    let dir = log_dir(
        "[files.imu]\ntime = { from_index = true, period_s = 0.01 }\n",
        &[("imu.csv", "dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z\n0.001,0,0,0,0,-0.098\n0.002,0,0,0,0,-0.098\n")],
    );
    let log = LogDir::read(dir.path(), Strictness::Strict).unwrap();
    assert!((log.imu[1].gx - 0.2).abs() < 1e-12, "{:?}", log.imu);
    assert!((log.imu[1].az + 9.8).abs() < 1e-12, "{:?}", log.imu);
}

/// A gzip-compressed file named by the mapping reads as the plain one
/// (here with the real-log options together: index times, a flipped axis).
#[test]
fn a_gzip_file_reads_as_the_plain_one() {
    use std::io::Write;
    let text = "Time,gx,gy,gz,ax,ay,az\n0,0.1,0.2,0.3,1,2,-9.8\n0.0100004,0.1,0.2,0.3,1,2,-9.8\n";
    let sections = "[files.imu]\nfile = \"raw/imu.csv.gz\"\nignore = [\"Time\"]\naxes = [\"x\", \"-y\", \"z\"]\n\
                    time = { from_index = true, period_s = 0.01, stamp = \"start\" }\n";
    let dir = log_dir(sections, &[]);
    std::fs::create_dir_all(dir.path().join("raw")).unwrap();
    // Two gzip members in a row, as concatenated `gzip` output.
    let mut bytes = Vec::new();
    let (a, b) = text.split_at(40);
    for part in [a, b] {
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        gz.write_all(part.as_bytes()).unwrap();
        bytes.extend(gz.finish().unwrap());
    }
    std::fs::write(dir.path().join("raw/imu.csv.gz"), bytes).unwrap();
    let log = LogDir::read(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(
        log.imu,
        vec![
            ImuRow::new(0.01, 0.1, -0.2, 0.3, 1.0, -2.0, -9.8),
            ImuRow::new(0.02, 0.1, -0.2, 0.3, 1.0, -2.0, -9.8)
        ]
    );
    assert!(is_gzip("imu.CSV.GZ") && !is_gzip("imu.csv"));
}

/// Every file read through a log directory stays in it: a symbolic link or
/// a path resolving outside is refused with the key that named it, and the
/// error quotes nothing of the file it reaches.
#[cfg(unix)]
#[test]
fn paths_and_links_out_of_the_log_are_refused() {
    use std::os::unix::fs::symlink;
    const SECRET: &str = "root:x:0:0:root:/root:/bin/bash";
    let outside = TempDir::new("outside");
    std::fs::write(outside.path().join("secret"), format!("{SECRET}\n")).unwrap();
    std::fs::create_dir_all(outside.path().join("raw")).unwrap();
    std::fs::write(outside.path().join("raw/imu.csv"), format!("{SECRET}\n")).unwrap();
    let secret = outside.path().join("secret");
    // (case, meta.toml sections, link in the log -> target, expected key;
    // `None`: accepted)
    type LinkCase = (
        &'static str,
        &'static str,
        &'static str,
        std::path::PathBuf,
        Option<&'static str>,
    );
    let cases: Vec<LinkCase> = vec![
        (
            "standard imu.csv linked out",
            "",
            "imu.csv",
            secret.clone(),
            Some("imu.csv"),
        ),
        (
            "standard depth.csv linked out",
            "",
            "depth.csv",
            secret.clone(),
            Some("depth.csv"),
        ),
        (
            "meta.toml linked out",
            "",
            "meta.toml",
            secret.clone(),
            Some("meta.toml"),
        ),
        (
            "mapped file linked out",
            "[files.depth]\nfile = \"ctd.csv\"\n",
            "ctd.csv",
            secret.clone(),
            Some("files.depth.file"),
        ),
        (
            "mapped file under a linked directory",
            "[files.imu]\nfile = \"raw/imu.csv\"\n",
            "raw",
            outside.path().join("raw"),
            Some("files.imu.file"),
        ),
        (
            "relative link with .. out of the log",
            "",
            "dvl.csv",
            std::path::PathBuf::from("../")
                .join(outside.path().file_name().unwrap())
                .join("secret"),
            Some("dvl.csv"),
        ),
        (
            "link inside the log",
            "[files.depth]\nfile = \"ctd.csv\"\n",
            "ctd.csv",
            std::path::PathBuf::from("data/d.csv"),
            None,
        ),
    ];
    for (name, sections, link, target, expect) in cases {
        let dir = log_dir(sections, &[("data/d.csv", "t,depth\n0.5,1\n")]);
        let at = dir.path().join(link);
        if at.exists() {
            std::fs::remove_file(&at).unwrap();
        }
        symlink(&target, &at).unwrap();
        let read = LogDir::read(dir.path(), Strictness::Lenient);
        let streamed = LogFiles::open(dir.path(), Strictness::Lenient)
            .and_then(|f| EventStream::open(&f).map(|_| ()));
        match expect {
            None => {
                let log = read.unwrap_or_else(|e| panic!("{name}: {e}"));
                assert_eq!(log.depth.map(|d| d.len()), Some(1), "{name}");
                streamed.unwrap_or_else(|e| panic!("{name}: {e}"));
            }
            Some(key) => {
                for err in [read.err(), streamed.err()] {
                    let err = err.unwrap_or_else(|| panic!("{name}: accepted"));
                    let msg = err.to_string();
                    assert!(matches!(err, LogError::Outside { .. }), "{name}: {err:?}");
                    assert_eq!(err.column(), Some(key), "{name}: {msg}");
                    assert!(msg.contains("outside the log directory"), "{name}: {msg}");
                    assert!(!msg.contains("root:"), "{name}: quotes the file: {msg}");
                }
            }
        }
    }
}
