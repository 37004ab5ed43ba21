// The mistakes shown in docs/guide/building-a-vehicle.md,
// with the standard blocks of the nav-blocks crate, as a user's crate uses them.
use nav_blocks::{Compass, Depth, Dvl, InsCore};

// The pressure block of the walk-through, as it should be.
nav_runtime::model! {
    pub block PressureDepth {
        states { pressure_bias }
        needs { position_error: 3, attitude_error: 3, c_bn: 3x3 }
        sensor PressureDepth: 1 {
            inputs { lever_arm: 3 }
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let arm_error = (c_bn - c_true) * lever_arm;
            h = [position_error[2] - arm_error[2] - pressure_bias];
        }
    }
}

// Mistake 1: reading a core state without listing it in `needs`.
nav_runtime::model! {
    pub block PressureNoNeeds {
        states { pressure_bias }
        needs { position_error: 3, c_bn: 3x3 }
        sensor PressureDepth: 1 {
            inputs { lever_arm: 3 }
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let arm_error = (c_bn - c_true) * lever_arm;
            h = [position_error[2] - arm_error[2] - pressure_bias];
        }
    }
}

// Mistake 2: a block copied from `Depth` that kept its state name.
nav_runtime::model! {
    pub block PressureCopied {
        states { depth_bias }
        needs { position_error: 3, attitude_error: 3, c_bn: 3x3 }
        sensor PressureDepth: 1 {
            inputs { lever_arm: 3 }
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let arm_error = (c_bn - c_true) * lever_arm;
            h = [position_error[2] - arm_error[2] - depth_bias];
        }
    }
}

nav_runtime::model! {
    pub model BothDepths = InsCore + Depth + PressureCopied + Dvl + Compass;
}

// Mistake 3: a need of the wrong shape, and one no block provides.
nav_runtime::model! {
    pub block PressureWrongNeeds {
        states { pressure_bias }
        needs { position_error: 3, attitude_error: 3, c_bn: 3, water_density }
        sensor PressureDepth: 1 {
            h = [position_error[2] * water_density - pressure_bias + c_bn[0] * attitude_error[0]];
        }
    }
}

nav_runtime::model! {
    pub model WrongNeeds = InsCore + PressureWrongNeeds + Dvl + Compass;
}

// Mistake 4: no horizontal position fix, so nothing observes the longitude error.
nav_runtime::model! {
    pub model Submerged = InsCore + PressureDepth + Dvl + Compass;
}

fn main() {}
