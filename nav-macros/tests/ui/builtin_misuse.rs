nav_runtime::model! {
    pub model Misuse {
        states { q: 4, v: 3, x }
        noise { w }
        continuous {
            d/dt q = quat_mul(q, v);
            d/dt v = rotvec_to_quat(q);
            d/dt x = min(v, x) + clamp(x, 1.0) + w;
        }
        sensor Euler: 3 {
            h = dcm_to_euler(quat_to_dcm(v));
        }
        sensor Square: 1 {
            h = x^2;
        }
    }
}

fn main() {}
