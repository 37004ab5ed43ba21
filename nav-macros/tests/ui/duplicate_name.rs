nav_runtime::model! {
    pub model Lev {
        states { velocity: 3, a: 3 }
        inputs { gyro: 3, velocity: 3 }
        parameters { gyro }
        continuous {
            d/dt velocity = -cross(gyro, velocity);
        }
        sensor Moving: 1 {
            inputs { a }
            h = [velocity[0]];
        }
    }
}

fn main() {}
