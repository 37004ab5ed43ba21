// Mistakes in the composition itself.
nav_runtime::model! {
    pub block Core {
        states { pos, vel }
        inputs { accel }
        continuous {
            d/dt pos = vel;
            d/dt vel = accel;
        }
    }
    pub block Gps {
        states { gps_bias }
        needs { pos }
        sensor Gps: 1 { h = pos + gps_bias; }
    }
    pub block Ticks {
        states { tick }
        discrete { tick = tick; }
        sensor Tick: 1 { h = tick; }
    }
}

nav_runtime::model! {
    pub model A = Core + Gps { order { gps_bias, pos, velocity } }
    pub model B = Core + Gps + Core;
    pub model C = Core + Gps + Ticks;
    pub model D = Core + Gsp;
}

fn main() {}
