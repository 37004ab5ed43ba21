// A sensor of another model registered with a model replay does not
// compile: the cart's position fix is not a sensor of the rover.
use nav_replay::model_replay::ModelReplay;

nav_runtime::model! {
    pub model Rover {
        states { north, east, heading }
        inputs { speed, yaw_rate }
        noise { speed_noise, yaw_rate_noise }
        continuous {
            d/dt north = speed * cos(heading) + speed_noise;
            d/dt east = speed * sin(heading);
            d/dt heading = yaw_rate + yaw_rate_noise;
        }
        sensor Fix: 2 { h = [north, east]; }
    }
}

nav_runtime::model! {
    pub model Cart {
        states { position, velocity }
        inputs { acceleration }
        noise { accel_noise }
        continuous {
            d/dt position = velocity;
            d/dt velocity = acceleration + accel_noise;
        }
        sensor Fix: 1 { h = [position]; }
    }
}

fn main() {
    let _ = ModelReplay::<Rover, 3>::new("rover").sensor::<CartFix, 1>();
}
