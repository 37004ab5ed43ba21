//! Path planning among the capsules of a [`Structure`]: RRT-Connect (Kuffner &
//! LaValle, ICRA 2000) between consecutive inspection waypoints, then random
//! shortcutting. Every edge, in the trees and in the shortcut path, is checked
//! exactly (segment-to-capsule distance against the inflated radius), not only
//! its end points, and must respect the vehicle's climb limit `|dz| <= s |dxy|`
//! (the heave thrusters are weaker than the horizontal ones, and a horizontal
//! course stays defined on every leg).

use std::time::Instant;

use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::structure::Structure;

/// Planner settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RrtConfig {
    /// Clearance added to every capsule radius (vehicle radius plus margin), m.
    pub inflation: f64,
    /// Tree extension step, m.
    pub step: f64,
    /// Largest `|dz| / |dxy|` of an edge.
    pub max_slope: f64,
    /// Iterations (samples) per waypoint pair before giving up.
    pub max_iterations: usize,
    /// Shortcut attempts per waypoint pair.
    pub shortcut_attempts: usize,
}

impl Default for RrtConfig {
    fn default() -> Self {
        Self {
            inflation: 0.6,
            step: 0.8,
            max_slope: 1.0,
            max_iterations: 20_000,
            shortcut_attempts: 150,
        }
    }
}

/// A planned path through all waypoints.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// Vertices, starting at the first waypoint and ending at the last.
    pub path: Vec<Vector3<f64>>,
    /// Wall-clock planning time, s.
    pub time_s: f64,
    /// Tree nodes created over all waypoint pairs.
    pub nodes: usize,
}

/// Why planning failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PlanError {
    /// A waypoint is not in free space.
    #[error("waypoint {index} at {point:?} is not in free space")]
    WaypointBlocked {
        /// Index of the waypoint.
        index: usize,
        /// Its position.
        point: [f64; 3],
    },
    /// No path found within the iteration budget.
    #[error("no path from waypoint {from} to {} within {iterations} iterations", from + 1)]
    NotFound {
        /// Index of the start waypoint of the failed pair.
        from: usize,
        /// The budget.
        iterations: usize,
    },
}

/// Whether the edge `p`-`q` is admissible: clear of the inflated capsules, inside
/// the planning space and within the climb limit.
pub fn edge_ok(s: &Structure, p: &Vector3<f64>, q: &Vector3<f64>, cfg: &RrtConfig) -> bool {
    let d = q - p;
    let horizontal = (d.x * d.x + d.y * d.y).sqrt();
    d.z.abs() <= cfg.max_slope * horizontal + 1e-9 && s.segment_free(p, q, cfg.inflation)
}

/// Plans through `waypoints` in order with RRT-Connect and shortcutting; the run is
/// a pure function of `seed`.
///
/// # Errors
/// [`PlanError`] if a waypoint is blocked or a pair cannot be connected.
pub fn plan_through(
    s: &Structure,
    waypoints: &[Vector3<f64>],
    cfg: &RrtConfig,
    seed: u64,
) -> Result<Plan, PlanError> {
    let start = Instant::now();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for (index, w) in waypoints.iter().enumerate() {
        if !s.point_free(w, cfg.inflation) {
            return Err(PlanError::WaypointBlocked {
                index,
                point: [w.x, w.y, w.z],
            });
        }
    }
    let mut path: Vec<Vector3<f64>> = waypoints.iter().take(1).copied().collect();
    let mut nodes = 0;
    for (from, pair) in waypoints.windows(2).enumerate() {
        let (raw, n) =
            rrt_connect(s, &pair[0], &pair[1], cfg, &mut rng).ok_or(PlanError::NotFound {
                from,
                iterations: cfg.max_iterations,
            })?;
        nodes += n;
        let short = shortcut(s, raw, cfg, &mut rng);
        path.extend_from_slice(&short[1..]);
    }
    Ok(Plan {
        path,
        time_s: start.elapsed().as_secs_f64(),
        nodes,
    })
}

/// A tree of points with parent links.
struct Tree {
    points: Vec<Vector3<f64>>,
    parent: Vec<usize>,
}

impl Tree {
    fn new(root: Vector3<f64>) -> Self {
        Self {
            points: vec![root],
            parent: vec![0],
        }
    }
    fn nearest(&self, p: &Vector3<f64>) -> usize {
        let mut best = (f64::INFINITY, 0);
        for (i, q) in self.points.iter().enumerate() {
            let d = (q - p).norm_squared();
            if d < best.0 {
                best = (d, i);
            }
        }
        best.1
    }
    fn add(&mut self, p: Vector3<f64>, parent: usize) -> usize {
        self.points.push(p);
        self.parent.push(parent);
        self.points.len() - 1
    }
    /// Points from the root to node `i`.
    fn branch(&self, mut i: usize) -> Vec<Vector3<f64>> {
        let mut out = vec![self.points[i]];
        while i != 0 {
            i = self.parent[i];
            out.push(self.points[i]);
        }
        out.reverse();
        out
    }
}

enum Extend {
    Reached(usize),
    Advanced(usize),
    Trapped,
}

fn extend(t: &mut Tree, target: &Vector3<f64>, s: &Structure, cfg: &RrtConfig) -> Extend {
    let near = t.nearest(target);
    let from = t.points[near];
    let d = target - from;
    let dist = d.norm();
    let (to, reached) = if dist <= cfg.step {
        (*target, true)
    } else {
        (from + d * (cfg.step / dist), false)
    };
    if !edge_ok(s, &from, &to, cfg) {
        return Extend::Trapped;
    }
    let i = t.add(to, near);
    if reached {
        Extend::Reached(i)
    } else {
        Extend::Advanced(i)
    }
}

/// RRT-Connect from `a` to `b`: the path and the number of tree nodes, or `None`.
pub fn rrt_connect<R: Rng>(
    s: &Structure,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    cfg: &RrtConfig,
    rng: &mut R,
) -> Option<(Vec<Vector3<f64>>, usize)> {
    if edge_ok(s, a, b, cfg) {
        return Some((vec![*a, *b], 2));
    }
    let mut ta = Tree::new(*a);
    let mut tb = Tree::new(*b);
    let mut swapped = false;
    let (lo, hi) = (s.bounds.min, s.bounds.max);
    for _ in 0..cfg.max_iterations {
        let sample = Vector3::new(
            rng.random_range(lo.x..hi.x),
            rng.random_range(lo.y..hi.y),
            rng.random_range(lo.z..hi.z),
        );
        let new = match extend(&mut ta, &sample, s, cfg) {
            Extend::Trapped => None,
            Extend::Reached(i) | Extend::Advanced(i) => Some(i),
        };
        if let Some(i) = new {
            let target = ta.points[i];
            // Connect: extend the other tree towards the new point until blocked.
            loop {
                match extend(&mut tb, &target, s, cfg) {
                    Extend::Advanced(_) => continue,
                    Extend::Trapped => break,
                    Extend::Reached(j) => {
                        let mut first = ta.branch(i);
                        let mut second = tb.branch(j);
                        second.reverse();
                        first.extend_from_slice(&second[1..]);
                        if swapped {
                            first.reverse();
                        }
                        let n = ta.points.len() + tb.points.len();
                        return Some((first, n));
                    }
                }
            }
        }
        core::mem::swap(&mut ta, &mut tb);
        swapped = !swapped;
    }
    None
}

/// Random shortcutting: replaces the vertices between two random vertices by a
/// straight edge whenever that edge is admissible, then a greedy pass from the start.
pub fn shortcut<R: Rng>(
    s: &Structure,
    mut path: Vec<Vector3<f64>>,
    cfg: &RrtConfig,
    rng: &mut R,
) -> Vec<Vector3<f64>> {
    for _ in 0..cfg.shortcut_attempts {
        if path.len() < 3 {
            break;
        }
        let i = rng.random_range(0..path.len() - 2);
        let j = rng.random_range(i + 2..path.len());
        if edge_ok(s, &path[i], &path[j], cfg) {
            path.drain(i + 1..j);
        }
    }
    // Greedy: from each kept vertex, jump to the farthest directly reachable one.
    let mut out = vec![path[0]];
    let mut i = 0;
    while i + 1 < path.len() {
        let mut j = path.len() - 1;
        while j > i + 1 && !edge_ok(s, &path[i], &path[j], cfg) {
            j -= 1;
        }
        out.push(path[j]);
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
        Vector3::new(x, y, z)
    }

    /// Waypoints from one long face, over the top, and through the inside.
    fn waypoints() -> Vec<Vector3<f64>> {
        vec![
            v(-3.5, 2.4, 14.0),
            v(3.5, 2.4, 14.0),
            v(0.0, -2.4, 11.0),
            v(3.7, 0.0, 16.0),
            v(-3.7, 0.0, 16.0),
        ]
    }

    #[test]
    fn edges_never_intersect_inflated_capsules() {
        let s = Structure::test_jacket();
        let cfg = RrtConfig::default();
        for seed in 0..60 {
            let plan = plan_through(&s, &waypoints(), &cfg, seed).expect("plans");
            assert_eq!(plan.path[0], waypoints()[0]);
            assert_eq!(*plan.path.last().unwrap(), *waypoints().last().unwrap());
            for e in plan.path.windows(2) {
                assert!(edge_ok(&s, &e[0], &e[1], &cfg), "seed {seed}: edge {e:?}");
                // Independent check by dense sampling along the edge.
                for k in 0..=100 {
                    let p = e[0] + (e[1] - e[0]) * (k as f64 / 100.0);
                    for c in &s.capsules {
                        assert!(c.axis_distance(&p) > c.radius + cfg.inflation - 1e-9);
                    }
                    assert!(s.bounds.contains(&p));
                }
            }
        }
    }

    #[test]
    fn edge_check_catches_thin_obstacles_between_free_ends() {
        let s = Structure::test_jacket();
        let cfg = RrtConfig::default();
        // Both ends free, the straight line cuts the +y mid-depth brace.
        let (p, q) = (v(0.0, 2.4, 15.0), v(0.0, 0.0, 17.0));
        assert!(s.point_free(&p, cfg.inflation) && s.point_free(&q, cfg.inflation));
        assert!(!edge_ok(&s, &p, &q, &cfg));
        // Too steep although free.
        assert!(!edge_ok(&s, &v(0.0, 0.0, 14.0), &v(0.0, 0.2, 17.0), &cfg));
    }

    #[test]
    fn blocked_waypoint_is_an_error() {
        let s = Structure::test_jacket();
        let w = [v(3.0, 1.4, 16.0), v(0.0, 0.0, 16.0)];
        assert!(matches!(
            plan_through(&s, &w, &RrtConfig::default(), 1),
            Err(PlanError::WaypointBlocked { index: 0, .. })
        ));
    }
}
