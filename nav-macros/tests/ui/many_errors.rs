nav_runtime::model! {
    pub model Lev {
        states { velocity: 3, a: 3 }
        inputs { gyro: 3, specific_force: 3 }
        parameters { gravity }
        noise { accel_noise: 3, gyro_noise: 3 }
        continuous {
            let w = gyro * gyro;
            d/dt velocity = velocty + specific_force;
            d/dt a = while true {};
            d/dt b = a;
        }
        sensor Moving: 3 {
            h = [velocity[0], norm_squared(a)];
        }
    }
}

fn main() {}
