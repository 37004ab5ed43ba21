// A state that no measurement uses, and an `allow_unused` entry that is used.
nav_runtime::model! {
    pub block Core {
        states { pos, vel }
        inputs { accel }
        continuous {
            d/dt pos = vel;
            d/dt vel = accel;
        }
    }
    pub block Odo {
        states { odo_scale, odo_offset: 2 }
        needs { vel }
        sensor Odo: 1 { h = (1.0 + odo_scale) * vel + odo_offset[0]; }
    }
}

nav_runtime::model! {
    pub model Auv = Core + Odo;
    pub model Auv2 = Core + Odo {
        allow_unused { pos, vel, odo_offset[1] }
    }
}

fn main() {}
