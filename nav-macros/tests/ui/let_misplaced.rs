nav_runtime::model! {
    pub model Misplaced {
        states { x, let y = 2.0 }
        noise { w }
        continuous { d/dt x = w; }
    }
}

nav_runtime::model! {
    pub model NoiseInShared {
        states { x }
        noise { w }
        let shared = x + w;
        continuous { d/dt x = shared; }
    }
}

nav_runtime::model! {
    pub model LetInSensorOnly {
        states { x }
        noise { w }
        continuous {
            let rate = 2.0 * x;
            d/dt x = rate + w;
        }
        sensor S: 1 { h = rate; }
    }
}

fn main() {}
