nav_runtime::model! {
    pub model Cart {
        states { x }
        noise { w }
        continuous { d/dt x = w; }
        sensor Fix: 1 { h = x; }
    }
    pub model CartFix {
        states { y }
        noise { w }
        continuous { d/dt y = w; }
    }
}

fn main() {}
