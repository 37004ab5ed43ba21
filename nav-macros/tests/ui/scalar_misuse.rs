// The scalar of a model: `f32` or `f64`, once, in a model or a composition
// (a block takes the scalar of the model it is composed into).
nav_runtime::model! {
    pub model Half {
        scalar f16;
        states { x }
        noise { w }
        continuous { d/dt x = w; }
    }
}

nav_runtime::model! {
    pub model Twice {
        scalar f32;
        states { x }
        noise { w }
        scalar f64;
        continuous { d/dt x = w; }
    }
}

nav_runtime::model! {
    pub block Part {
        scalar f32;
        states { x }
    }
}

nav_runtime::model! {
    pub model Single {
        scalar f32;
        states { x }
        noise { w }
        continuous { d/dt x = w; }
    }
}

fn main() {
    // An f32 model runs in an f32 filter: an f64 covariance does not fit.
    let _ = nav_runtime::ekf::Ekf::<Single, 1, f32>::new(
        nav_runtime::nalgebra::SVector::<f32, 1>::zeros(),
        nav_runtime::nalgebra::SMatrix::<f64, 1, 1>::identity(),
        SingleParams::default(),
        SingleNoise::default(),
    );
}
