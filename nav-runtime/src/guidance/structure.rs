//! The inspected structure: a jacket of legs and braces modelled as capsules
//! (segments with a radius), its markers, and the distance queries that collision
//! checks, camera occlusion and keep-out constraints are built on.
//!
//! Frame: local North-East-Down, metres, origin at the jacket's horizontal centre
//! and the sea surface, so `z` is depth. The test jacket of docs/models/marker9.md is
//! 6 m (x) by 2.8 m (y) by 7.8 m (z), centred at 16 m depth; the planning space is
//! 8 m (x) by 6 m (y) by 12 m (z) around it.

use nalgebra::Vector3;

/// A segment `a`-`b` swept by a sphere of `radius`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// First end of the axis, m.
    pub a: Vector3<f64>,
    /// Second end of the axis, m.
    pub b: Vector3<f64>,
    /// Radius, m.
    pub radius: f64,
}

impl Capsule {
    /// A capsule from its axis ends and radius.
    pub fn new(a: Vector3<f64>, b: Vector3<f64>, radius: f64) -> Self {
        Self { a, b, radius }
    }

    /// The point of the axis nearest `p`.
    pub fn closest_axis_point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let d = self.b - self.a;
        let len2 = d.norm_squared();
        let t = if len2 > 0.0 {
            ((p - self.a).dot(&d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.a + d * t
    }

    /// Distance from `p` to the axis (so `p` is inside when it is below `radius`).
    pub fn axis_distance(&self, p: &Vector3<f64>) -> f64 {
        (p - self.closest_axis_point(p)).norm()
    }

    /// Signed distance from `p` to the surface (negative inside).
    pub fn surface_distance(&self, p: &Vector3<f64>) -> f64 {
        self.axis_distance(p) - self.radius
    }

    /// Distance between the axis and the segment `p`-`q`.
    pub fn segment_axis_distance(&self, p: &Vector3<f64>, q: &Vector3<f64>) -> f64 {
        segment_segment_distance(p, q, &self.a, &self.b)
    }
}

/// Minimum distance between segments `p1`-`q1` and `p2`-`q2` (Ericson,
/// *Real-Time Collision Detection*, 2005, sec. 5.1.9, with the degenerate cases).
pub fn segment_segment_distance(
    p1: &Vector3<f64>,
    q1: &Vector3<f64>,
    p2: &Vector3<f64>,
    q2: &Vector3<f64>,
) -> f64 {
    const EPS: f64 = 1e-12;
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let f = d2.dot(&r);
    let (s, t);
    if a <= EPS && e <= EPS {
        return r.norm();
    }
    if a <= EPS {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= EPS {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > EPS * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    ((p1 + d1 * s) - (p2 + d2 * t)).norm()
}

/// A visual marker with a known absolute position, seen only from its front.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marker {
    /// Position of the marker centre, m.
    pub position: Vector3<f64>,
    /// Unit normal of the marker face (pointing to where it can be seen from).
    pub normal: Vector3<f64>,
    /// Index of the capsule it is mounted on.
    pub capsule: usize,
}

/// An axis-aligned box, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Lower corner.
    pub min: Vector3<f64>,
    /// Upper corner.
    pub max: Vector3<f64>,
}

impl Bounds {
    /// Whether `p` is inside (closed).
    pub fn contains(&self, p: &Vector3<f64>) -> bool {
        (0..3).all(|i| p[i] >= self.min[i] && p[i] <= self.max[i])
    }
}

/// The structure: capsules, markers and the planning space around it.
#[derive(Clone, Debug, PartialEq)]
pub struct Structure {
    /// Legs and braces.
    pub capsules: Vec<Capsule>,
    /// Markers on them.
    pub markers: Vec<Marker>,
    /// Planning space (positions the vehicle centre may take), m.
    pub bounds: Bounds,
}

/// Half length (x) of the test jacket, m.
pub const JACKET_HALF_X: f64 = 3.0;
/// Half width (y) of the test jacket, m.
pub const JACKET_HALF_Y: f64 = 1.4;
/// Depth of the jacket's top, m.
pub const JACKET_TOP: f64 = 12.1;
/// Depth of the jacket's bottom, m (7.8 m high, centred at 16 m).
pub const JACKET_BOTTOM: f64 = 19.9;
/// Leg radius, m.
pub const LEG_RADIUS: f64 = 0.15;
/// Brace radius, m.
pub const BRACE_RADIUS: f64 = 0.08;

impl Structure {
    /// The test jacket of docs/models/marker9.md: four vertical legs at the corners
    /// of 6 x 2.8 m, twelve braces (top and bottom frames, a mid-depth horizontal
    /// and a diagonal on each long face), 25 markers, and the 8 x 6 x 12 m planning
    /// space (depth 10-22 m).
    pub fn test_jacket() -> Self {
        let (hx, hy, top, bot) = (JACKET_HALF_X, JACKET_HALF_Y, JACKET_TOP, JACKET_BOTTOM);
        let mid = 0.5 * (top + bot);
        let v = Vector3::new;
        let mut capsules = Vec::new();
        // Legs 0..4: (+x,+y), (-x,+y), (-x,-y), (+x,-y).
        let corners = [(hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy)];
        for &(x, y) in &corners {
            capsules.push(Capsule::new(v(x, y, top), v(x, y, bot), LEG_RADIUS));
        }
        // Top and bottom frames: 8 horizontal braces around the perimeter.
        for &z in &[top, bot] {
            for i in 0..4 {
                let (x0, y0) = corners[i];
                let (x1, y1) = corners[(i + 1) % 4];
                capsules.push(Capsule::new(v(x0, y0, z), v(x1, y1, z), BRACE_RADIUS));
            }
        }
        // Long faces (y = +-hy): a mid-depth horizontal and a diagonal each.
        for &y in &[hy, -hy] {
            capsules.push(Capsule::new(v(-hx, y, mid), v(hx, y, mid), BRACE_RADIUS));
            capsules.push(Capsule::new(v(-hx, y, bot), v(hx, y, top), BRACE_RADIUS));
        }
        let markers = jacket_markers(&capsules);
        Self {
            capsules,
            markers,
            bounds: Bounds {
                min: v(-4.0, -3.0, 10.0),
                max: v(4.0, 3.0, 22.0),
            },
        }
    }

    /// Smallest surface distance from `p` to any capsule, and that capsule's index.
    pub fn nearest(&self, p: &Vector3<f64>) -> (f64, usize) {
        let mut best = (f64::INFINITY, 0);
        for (i, c) in self.capsules.iter().enumerate() {
            let d = c.surface_distance(p);
            if d < best.0 {
                best = (d, i);
            }
        }
        best
    }

    /// Whether a sphere of radius `inflation` at `p` is clear of every capsule
    /// and `p` lies in the planning space.
    pub fn point_free(&self, p: &Vector3<f64>, inflation: f64) -> bool {
        self.bounds.contains(p)
            && self
                .capsules
                .iter()
                .all(|c| c.axis_distance(p) > c.radius + inflation)
    }

    /// Whether the segment `p`-`q` swept by a sphere of radius `inflation` is clear
    /// of every capsule and inside the planning space (the box is convex, so the
    /// ends being inside suffices). Exact: segment-to-segment distances, not samples.
    pub fn segment_free(&self, p: &Vector3<f64>, q: &Vector3<f64>, inflation: f64) -> bool {
        self.bounds.contains(p)
            && self.bounds.contains(q)
            && self
                .capsules
                .iter()
                .all(|c| c.segment_axis_distance(p, q) > c.radius + inflation)
    }

    /// Whether the sight line `p`-`q` passes through any capsule, ignoring capsule
    /// `skip` (the one a marker at `q` is mounted on).
    pub fn occluded(&self, p: &Vector3<f64>, q: &Vector3<f64>, skip: usize) -> bool {
        self.capsules
            .iter()
            .enumerate()
            .any(|(i, c)| i != skip && c.segment_axis_distance(p, q) < c.radius)
    }
}

/// 25 markers: three per leg on its outer (long-face) side, one per leg facing
/// inward at mid-depth, three on each mid-depth brace facing out, three on the
/// +y mid-depth brace facing in.
fn jacket_markers(capsules: &[Capsule]) -> Vec<Marker> {
    let mut out = Vec::new();
    let mut put = |capsule: usize, axis: Vector3<f64>, normal: Vector3<f64>| {
        let r = capsules[capsule].radius;
        out.push(Marker {
            position: axis + normal * (r + 0.005),
            normal,
            capsule,
        });
    };
    let y = Vector3::new(0.0, 1.0, 0.0);
    let mid = 0.5 * (JACKET_TOP + JACKET_BOTTOM);
    for (leg, c) in capsules.iter().enumerate().take(4) {
        let outward = if c.a.y > 0.0 { y } else { -y };
        for &z in &[13.5, mid, 18.5] {
            put(leg, Vector3::new(c.a.x, c.a.y, z), outward);
        }
        put(leg, Vector3::new(c.a.x, c.a.y, mid), -outward);
    }
    // Mid-depth braces: capsules 12 (+y) and 14 (-y).
    for (brace, side) in [(12usize, 1.0), (14usize, -1.0)] {
        for &x in &[-1.5, 0.0, 1.5] {
            put(brace, Vector3::new(x, side * JACKET_HALF_Y, mid), y * side);
        }
    }
    for &x in &[-1.5, 0.0, 1.5] {
        put(12, Vector3::new(x, JACKET_HALF_Y, mid), -y);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
        Vector3::new(x, y, z)
    }

    #[test]
    fn jacket_has_the_papers_dimensions() {
        let s = Structure::test_jacket();
        assert_eq!(s.capsules.len(), 16);
        assert_eq!(s.markers.len(), 25);
        let (mut lo, mut hi) = (v(1e9, 1e9, 1e9), v(-1e9, -1e9, -1e9));
        for c in &s.capsules {
            for p in [c.a, c.b] {
                lo = lo.inf(&p);
                hi = hi.sup(&p);
            }
        }
        let size = hi - lo;
        assert!((size - v(6.0, 2.8, 7.8)).norm() < 1e-12, "{size}");
        assert!((0.5 * (lo.z + hi.z) - 16.0).abs() < 1e-12);
        let span = s.bounds.max - s.bounds.min;
        assert!((span - v(8.0, 6.0, 12.0)).norm() < 1e-12);
        for m in &s.markers {
            let c = &s.capsules[m.capsule];
            assert!((c.axis_distance(&m.position) - c.radius - 0.005).abs() < 1e-9);
        }
    }

    /// Table of (segment p-q, segment a-b, expected distance).
    #[test]
    fn segment_distances() {
        let cases = [
            // Crossing at right angles, 1 m apart in z.
            (
                v(-1.0, 0.0, 0.0),
                v(1.0, 0.0, 0.0),
                v(0.0, -1.0, 1.0),
                v(0.0, 1.0, 1.0),
                1.0,
            ),
            // Parallel, overlapping, 2 m apart.
            (
                v(0.0, 0.0, 0.0),
                v(4.0, 0.0, 0.0),
                v(1.0, 2.0, 0.0),
                v(3.0, 2.0, 0.0),
                2.0,
            ),
            // Parallel, disjoint end to end.
            (
                v(0.0, 0.0, 0.0),
                v(1.0, 0.0, 0.0),
                v(4.0, 0.0, 0.0),
                v(5.0, 0.0, 0.0),
                3.0,
            ),
            // Point against segment.
            (
                v(0.5, 3.0, 0.0),
                v(0.5, 3.0, 0.0),
                v(0.0, 0.0, 0.0),
                v(1.0, 0.0, 0.0),
                3.0,
            ),
            // Point against point.
            (
                v(0.0, 0.0, 0.0),
                v(0.0, 0.0, 0.0),
                v(3.0, 4.0, 0.0),
                v(3.0, 4.0, 0.0),
                5.0,
            ),
            // Skew, nearest points at ends.
            (
                v(0.0, 0.0, 0.0),
                v(1.0, 0.0, 0.0),
                v(2.0, 1.0, 0.0),
                v(2.0, 2.0, 0.0),
                2f64.sqrt(),
            ),
            // Intersecting.
            (
                v(-1.0, -1.0, 0.0),
                v(1.0, 1.0, 0.0),
                v(-1.0, 1.0, 0.0),
                v(1.0, -1.0, 0.0),
                0.0,
            ),
        ];
        for (i, (p, q, a, b, want)) in cases.iter().enumerate() {
            let d1 = segment_segment_distance(p, q, a, b);
            let d2 = segment_segment_distance(a, b, q, p);
            assert!((d1 - want).abs() < 1e-12, "case {i}: {d1} vs {want}");
            assert!((d2 - want).abs() < 1e-12, "case {i} swapped: {d2}");
        }
    }

    /// The exact distance never exceeds the distance between any pair of sampled
    /// points, and comes within the sampling resolution of the smallest one.
    #[test]
    fn segment_distance_matches_dense_sampling() {
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 4.0 - 2.0
        };
        for _ in 0..200 {
            let (p, q, a, b) = (
                v(rnd(), rnd(), rnd()),
                v(rnd(), rnd(), rnd()),
                v(rnd(), rnd(), rnd()),
                v(rnd(), rnd(), rnd()),
            );
            let exact = segment_segment_distance(&p, &q, &a, &b);
            let mut sampled = f64::INFINITY;
            let n = 200;
            for i in 0..=n {
                let x = p + (q - p) * (i as f64 / n as f64);
                let c = Capsule::new(a, b, 0.0);
                sampled = sampled.min(c.axis_distance(&x));
            }
            assert!(exact <= sampled + 1e-12);
            assert!(sampled - exact < (q - p).norm() / n as f64 + 1e-9);
        }
    }

    #[test]
    fn capsule_point_queries() {
        let c = Capsule::new(v(0.0, 0.0, 0.0), v(0.0, 0.0, 2.0), 0.5);
        assert!((c.surface_distance(&v(1.0, 0.0, 1.0)) - 0.5).abs() < 1e-12);
        assert!((c.surface_distance(&v(0.0, 0.0, 3.0)) - 0.5).abs() < 1e-12);
        assert!((c.surface_distance(&v(0.0, 0.2, 1.0)) + 0.3).abs() < 1e-12);
        let s = Structure::test_jacket();
        assert!(!s.point_free(&v(3.0, 1.4, 16.0), 0.0));
        assert!(s.point_free(&v(0.0, 0.0, 16.0), 0.6));
        assert!(!s.point_free(&v(0.0, 0.0, 25.0), 0.0), "outside the bounds");
        // Straight through the inside at mid-depth, entering by a short face.
        assert!(s.segment_free(&v(3.9, 0.0, 16.0), &v(-3.9, 0.0, 16.0), 0.6));
        // Through a long face at mid-depth: the mid brace blocks it.
        assert!(!s.segment_free(&v(0.0, 2.5, 16.0), &v(0.0, -2.5, 16.0), 0.1));
    }
}
