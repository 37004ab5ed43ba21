use nav_runtime::model::Sensor;
use nav_runtime::nalgebra::SMatrix;

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

/// Accepts a measurement-noise matrix of the sensor's own size.
fn takes<S: Sensor<N, M>, const N: usize, const M: usize>(_r: SMatrix<f64, M, M>) {}

fn main() {
    takes::<LevMoving, 6, 2>(SMatrix::<f64, 3, 3>::identity());
}
