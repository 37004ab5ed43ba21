//! Replays of logs on disk: the streamed replay against the replay in
//! memory, IMU increments against rates, the USBL misalignment key. One test
//! binary (each links the whole `models` crate).

#[path = "log_replay/frozen_imu.rs"]
mod frozen_imu;
#[path = "log_replay/imu_increments.rs"]
mod imu_increments;
#[path = "log_replay/streaming.rs"]
mod streaming;
#[path = "log_replay/usbl_misalignment.rs"]
mod usbl_misalignment;
