// A measurement that references a state of a block that is not included.
nav_runtime::model! {
    pub block Core {
        states { pos, vel }
        inputs { accel }
        continuous {
            d/dt pos = vel;
            d/dt vel = accel;
        }
    }
    pub block Dvl {
        states { dvl_bias }
        needs { vel }
        sensor Dvl: 1 { h = vel + dvl_bias; }
    }
    /// A second DVL head sharing the bias state of `Dvl`.
    pub block DvlAft {
        needs { vel, dvl_bias }
        sensor DvlAft: 1 { h = vel - dvl_bias; }
    }
}

nav_runtime::model! {
    pub model Auv = Core + DvlAft;
}

fn main() {}
