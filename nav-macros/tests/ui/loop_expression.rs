nav_runtime::model! {
    pub model Lev {
        states { velocity: 3, a: 3 }
        inputs { gyro: 3, specific_force: 3 }
        parameters { gravity }
        noise { accel_noise: 3, gyro_noise: 3 }
        continuous {
            let s = for i in 0..3 { gyro[i] };
            d/dt velocity = specific_force;
        }
        sensor Moving: 2 {
            h = [velocity[0], norm_squared(a)];
        }
    }
}

fn main() {}
