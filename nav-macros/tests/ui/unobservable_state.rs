// Structural observability at the declaration: a state no sensor can reach,
// a state one declared sensor set cannot reach, a misspelled sensor in
// `runs_with`, and an `allow_unused` entry that every set observes.

nav_runtime::model! {
    /// Position is dead-reckoned from velocity: nothing measures it.
    pub model Survey {
        states { position: 2, velocity: 2, depth_bias }
        inputs { accel: 2 }
        continuous {
            d/dt position = velocity;
            d/dt velocity = accel;
        }
        sensor Dvl: 2 { h = velocity; }
        sensor Depth: 1 { h = depth_bias; }
    }
}

nav_runtime::model! {
    /// With USBL the position is seen, but not in the first set.
    pub model Survey2 {
        states { position: 2, velocity: 2, depth_bias }
        inputs { accel: 2 }
        continuous {
            d/dt position = velocity;
            d/dt velocity = accel;
        }
        sensor Dvl: 2 { h = velocity; }
        sensor Depth: 1 { h = depth_bias; }
        sensor Usbl: 2 { h = position; }
        runs_with { [Dvl, Depth], [Dvl, Depth, Usbl] }
        allow_unused { velocity[1] }
    }
}

nav_runtime::model! {
    /// A misspelled sensor: the typo alone is reported, not its consequences.
    pub model Survey4 {
        states { position: 2, velocity: 2 }
        inputs { accel: 2 }
        continuous {
            d/dt position = velocity;
            d/dt velocity = accel;
        }
        sensor Dvl: 2 { h = velocity; }
        sensor Usbl: 2 { h = position; }
        runs_with { [Dvll], [Dvl, Usbl] }
    }
}

nav_runtime::model! {
    /// Correct: the dead-reckoned position is accepted.
    pub model Survey3 {
        states { position: 2, velocity: 2, depth_bias }
        inputs { accel: 2 }
        continuous {
            d/dt position = velocity;
            d/dt velocity = accel;
        }
        sensor Dvl: 2 { h = velocity; }
        sensor Depth: 1 { h = depth_bias; }
        sensor Usbl: 2 { h = position; }
        runs_with { [Dvl, Depth], [Dvl, Depth, Usbl] }
        allow_unused { position }
    }
}

fn main() {
    let _ = Survey3::RUNS_WITH;
}
