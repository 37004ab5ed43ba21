use nav_runtime::model::Sensor;

nav_runtime::model! {
    pub model Lev {
        states { velocity: 3, a: 3 }
        inputs { gyro: 3, specific_force: 3 }
        parameters { gravity }
        noise { accel_noise: 3, gyro_noise: 3 }
        continuous {
            d/dt velocity = -cross(gyro, velocity) + gravity * a + specific_force + accel_noise;
            d/dt a = -cross(gyro + gyro_noise, a);
        }
        sensor Moving: 2 {
            h = [velocity[0], norm_squared(a)];
        }
    }
}

nav_runtime::model! {
    pub model Other {
        states { velocity: 3, a: 3 }
        continuous {
            d/dt velocity = a;
        }
        sensor Moving: 2 {
            h = [velocity[0], velocity[1] + velocity[2]];
        }
    }
}

/// Requires a sensor of model `Lev`.
fn needs<S: Sensor<6, 2, Model = Lev>>() {}

fn main() {
    needs::<LevMoving>();
    needs::<OtherMoving>();
}
