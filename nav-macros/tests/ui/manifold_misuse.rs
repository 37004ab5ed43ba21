nav_runtime::model! {
    pub model AngleInput {
        states { x }
        inputs { heading: angle }
        noise { w }
        continuous { d/dt x = w; }
    }
}

nav_runtime::model! {
    pub model Unknown {
        states { x: unitvector }
        noise { w }
        continuous { d/dt x = w; }
    }
}

fn main() {}
