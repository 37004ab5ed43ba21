nav_runtime::model! {
    pub model Functions {
        states { x, v: 3 }
        noise { w }
        fn twice(a) = 2.0 * a;
        fn sin(a) = a;
        fn forever(a) = forever(a);
        fn scaled(a) = a * gain;
        continuous {
            d/dt x = twice(x, x) + forever(x) + w;
            d/dt v = scaled(v);
        }
    }
}

fn main() {}
