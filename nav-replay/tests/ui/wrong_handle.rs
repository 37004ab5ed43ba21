// A DVL reading pushed under the depth meter's handle does not compile.
use nav_blocks::{Compass, Depth, Dvl, InsCore};
use nav_ins::prelude::*;
use nav_ins::Absent;

nav_runtime::model! {
    /// The core with a depth meter, a DVL and a compass: 20 states.
    pub model Auv = InsCore + Depth + Dvl + Compass {
        allow_unused { position_error[1] }
    }
}

impl InsVehicle<20> for Auv {
    const REPLAY_NAME: &'static str = "auv";
    const DESCRIPTION: &'static str = "";
    type Depth = AuvDepth;
    type Dvl = AuvDvl;
    type Compass = AuvCompass;
    type CompassSmallAngle = AuvCompassSmallAngle;
    type Usbl = Absent;
    type Gnss = Absent;
    type Baro = Absent;
    type Mag = Absent;
}

fn main() {
    let initial = InitialState {
        t: 0.0,
        position: Geodetic::new(0.7, 2.2, -50.0),
        velocity: Vector3::zeros(),
        attitude: Euler { roll: 0.0, pitch: 0.0, yaw: 0.0 },
        sigma: InitialSigma::default(),
    };
    let imu = ImuSettings {
        period_s: 0.01,
        gyro_bias_sigma: 1e-6,
        gyro_noise_sigma: 1e-6,
        accel_bias_sigma: 1e-3,
        accel_noise_sigma: 1e-3,
    };
    let mut b = Navigator::<Auv, 20>::builder(initial, imu);
    let depth = b.sensor::<DepthReading>(SensorSettings::new(0.05)).unwrap();
    let mut nav = b.build(ImuSample::default()).unwrap();
    nav.push(depth, 1.0, DvlReading(Vector3::zeros()));
}
