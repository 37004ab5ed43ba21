//! Rotations as scalar graphs, for the builtins `quat_mul`, `quat_to_dcm`,
//! `dcm_to_euler` and `rotvec_to_quat` (see `docs/language.md`).
//!
//! Conventions: Hamilton quaternions stored `[w, x, y, z]` (scalar first);
//! a quaternion `q` and a matrix `C = C_b^n` rotate body to navigation axes,
//! `v_n = q ⊗ [0, v_b] ⊗ q^*` = `C v_b`; Euler angles are roll, pitch, yaw
//! (Z-Y-X), the same as `euler_dcm`.

use super::expr::{Func, Graph, Id};

/// The Hamilton product `p ⊗ q` of two `[w, x, y, z]` quaternions.
pub fn quat_mul(g: &mut Graph, p: &[Id], q: &[Id]) -> Vec<Id> {
    // (sign, index into p, index into q) of the four terms of each component.
    const TERMS: [[(bool, usize, usize); 4]; 4] = [
        [(true, 0, 0), (false, 1, 1), (false, 2, 2), (false, 3, 3)],
        [(true, 0, 1), (true, 1, 0), (true, 2, 3), (false, 3, 2)],
        [(true, 0, 2), (false, 1, 3), (true, 2, 0), (true, 3, 1)],
        [(true, 0, 3), (true, 1, 2), (false, 2, 1), (true, 3, 0)],
    ];
    TERMS
        .iter()
        .map(|terms| {
            let mut acc = Graph::ZERO;
            for &(plus, i, j) in terms {
                let t = g.mul(p[i], q[j]);
                acc = if plus { g.add(acc, t) } else { g.sub(acc, t) };
            }
            acc
        })
        .collect()
}

/// `C_b^n` of a unit quaternion, row-major:
/// `[[1 - 2(y²+z²), 2(xy - wz), 2(xz + wy)], [2(xy + wz), 1 - 2(x²+z²), 2(yz - wx)],
/// [2(xz - wy), 2(yz + wx), 1 - 2(x²+y²)]]`. For a quaternion that is not of
/// unit norm the result is not a rotation: normalize it first.
pub fn quat_to_dcm(g: &mut Graph, q: &[Id]) -> Vec<Id> {
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    let two = g.constant(2.0);
    let twice = |g: &mut Graph, a: Id, b: Id| {
        let ab = g.mul(a, b);
        g.mul(two, ab)
    };
    let (xx, yy, zz) = (twice(g, x, x), twice(g, y, y), twice(g, z, z));
    let (xy, xz, yz) = (twice(g, x, y), twice(g, x, z), twice(g, y, z));
    let (wx, wy, wz) = (twice(g, w, x), twice(g, w, y), twice(g, w, z));
    let diag = |g: &mut Graph, a: Id, b: Id| {
        let s = g.add(a, b);
        g.sub(Graph::ONE, s)
    };
    let c00 = diag(g, yy, zz);
    let c11 = diag(g, xx, zz);
    let c22 = diag(g, xx, yy);
    let c01 = g.sub(xy, wz);
    let c02 = g.add(xz, wy);
    let c10 = g.add(xy, wz);
    let c12 = g.sub(yz, wx);
    let c20 = g.sub(xz, wy);
    let c21 = g.add(yz, wx);
    vec![c00, c01, c02, c10, c11, c12, c20, c21, c22]
}

/// `[roll, pitch, yaw]` of `C_b^n` (row-major), the inverse of `euler_dcm`:
/// roll `atan2(c21, c22)`, pitch `atan2(-c20, sqrt(c21² + c22²))` (in
/// [-pi/2, pi/2]), yaw `atan2(c10, c00)`. Singular at pitch = ±pi/2.
pub fn dcm_to_euler(g: &mut Graph, c: &[Id]) -> Vec<Id> {
    let roll = g.atan2(c[7], c[8]);
    let a = g.mul(c[7], c[7]);
    let b = g.mul(c[8], c[8]);
    let s = g.add(a, b);
    let r = g.call(Func::Sqrt, s);
    let minus = g.neg(c[6]);
    let pitch = g.atan2(minus, r);
    let yaw = g.atan2(c[3], c[0]);
    vec![roll, pitch, yaw]
}

/// The exponential map of a rotation vector `v` (rad): `[cos(θ/2),
/// sin(θ/2)/θ v]` with `θ = |v|`, a unit quaternion. Built from `s = |v|²`
/// with the half-angle factors [`Func::HalfCos`] and [`Func::HalfSinc`], so
/// it and its derivatives are finite at `v = 0` (where it is `[1, v/2]` to
/// first order, the usual small-angle error quaternion).
pub fn rotvec_to_quat(g: &mut Graph, v: &[Id]) -> Vec<Id> {
    let squares: Vec<Id> = v.iter().map(|&a| g.mul(a, a)).collect();
    let s = g.sum(squares);
    let w = g.call(Func::HalfCos, s);
    let k = g.call(Func::HalfSinc, s);
    let mut q = vec![w];
    q.extend(v.iter().map(|&a| g.mul(k, a)));
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::symbolic::Sym;

    fn eval(g: &Graph, ids: &[Id], xs: &[f64]) -> Vec<f64> {
        ids.iter()
            .map(|&id| {
                g.eval(id, &|s| match s {
                    Sym::State(k) => xs[k as usize],
                    _ => f64::NAN,
                })
            })
            .collect()
    }

    fn syms(g: &mut Graph, from: u32, n: u32) -> Vec<Id> {
        (from..from + n).map(|k| g.sym(Sym::State(k))).collect()
    }

    /// `quat_to_dcm(p ⊗ q) = quat_to_dcm(p) quat_to_dcm(q)`, and the exponential
    /// map about z is the rotation matrix about z.
    #[test]
    fn product_and_matrix_agree() {
        let mut g = Graph::new();
        let p = syms(&mut g, 0, 4);
        let q = syms(&mut g, 4, 4);
        let pq = quat_mul(&mut g, &p, &q);
        let c_pq = quat_to_dcm(&mut g, &pq);
        let c_p = quat_to_dcm(&mut g, &p);
        let c_q = quat_to_dcm(&mut g, &q);
        let unit = |v: [f64; 4]| {
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            v.map(|x| x / n)
        };
        let mut xs = unit([0.9, 0.1, -0.3, 0.2]).to_vec();
        xs.extend(unit([0.4, -0.7, 0.2, 0.5]));
        let (a, b, ab) = (
            eval(&g, &c_p, &xs),
            eval(&g, &c_q, &xs),
            eval(&g, &c_pq, &xs),
        );
        for i in 0..3 {
            for j in 0..3 {
                let want: f64 = (0..3).map(|k| a[i * 3 + k] * b[k * 3 + j]).sum();
                assert!((ab[i * 3 + j] - want).abs() < 1e-14, "({i}, {j})");
            }
        }
        let mut g = Graph::new();
        let v = syms(&mut g, 0, 3);
        let q = rotvec_to_quat(&mut g, &v);
        let c = quat_to_dcm(&mut g, &q);
        let yaw: f64 = 0.7;
        let c = eval(&g, &c, &[0.0, 0.0, yaw]);
        let want = [
            yaw.cos(),
            -yaw.sin(),
            0.0,
            yaw.sin(),
            yaw.cos(),
            0.0,
            0.0,
            0.0,
            1.0,
        ];
        for (got, want) in c.iter().zip(want) {
            assert!((got - want).abs() < 1e-15);
        }
        let q0 = eval(&g, &q, &[0.0, 0.0, 0.0]);
        assert_eq!(q0, vec![1.0, 0.0, 0.0, 0.0]);
    }

    /// `dcm_to_euler` inverts the matrix built from roll, pitch, yaw (the same
    /// matrix `euler_dcm` builds: checked against its closed form).
    #[test]
    fn euler_round_trip() {
        let (roll, pitch, yaw): (f64, f64, f64) = (0.3, -0.6, 2.5);
        let (sf, cf) = roll.sin_cos();
        let (st, ct) = pitch.sin_cos();
        let (sp, cp) = yaw.sin_cos();
        let c_bn = [
            ct * cp,
            sf * st * cp - cf * sp,
            cf * st * cp + sf * sp,
            ct * sp,
            sf * st * sp + cf * cp,
            cf * st * sp - sf * cp,
            -st,
            sf * ct,
            cf * ct,
        ];
        let mut g = Graph::new();
        let c = syms(&mut g, 0, 9);
        let e = dcm_to_euler(&mut g, &c);
        let got = eval(&g, &e, &c_bn);
        for (got, want) in got.iter().zip([roll, pitch, yaw]) {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
    }
}
