// A block that needs an input the core does not provide.
nav_runtime::model! {
    pub block Core {
        states { pos, vel }
        inputs { accel, c_bn: 3x3 }
        continuous {
            d/dt pos = vel;
            d/dt vel = accel;
        }
    }
    pub block Pressure {
        states { pressure_bias }
        needs { pos, water_density, c_bn: 3 }
        sensor Pressure: 1 { h = water_density * pos + pressure_bias + c_bn[0]; }
    }
}

nav_runtime::model! {
    pub model Auv = Core + Pressure;
}

fn main() {}
