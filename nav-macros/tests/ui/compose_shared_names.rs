// Block-level `let`s and functions belong to their block: two blocks with
// one `let` name, and a `needs` naming another block's function.
nav_runtime::model! {
    pub block Core {
        states { pos, vel }
        inputs { accel }
        let speed = vel * vel;
        fn square(a) = a * a;
        continuous {
            d/dt pos = vel;
            d/dt vel = accel;
        }
        sensor Speed: 1 { h = [speed]; }
    }
    pub block Odo {
        states { odo_bias }
        needs { vel }
        let speed = vel + odo_bias;
        sensor Odo: 1 { h = [speed]; }
    }
    pub block Log {
        states { log_bias }
        needs { square }
        sensor Log: 1 { h = [log_bias]; }
    }
}

nav_runtime::model! {
    pub model Auv = Core + Odo;
}

nav_runtime::model! {
    pub model Boat = Core + Log;
}

fn main() {}
