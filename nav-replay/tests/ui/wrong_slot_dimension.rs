// A one-output sensor (the depth meter) in the three-output GNSS slot of an
// `InsVehicle` impl does not compile.
use nav_ins::{Absent, InsVehicle};
use nav_blocks::{Depth, GnssFix, InsCore};

nav_runtime::model! {
    /// Core + GNSS fix + depth meter.
    pub model Wrong = InsCore + GnssFix + Depth;
}

impl InsVehicle<16> for Wrong {
    const REPLAY_NAME: &'static str = "wrong";
    const DESCRIPTION: &'static str = "";
    type Depth = Absent;
    type Dvl = Absent;
    type Compass = Absent;
    type CompassSmallAngle = Absent;
    type Usbl = Absent;
    type Gnss = WrongDepth;
    type Baro = Absent;
    type Mag = Absent;
}

fn main() {}
