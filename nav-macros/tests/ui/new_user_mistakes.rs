// Mistakes of a first model (a ship, an altimeter): each is reported once,
// at its token, saying what the name is and what to write instead.

nav_runtime::model! {
    pub model Ship {
        states { position: 2, heading: angle, surge }
        inputs { yaw_rate }
        parameters { declination, drag }
        noise { gyro_noise, surge_noise }
        continuous {
            d/dt position = [surge * cos(heading), surge * sin(heading)];
            d/dt heading = yaw_rate + gyro_noise;
            d/dt surge = -drag * surge + surge_noise;
            // A parameter is not estimated: no "did you mean" a state.
            d/dt drag = 0.0;
            // The wrong form is one error, not also "assigned more than once".
            surge = 0.0;
        }
        sensor Compass: 1 {
            // Components are numbered from 0.
            angles = [1];
            let magnetic = heading - declination;
            h = magnetic;
        }
        sensor Magnetic: 1 {
            // Another sensor's `let`.
            h = magnetic;
        }
        sensor Speed: 1 {
            let s = surge;
        }
    }
}

nav_runtime::model! {
    pub model Attitude {
        states { angles: angle: 3 }
        continuous { d/dt angles = 0.0; }
        sensor A: 1 { h = angles; }
    }
}

nav_runtime::model! {
    pub model Altimeter {
        states { altitude }
        continuous { d/dt altitude = 0.0; }
        sensor Baro { h = altitude; }
    }
}

nav_runtime::model! {
    pub model Rangefinder {
        state { altitude }
        continuous { d/dt altitude = 0.0; }
        sensor Range: 1 { h = altitude; }
    }
}

fn main() {}
