// Mistakes inside a block are reported at the block, once.
nav_runtime::model! {
    pub block Depth {
        states { depth_bias }
        needs { position_error: 3 }
        sensor Depth: 1 { h = position_eror[2] - depth_bias; }
        sensor Depth2: 1 { h = height - depth_bias; }
    }
}

nav_runtime::model! {
    pub model Vehicle { states { x } needs { y } continuous { d/dt x = 0.0; } }
}

fn main() {}
