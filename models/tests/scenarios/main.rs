//! The papers' crate through its public API: the navigator, the replays of
//! logs and declared models, calibration, preflight, tuning and the op-count
//! baseline, one file each. One test binary, each file a module of it, so
//! that the suite compiles and links the models once instead of once per
//! file. (`replay_allocations.rs` stays a binary of its own: it counts the
//! allocations of its whole process.)

mod turning_flight;

mod ahrs_same_epoch_nees;
mod ahrs_smoothing;
mod ahrs_tuning;
mod constant_states;
mod dvl_calibration;
mod gnss_ins_smoothing;
mod log_replay;
mod model_replay;
mod navigator;
mod navigator_lockout;
mod navigator_vehicle;
mod op_counts;
mod preflight;
mod preflight_mapped;
mod px4_rotation_matrix;
mod usbl_calibration;
