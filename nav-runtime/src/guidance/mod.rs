//! Guidance near a structure: planning ([`rrt`]), path following by line of sight
//! ([`los`]) and a constrained course correction solved as one convex program per
//! tick ([`heading_qp`]), over the capsule world of [`structure`].
//!
//! The path is a 3-D polyline. Horizontal guidance works on its projection and
//! commands a ground course `chi` and a horizontal ground speed; the vertical
//! channel follows the depth of the path at the along-track position. The vehicle
//! is hover-capable (surge, sway and heave thrusters, see [`crate::vehicle`]), so
//! it turns the velocity vector to the commanded course at a bounded rate and
//! slows down before corners; the estimated water current enters as the
//! feed-forward that converts ground velocity into water-relative velocity.
//!
//! Errors against segment `k` (docs/guidance.md, Fossen's MSS conventions): path angle
//! `pi_h = atan2(dy, dx)`, along-track `x_e`, cross-track `y_e` (positive to the
//! right of the direction of travel in NED, i.e. east of a northbound leg).

pub mod heading_qp;
pub mod los;
pub mod rrt;
pub mod structure;

use nalgebra::{Vector2, Vector3};

use crate::math::wrap_angle;

/// A planned 3-D path.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    /// Vertices, m (NED, z = depth).
    pub points: Vec<Vector3<f64>>,
}

/// Errors of a position against one segment of a [`Path`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentErrors {
    /// Index of the segment (from vertex `segment` to `segment + 1`).
    pub segment: usize,
    /// Horizontal path angle `pi_h`, rad.
    pub path_angle: f64,
    /// Along-track distance from the segment start, horizontal, m.
    pub along: f64,
    /// Signed cross-track error, horizontal, m.
    pub cross: f64,
    /// Horizontal length of the segment, m.
    pub length: f64,
    /// Depth of the path at the along-track position (clamped to the segment), m.
    pub depth: f64,
    /// Depth change per horizontal metre along the segment.
    pub slope: f64,
}

impl Path {
    /// A path from its vertices (at least two).
    pub fn new(points: Vec<Vector3<f64>>) -> Self {
        assert!(points.len() >= 2, "a path needs two vertices");
        Self { points }
    }

    /// Number of segments.
    pub fn segments(&self) -> usize {
        self.points.len() - 1
    }

    /// Errors of horizontal position `p` (and nothing else) against segment `k`.
    pub fn errors(&self, k: usize, p: &Vector2<f64>) -> SegmentErrors {
        let (a, b) = (self.points[k], self.points[k + 1]);
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let length = (dx * dx + dy * dy).sqrt();
        let pi_h = dy.atan2(dx);
        let (c, s) = (pi_h.cos(), pi_h.sin());
        let (rx, ry) = (p.x - a.x, p.y - a.y);
        let along = rx * c + ry * s;
        let cross = -rx * s + ry * c;
        let slope = if length > 1e-9 {
            (b.z - a.z) / length
        } else {
            0.0
        };
        let frac = if length > 1e-9 {
            (along / length).clamp(0.0, 1.0)
        } else {
            1.0
        };
        SegmentErrors {
            segment: k,
            path_angle: pi_h,
            along,
            cross,
            length,
            depth: a.z + frac * (b.z - a.z),
            slope,
        }
    }

    /// Horizontal course change at vertex `k + 1` (end of segment `k`), rad in
    /// `[0, pi]`; zero at the final vertex.
    pub fn turn_angle(&self, k: usize) -> f64 {
        if k + 2 >= self.points.len() {
            return 0.0;
        }
        let h = |i: usize| {
            let d = self.points[i + 1] - self.points[i];
            d.y.atan2(d.x)
        };
        wrap_angle(h(k + 1) - h(k)).abs()
    }

    /// Shortest 3-D distance from `p` to segments `from..=to` (clamped).
    pub fn distance(&self, p: &Vector3<f64>, from: usize, to: usize) -> f64 {
        let last = self.segments() - 1;
        let mut best = f64::INFINITY;
        for k in from.min(last)..=to.min(last) {
            let c = structure::Capsule::new(self.points[k], self.points[k + 1], 0.0);
            best = best.min(c.axis_distance(p));
        }
        best
    }

    /// Horizontal length of the whole path, m.
    pub fn length(&self) -> f64 {
        self.points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
    }
}

/// Guidance settings shared by every law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuidanceConfig {
    /// Cruise horizontal ground speed, m/s.
    pub cruise_speed: f64,
    /// Slowest commanded speed (at sharp corners), m/s.
    pub min_speed: f64,
    /// Deceleration used to plan the approach to a corner, m/s^2.
    pub deceleration: f64,
    /// Corner deviation budget: the corner speed makes the turning arc pass
    /// within this distance of the vertex, m.
    pub corner_deviation: f64,
    /// Largest course rate, rad/s (turn radius `U / r_max`).
    pub max_course_rate: f64,
    /// Largest course acceleration, rad/s^2.
    pub max_course_accel: f64,
    /// Waypoint switching distance `R_switch`, m.
    pub switch_distance: f64,
    /// LOS enclosure radius `R` of eq. 4, m.
    pub los_radius: f64,
    /// Guidance tick, s.
    pub tick: f64,
    /// Largest speed increase, m/s^2.
    pub acceleration: f64,
    /// Largest vertical speed the heave channel is given, m/s.
    pub max_vertical_speed: f64,
}

impl Default for GuidanceConfig {
    fn default() -> Self {
        Self {
            cruise_speed: 0.35,
            min_speed: 0.05,
            deceleration: 0.04,
            corner_deviation: 0.06,
            max_course_rate: 0.4,
            max_course_accel: 0.5,
            switch_distance: 0.12,
            los_radius: 1.0,
            tick: 0.1,
            acceleration: 0.04,
            max_vertical_speed: 0.15,
        }
    }
}

impl GuidanceConfig {
    /// Minimum turning radius at speed `u`, m.
    pub fn turning_radius(&self, u: f64) -> f64 {
        u / self.max_course_rate
    }

    /// Speed that turns through `angle` at the largest course rate with the arc
    /// passing within `corner_deviation` of the vertex: the fillet of radius
    /// `rho` misses the vertex by `rho (1 / cos(angle / 2) - 1)`.
    pub fn corner_speed(&self, angle: f64) -> f64 {
        let half = 0.5 * angle.min(3.0);
        let miss = 1.0 / half.cos() - 1.0;
        let rho = if miss > 1e-9 {
            self.corner_deviation / miss
        } else {
            f64::INFINITY
        };
        (rho * self.max_course_rate).clamp(self.min_speed, self.cruise_speed)
    }

    /// Horizontal speed limit on segment `k` from the vertical speed limit.
    pub fn climb_limit(&self, path: &Path, k: usize) -> f64 {
        let e = path.errors(k, &Vector2::new(path.points[k].x, path.points[k].y));
        if e.slope.abs() > 1e-9 {
            self.max_vertical_speed / e.slope.abs()
        } else {
            f64::INFINITY
        }
    }

    /// Horizontal speed profile at along-track `along` on segment `k`: the
    /// slowest of the cruise speed, the climb limit and the braking curve to the
    /// corner speed of the next vertex.
    pub fn speed(&self, path: &Path, k: usize, along: f64) -> f64 {
        let e = path.errors(k, &Vector2::new(path.points[k].x, path.points[k].y));
        let to_go = (e.length - along).max(0.0);
        let corner = if k + 1 == path.segments() {
            self.min_speed
        } else {
            self.corner_speed(path.turn_angle(k))
                .min(self.climb_limit(path, k + 1))
        };
        (corner * corner + 2.0 * self.deceleration * to_go)
            .sqrt()
            .min(self.cruise_speed)
            .min(self.climb_limit(path, k))
    }

    /// The speed command: the profile, slowed while the course is not yet
    /// aligned with the path (`cos` of the course error, never below the minimum
    /// speed), and
    /// raised from `previous` by at most `acceleration * step`.
    pub fn speed_command(
        &self,
        path: &Path,
        e: &SegmentErrors,
        course: f64,
        previous: f64,
        step: f64,
    ) -> f64 {
        let align = wrap_angle(course - e.path_angle).cos().max(0.0);
        (self.speed(path, e.segment, e.along) * align)
            .min(previous + self.acceleration * step)
            .max(self.min_speed)
    }
}

/// Which path-following law produces the course.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Law {
    /// Enclosure LOS (eq. 4); with no intersection it heads for the next waypoint.
    Los,
    /// Improved LOS: along the path normal when `|e|` exceeds the turning radius.
    ImprovedLos,
    /// The convex course correction of [`heading_qp`].
    ConvexCorrection,
}

impl Law {
    /// All laws, in table order.
    pub const ALL: [Law; 3] = [Law::Los, Law::ImprovedLos, Law::ConvexCorrection];

    /// Short name used in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Law::Los => "los",
            Law::ImprovedLos => "improved_los",
            Law::ConvexCorrection => "convex",
        }
    }
}

/// Tracks the active segment with the switching rule `d - x_e < R_switch`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathFollower {
    /// Active segment.
    pub segment: usize,
    /// True once the last waypoint has been reached.
    pub finished: bool,
}

impl PathFollower {
    /// Starts on the first segment.
    pub fn new() -> Self {
        Self {
            segment: 0,
            finished: false,
        }
    }

    /// Advances the active segment for horizontal position `p`; returns its errors.
    pub fn update(&mut self, path: &Path, p: &Vector2<f64>, cfg: &GuidanceConfig) -> SegmentErrors {
        loop {
            let e = path.errors(self.segment, p);
            if e.length - e.along < cfg.switch_distance {
                if self.segment + 1 < path.segments() {
                    self.segment += 1;
                    continue;
                }
                self.finished = true;
            }
            return e;
        }
    }
}

impl Default for PathFollower {
    fn default() -> Self {
        Self::new()
    }
}

/// What guidance hands the vehicle's autopilot each tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuidanceCommand {
    /// Commanded ground course (unwrapped), rad; also the heading command.
    pub course: f64,
    /// Commanded course rate (feed-forward), rad/s.
    pub course_rate: f64,
    /// Horizontal ground speed, m/s.
    pub speed: f64,
    /// Depth reference, m.
    pub depth: f64,
    /// Vertical ground speed feed-forward, m/s (positive down).
    pub vertical_speed: f64,
}

impl GuidanceCommand {
    /// Desired horizontal ground velocity `[v_N, v_E]`, m/s.
    pub fn ground_velocity(&self) -> Vector2<f64> {
        Vector2::new(self.course.cos(), self.course.sin()) * self.speed
    }
}

/// A course command that follows a target course within the rate and rate-change
/// limits: how the LOS laws (and the fallback of the convex program) respect the
/// same turning limits as the convex program.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CourseLimiter {
    /// Current course command (unwrapped), rad.
    pub course: f64,
    /// Current course rate, rad/s.
    pub rate: f64,
}

impl CourseLimiter {
    /// Starts at `course` with zero rate.
    pub fn new(course: f64) -> Self {
        Self { course, rate: 0.0 }
    }

    /// One tick toward `target` (any wrapping): the rate that reaches it in one
    /// tick or can still stop at it (`sqrt(2 a |error|)`), limited by
    /// `max_course_accel` and `max_course_rate`.
    pub fn step(&mut self, target: f64, cfg: &GuidanceConfig) -> f64 {
        let err = wrap_angle(target - self.course);
        let braking = (2.0 * cfg.max_course_accel * err.abs()).sqrt();
        let wanted = err.signum() * (err.abs() / cfg.tick).min(braking);
        let da = cfg.max_course_accel * cfg.tick;
        self.rate = wanted
            .clamp(self.rate - da, self.rate + da)
            .clamp(-cfg.max_course_rate, cfg.max_course_rate);
        self.course += self.rate * cfg.tick;
        self.course
    }
}

/// Unwraps angle `a` to within pi of `near`.
pub fn unwrap_near(a: f64, near: f64) -> f64 {
    near + wrap_angle(a - near)
}

/// Moves `from` toward `to` (unwrapped near `from`) by at most `max_step`.
pub fn rate_limit(from: f64, to: f64, max_step: f64) -> f64 {
    from + wrap_angle(to - from).clamp(-max_step, max_step)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Path {
        Path::new(vec![
            Vector3::new(0.0, 0.0, 10.0),
            Vector3::new(4.0, 0.0, 12.0),
            Vector3::new(4.0, 4.0, 12.0),
        ])
    }

    #[test]
    fn segment_errors_table() {
        let p = square();
        // (segment, position, along, cross, depth)
        let cases = [
            (0, [1.0, 0.5], 1.0, 0.5, 10.5),
            (0, [2.0, -1.0], 2.0, -1.0, 11.0),
            (0, [-1.0, 0.0], -1.0, 0.0, 10.0),
            (1, [3.0, 1.0], 1.0, 1.0, 12.0),
            (1, [5.0, 2.0], 2.0, -1.0, 12.0),
        ];
        for (k, xy, along, cross, depth) in cases {
            let e = p.errors(k, &Vector2::new(xy[0], xy[1]));
            assert!((e.along - along).abs() < 1e-12, "{k} {xy:?}");
            assert!((e.cross - cross).abs() < 1e-12, "{k} {xy:?}");
            assert!((e.depth - depth).abs() < 1e-12, "{k} {xy:?}");
        }
        assert!((p.turn_angle(0) - core::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(p.turn_angle(1), 0.0);
    }

    #[test]
    fn follower_switches_near_the_waypoint() {
        let p = square();
        let cfg = GuidanceConfig::default();
        let mut f = PathFollower::new();
        assert_eq!(f.update(&p, &Vector2::new(3.0, 0.0), &cfg).segment, 0);
        assert_eq!(f.update(&p, &Vector2::new(3.95, 0.1), &cfg).segment, 1);
        assert!(!f.finished);
        f.update(&p, &Vector2::new(4.0, 3.95), &cfg);
        assert!(f.finished);
    }

    #[test]
    fn corner_speed_keeps_the_arc_near_the_vertex() {
        let cfg = GuidanceConfig::default();
        assert_eq!(cfg.corner_speed(0.0), cfg.cruise_speed);
        for deg in [30.0f64, 60.0, 90.0, 120.0] {
            let a = deg.to_radians();
            let u = cfg.corner_speed(a);
            let rho = cfg.turning_radius(u);
            let miss = rho * (1.0 / (0.5 * a).cos() - 1.0);
            assert!(
                miss <= cfg.corner_deviation + 1e-12 || u == cfg.min_speed,
                "{deg}"
            );
        }
        // Speed profile never exceeds cruise and reaches the corner speed at the vertex.
        let p = square();
        assert!(
            (cfg.speed(&p, 0, p.errors(0, &Vector2::zeros()).length)
                - cfg.corner_speed(p.turn_angle(0)))
            .abs()
                < 1e-12
        );
        assert!(cfg.speed(&p, 0, 0.0) <= cfg.cruise_speed);
    }
}
