// Two blocks declaring the same state.
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
    pub block DvlScaled {
        states { dvl_bias, dvl_scale }
        needs { vel }
        sensor DvlScaled: 1 { h = (1.0 + dvl_scale) * vel + dvl_bias; }
    }
}

nav_runtime::model! {
    pub model Auv = Core + Dvl + DvlScaled;
}

fn main() {}
