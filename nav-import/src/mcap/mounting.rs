//! Sensor mountings from `/tf_static`: the chain of static transforms from a
//! sensor's `header.frame_id` to the vehicle's body frame, composed, as the
//! rotation of the sensor's vectors into the body frame and its position.
//!
//! A transform `parent -> child` of `tf2_msgs/TFMessage` says
//! `p_parent = R(q) p_child + t` (REP-103 frames, forward-left-up). Both the
//! sensor's frame and the body frame are walked up to the root of their
//! tree; the two chains give `T_body_sensor = T_root_body^-1 T_root_sensor`
//! (so a sensor may hang from a sibling of the body frame). The result is
//! given in the log's forward-right-down axes: `B R B` and `B t`, with
//! `B = diag(1, -1, -1)`.

use std::collections::{HashMap, HashSet};

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// A rotation whose squared norm is further than this from 1 is refused
/// (tf2's own tolerance for a transform it accepts); closer, it is
/// normalised.
const NORM_SQUARED_TOLERANCE: f64 = 1e-2;
/// A norm further than this from 1 is normalised with a warning.
const NORM_WARNING: f64 = 1e-9;
/// A translation component beyond this, m, is absurd for a mounting (the
/// log format's limit for a lever arm).
pub const MAX_TRANSLATION_M: f64 = 1000.0;
/// Longest chain walked (a tree deeper than this is refused as a cycle
/// would be).
const MAX_DEPTH: usize = 64;

/// One static transform as read, and where it was read.
#[derive(Debug, Clone)]
pub struct Transform {
    /// Parent frame id.
    pub parent: String,
    /// Translation of the child's origin in the parent, m (FLU).
    pub translation: [f64; 3],
    /// Rotation child -> parent, quaternion x, y, z, w.
    pub rotation: [f64; 4],
    /// Topic the transform came on.
    pub topic: String,
    /// Index of its message on that topic.
    pub index: u64,
}

/// Where a sensor's frame sits in the body frame, in FRD axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mount {
    /// Rotation sensor FRD -> body FRD.
    pub rotation: Matrix3<f64>,
    /// Position of the sensor frame's origin in the body frame, FRD, m.
    pub translation: Vector3<f64>,
}

impl Mount {
    /// The identity: the sensor is the body frame.
    pub fn identity() -> Self {
        Mount {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// `v` (sensor FRD) in the body frame (FRD).
    pub fn rotate(&self, v: [f64; 3]) -> [f64; 3] {
        let r = self.rotation * Vector3::from(v);
        [r[0], r[1], r[2]]
    }

    /// Whether the rotation is the identity (to rounding).
    pub fn is_unrotated(&self) -> bool {
        (self.rotation - Matrix3::identity()).amax() < 1e-12
    }
}

/// A transform that cannot be used, naming where it was read.
#[derive(Debug, Clone, PartialEq)]
pub struct MountError {
    /// Topic of the transform.
    pub topic: String,
    /// Index of its message on that topic.
    pub index: u64,
    /// What is wrong.
    pub reason: String,
}

/// How a frame was resolved.
#[derive(Debug, Clone, PartialEq)]
pub enum Resolved {
    /// The frame is connected to the body frame.
    Mounted(Mount),
    /// The frame is not connected to the body frame: its tree's root.
    Unconnected {
        /// Root of the frame's own chain.
        root: String,
    },
}

/// The static transforms of a bag, child frame -> transform (the last one
/// read for a child wins, as in tf2).
#[derive(Debug, Clone, Default)]
pub struct Tree {
    transforms: HashMap<String, Transform>,
    /// Transforms normalised on use: (topic, index, norm).
    pub normalised: Vec<(String, u64, f64)>,
}

/// A frame id without a leading `/` (ROS 1 style ids in ROS 2 bags).
pub fn frame_name(id: &str) -> &str {
    id.strip_prefix('/').unwrap_or(id)
}

/// FLU <-> FRD axes.
fn flip() -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0))
}

impl Tree {
    /// Records `child`'s transform.
    pub fn insert(&mut self, child: &str, transform: Transform) {
        self.transforms
            .insert(frame_name(child).to_string(), transform);
    }

    /// Whether `frame` appears in the tree, as a child or a parent.
    pub fn contains(&self, frame: &str) -> bool {
        let frame = frame_name(frame);
        self.transforms.contains_key(frame)
            || self
                .transforms
                .values()
                .any(|t| frame_name(&t.parent) == frame)
    }

    /// Where the transform of child `frame` was read: (topic, index).
    pub fn source(&self, frame: &str) -> Option<(&str, u64)> {
        self.transforms
            .get(frame_name(frame))
            .map(|t| (t.topic.as_str(), t.index))
    }

    /// Whether no transform was read.
    pub fn is_empty(&self) -> bool {
        self.transforms.is_empty()
    }

    /// Rotation and translation of one transform (FLU), checked.
    fn checked(
        &mut self,
        child: &str,
        t: &Transform,
    ) -> Result<(Matrix3<f64>, Vector3<f64>), MountError> {
        let err = |reason: String| MountError {
            topic: t.topic.clone(),
            index: t.index,
            reason: format!("transform `{}` -> `{child}`: {reason}", t.parent),
        };
        let [x, y, z, w] = t.rotation;
        let norm2 = x * x + y * y + z * z + w * w;
        if !norm2.is_finite() || (norm2 - 1.0).abs() > NORM_SQUARED_TOLERANCE {
            return Err(err(format!(
                "rotation ({x}, {y}, {z}, {w}) has norm {:.6}: a unit quaternion expected",
                norm2.sqrt()
            )));
        }
        if let Some(v) = t
            .translation
            .iter()
            .find(|v| !v.is_finite() || v.abs() > MAX_TRANSLATION_M)
        {
            return Err(err(format!(
                "translation component {v}: finite and within {MAX_TRANSLATION_M} m expected for a mounting"
            )));
        }
        let norm = norm2.sqrt();
        if (norm - 1.0).abs() > NORM_WARNING
            && !self
                .normalised
                .iter()
                .any(|(topic, index, _)| *topic == t.topic && *index == t.index)
        {
            self.normalised.push((t.topic.clone(), t.index, norm));
        }
        let q = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
        Ok((
            *q.to_rotation_matrix().matrix(),
            Vector3::from(t.translation),
        ))
    }

    /// `frame` walked up to its root: (root, R_root_frame, t_root_frame), FLU.
    fn chain_to_root(
        &mut self,
        frame: &str,
    ) -> Result<(String, Matrix3<f64>, Vector3<f64>), MountError> {
        let mut r = Matrix3::identity();
        let mut t = Vector3::zeros();
        let mut current = frame_name(frame).to_string();
        let mut seen: HashSet<String> = HashSet::new();
        seen.insert(current.clone());
        while let Some(transform) = self.transforms.get(&current).cloned() {
            let (rp, tp) = self.checked(&current, &transform)?;
            r = rp * r;
            t = rp * t + tp;
            let parent = frame_name(&transform.parent).to_string();
            if !seen.insert(parent.clone()) || seen.len() > MAX_DEPTH {
                return Err(MountError {
                    topic: transform.topic.clone(),
                    index: transform.index,
                    reason: format!(
                        "transform `{parent}` -> `{current}` closes a cycle of frames (from `{}`): a tree expected",
                        frame_name(frame)
                    ),
                });
            }
            current = parent;
        }
        Ok((current, r, t))
    }

    /// Where `frame` sits in `body` (FRD).
    ///
    /// # Errors
    /// A transform on either chain that is a cycle, a rotation that is not
    /// one, or a translation that is not finite or absurd.
    pub fn resolve(&mut self, frame: &str, body: &str) -> Result<Resolved, MountError> {
        if frame_name(frame) == frame_name(body) {
            return Ok(Resolved::Mounted(Mount::identity()));
        }
        let (root_s, r_s, t_s) = self.chain_to_root(frame)?;
        let (root_b, r_b, t_b) = self.chain_to_root(body)?;
        if root_s != root_b {
            return Ok(Resolved::Unconnected { root: root_s });
        }
        let r = r_b.transpose() * r_s;
        let t = r_b.transpose() * (t_s - t_b);
        let b = flip();
        Ok(Resolved::Mounted(Mount {
            rotation: b * r * b,
            translation: b * t,
        }))
    }
}
