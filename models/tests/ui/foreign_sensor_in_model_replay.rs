// A sensor of another model registered with a model replay does not
// compile: the cart's position fix is not a sensor of the rover.
use nav_replay::model_replay::ModelReplay;
use models::vehicles::rover::Rover;

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
