//! A vehicle that is not an INS, replayed with [`nav_replay::model_replay`]: a
//! wheeled rover (position and heading from wheel speed and yaw rate) with a
//! position fix and a range-bearing sensor to a beacon. The example
//! `replay_model` is its replay program; [`write_log`] simulates logs for
//! the tests and wrote the fixture `models/tests/fixtures/rover/`.

use std::fmt::Write as _;
use std::path::Path;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use nav_replay::model_replay::ModelReplay;

nav_runtime::model! {
    /// A wheeled rover: position and heading from wheel speed and yaw rate.
    pub model Rover {
        states {
            /// North, east position, m.
            position: 2,
            /// Heading, rad.
            heading: angle,
        }
        inputs {
            /// Wheel speed, m/s.
            speed,
            /// Yaw rate, rad/s.
            yaw_rate,
        }
        parameters {
            /// Beacon position (north, east), m.
            beacon: 2,
        }
        noise {
            /// Wheel-speed white noise, (m/s)^2/Hz.
            speed_noise,
            /// Gyro white noise, (rad/s)^2/Hz.
            yaw_rate_noise,
        }
        continuous {
            d/dt position = [(speed + speed_noise) * cos(heading), (speed + speed_noise) * sin(heading)];
            d/dt heading = yaw_rate + yaw_rate_noise;
        }
        /// A position fix, m.
        sensor Fix: 2 {
            h = position;
        }
        /// Range (m) and bearing (rad) to the beacon.
        sensor RangeBearing: 2 {
            angles = [1];
            let d = beacon - position;
            h = [norm(d), atan2(d[1], d[0]) - heading];
        }
        /// Range (m) to a surveyed landmark whose position comes with each
        /// reading.
        sensor LandmarkRange: 1 {
            inputs {
                /// The landmark's position (north, east), m.
                landmark: 2,
            }
            h = [norm(landmark - position)];
        }
    }
}

/// The replay program of the rover: its three sensors registered.
pub fn rover_replay() -> ModelReplay<Rover, 3> {
    ModelReplay::new("rover")
        .sensor::<RoverFix, 2>()
        .sensor::<RoverRangeBearing, 2>()
        .sensor::<RoverLandmarkRange, 1>()
}

/// Wheel-speed noise density, m/s/sqrt(Hz) (per sample: this over sqrt(DT)).
pub const SPEED_SIGMA: f64 = 0.05;
/// Yaw-rate noise density, rad/s/sqrt(Hz) (per sample: this over sqrt(DT)).
pub const YAW_RATE_SIGMA: f64 = 0.002;
/// Fix noise per axis, m.
pub const FIX_SIGMA: f64 = 0.5;
/// Range noise, m.
pub const RANGE_SIGMA: f64 = 0.3;
/// Bearing noise, rad.
pub const BEARING_SIGMA: f64 = 0.01;
/// The surveyed landmarks the rover ranges to in turn (north, east), m.
pub const LANDMARKS: [[f64; 2]; 3] = [[20.0, 30.0], [60.0, -10.0], [-10.0, 40.0]];
/// Beacon position (north, east), m.
pub const BEACON: [f64; 2] = [40.0, -25.0];
/// Input sample interval, s.
pub const DT: f64 = 0.1;
/// Input samples of the test drive (200 s).
pub const DRIVE_STEPS: usize = 2000;

/// How a simulated log is written.
#[derive(Clone, Copy, Debug)]
pub struct LogStyle {
    /// Yaw rate in deg/s and range in ft (else SI).
    pub other_units: bool,
    /// Columns in another order, with an extra one.
    pub shuffled: bool,
}

/// A drive of `steps` input samples every 0.1 s (turning, then a tighter
/// turn the other way from 50 to 90 s and from 140 to 170 s), with a fix
/// every 1 s and a range-bearing every 0.5 s; written into `dir` with its
/// truth and the mapping (`replay.toml`). Noise from `seed`.
///
/// # Panics
/// If `dir` cannot be written (a test or fixture helper).
pub fn write_log(dir: &Path, seed: u64, style: LogStyle, steps: usize) {
    std::fs::create_dir_all(dir).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = Normal::new(0.0, 1.0).unwrap();
    let mut g = move || n.sample(&mut rng);
    let (mut x, mut y, mut psi) = (0.0_f64, 0.0_f64, 0.3_f64);
    let rate_unit = if style.other_units {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    };
    let range_unit = if style.other_units { 1.0 / 0.3048 } else { 1.0 };
    let mut inputs = if style.shuffled {
        String::from("w_deg,extra,time,v\n")
    } else {
        String::from("t,speed,yaw_rate\n")
    };
    let mut fixes = String::from("t,north,east\n");
    let mut ranges = String::from("t,range,bearing\n");
    let mut landmarks = String::from("t,landmark_n,landmark_e,range\n");
    let mut truth = String::from("t,position[0],position[1],heading\n");
    for k in 0..=steps {
        let t = k as f64 * DT;
        // True inputs over the interval ending at t.
        let speed = 1.5;
        let rate = if (50.0..90.0).contains(&t) || (140.0..170.0).contains(&t) {
            0.05
        } else {
            -0.02
        };
        // The filter's step: position from the heading at the interval's
        // start.
        if k > 0 {
            x += speed * psi.cos() * DT;
            y += speed * psi.sin() * DT;
            psi += rate * DT;
        }
        let measured_speed = speed + SPEED_SIGMA / DT.sqrt() * g();
        let measured_rate = rate + YAW_RATE_SIGMA / DT.sqrt() * g();
        if style.shuffled {
            writeln!(
                inputs,
                "{},7,{t},{measured_speed}",
                measured_rate * rate_unit
            )
            .unwrap();
        } else {
            writeln!(inputs, "{t},{measured_speed},{}", measured_rate * rate_unit).unwrap();
        }
        let wrapped = nav_runtime::math::wrap_angle(psi);
        writeln!(truth, "{t},{x},{y},{wrapped}").unwrap();
        if k % 10 == 5 {
            writeln!(fixes, "{t},{},{}", x + FIX_SIGMA * g(), y + FIX_SIGMA * g()).unwrap();
        }
        if k % 5 == 0 && k > 0 {
            let (dn, de) = (BEACON[0] - x, BEACON[1] - y);
            let range = dn.hypot(de) + RANGE_SIGMA * g();
            let bearing = nav_runtime::math::wrap_angle(de.atan2(dn) - psi + BEARING_SIGMA * g());
            writeln!(ranges, "{t},{},{bearing}", range * range_unit).unwrap();
        }
        if k % 20 == 10 {
            let [ln, le] = LANDMARKS[(k / 20) % LANDMARKS.len()];
            let range = (ln - x).hypot(le - y) + RANGE_SIGMA * g();
            writeln!(landmarks, "{t},{ln},{le},{range}").unwrap();
        }
    }
    std::fs::write(dir.join("wheels.csv"), inputs).unwrap();
    std::fs::write(dir.join("gnss.csv"), fixes).unwrap();
    std::fs::write(dir.join("beacon.csv"), ranges).unwrap();
    std::fs::write(dir.join("landmarks.csv"), landmarks).unwrap();
    std::fs::write(dir.join("truth.csv"), truth).unwrap();
    std::fs::write(dir.join("replay.toml"), mapping(style)).unwrap();
}

/// The `replay.toml` of a simulated log.
pub fn mapping(style: LogStyle) -> String {
    let columns = match (style.shuffled, style.other_units) {
        (true, true) => "time = \"time\"\n[inputs.columns]\nspeed = \"v\"\nyaw_rate = { column = \"w_deg\", unit = \"deg/s\" }\n",
        (true, false) => "time = \"time\"\n[inputs.columns]\nspeed = \"v\"\nyaw_rate = \"w_deg\"\n",
        (false, true) => "[inputs.columns]\nyaw_rate = { column = \"yaw_rate\", unit = \"deg/s\" }\n",
        (false, false) => "",
    };
    let range = if style.other_units {
        "{ column = \"range\", unit = \"ft\" }"
    } else {
        "\"range\""
    };
    format!(
        r#"[inputs]
file = "wheels.csv"
{columns}
[parameters]
beacon = [{b0}, {b1}]

[noise]
speed_noise = {sn}
yaw_rate_noise = {yn}

[initial]
t = 0.0
[initial.state]
position = 0.0
heading = {{ value = 17.188733853924695, unit = "deg" }}
[initial.sigma]
position = 1.0
heading = 0.05

[sensors.Fix]
file = "gnss.csv"
z = ["north", "east"]
sigma = {fix}

[sensors.RangeBearing]
file = "beacon.csv"
z = [{range}, "bearing"]
sigma = [{rs}, {bs}]

[sensors.LandmarkRange]
file = "landmarks.csv"
z = "range"
sigma = {rs}
aux = {{ landmark = ["landmark_n", "landmark_e"] }}

[truth.columns]
position = ["position[0]", "position[1]"]
"#,
        b0 = BEACON[0],
        b1 = BEACON[1],
        sn = SPEED_SIGMA * SPEED_SIGMA,
        yn = YAW_RATE_SIGMA * YAW_RATE_SIGMA,
        fix = FIX_SIGMA,
        rs = RANGE_SIGMA,
        bs = BEARING_SIGMA,
    )
}
