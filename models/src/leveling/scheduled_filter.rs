//! The leveling filter as the multi-rate scheduler runs it
//! (`nav_runtime::scheduler`, the scheduler every replay uses): the EKF of a
//! leveling model, the yaw it carries for the Earth-rate input, and, when
//! the run is recorded, the recorder. Propagated by IMU samples, each held
//! over the interval that follows it (the paper's filter integrates the
//! previous sample, eq. 15-17 of docs/models/leveling6.md); corrected by the
//! speed log or the zero-velocity pseudo-measurement at their own times.
//! Everything a step changes is in the value, so the scheduler's checkpoints
//! and re-propagation after a late row see the same history.

use nav_ins::ImuSample;
use nav_runtime::attitude::Euler;
use nav_runtime::ekf::{Ekf, FilterError, Propagate, UpdateReport};
use nav_runtime::innovations::InnovationStatistics;
use nav_runtime::math::wrap_angle;
use nav_runtime::model::{Model, Record, Sensor};
use nav_runtime::nalgebra::{SMatrix, SVector, Vector3};
use nav_runtime::scheduler::MeasurementOutcome;
use nav_runtime::smoother::Recorder;

use super::filter::{roll_pitch, LevelingModel};

/// A leveling model's filter with its yaw and recording.
pub struct LevelingFilter<M: LevelingModel<N>, const N: usize> {
    /// The EKF of the model.
    pub ekf: Ekf<M, N>,
    /// Yaw integrated from the gyro (not estimated), rad: it turns the Earth
    /// rate into body axes (eq. 16).
    pub yaw: f64,
    /// Earth rate in NED at the log's latitude, rad/s.
    earth_rate_n: Vector3<f64>,
    /// Reflect `a3 < 0` after each speed-log update (the vehicle is upright).
    upright: bool,
    /// The recorder of the run, when recorded; each epoch's snapshot is
    /// the state, so that the smoother can correct it.
    pub recorder: Option<Recorder<N, N>>,
}

impl<M: LevelingModel<N>, const N: usize> Clone for LevelingFilter<M, N> {
    fn clone(&self) -> Self {
        LevelingFilter {
            ekf: self.ekf.clone(),
            yaw: self.yaw,
            earth_rate_n: self.earth_rate_n,
            upright: self.upright,
            recorder: self.recorder.clone(),
        }
    }

    /// Part by part into `self`: a scheduler checkpoint copies no
    /// recorder work space.
    fn clone_from(&mut self, source: &Self) {
        self.ekf.clone_from(&source.ekf);
        self.yaw = source.yaw;
        self.earth_rate_n = source.earth_rate_n;
        self.upright = source.upright;
        self.recorder.clone_from(&source.recorder);
    }
}

impl<M: LevelingModel<N>, const N: usize> LevelingFilter<M, N> {
    /// `ekf` starting at yaw `yaw` (rad) with the Earth rate `earth_rate_n`
    /// (NED, rad/s).
    pub fn new(
        ekf: Ekf<M, N>,
        yaw: f64,
        earth_rate_n: Vector3<f64>,
        upright: bool,
        recorder: Option<Recorder<N, N>>,
    ) -> Self {
        LevelingFilter {
            ekf,
            yaw,
            earth_rate_n,
            upright,
            recorder,
        }
    }

    /// The update of sensor `S`, recorded (the covariance before and
    /// after, the correction, and its information) when recording; with
    /// `reflect`, an upright vehicle's mirror solution is reflected after it.
    ///
    /// # Errors
    /// As [`Ekf::update`]; the filter is unchanged on error.
    pub fn update<S, const K: usize>(
        &mut self,
        z: &SVector<f64, K>,
        r: &SMatrix<f64, K, K>,
        reflect: bool,
    ) -> Result<MeasurementOutcome, FilterError>
    where
        S: Sensor<N, K, Model = M, Aux = ()>,
    {
        let report = self.recorded_update::<S, K>(z, r)?;
        if reflect && self.upright {
            keep_upright(&mut self.ekf)?;
        }
        Ok(MeasurementOutcome::from(&report))
    }

    /// The update of the speed log and unit norm ([`LevelingModel::Moving`],
    /// noise `r`) as [`LevelingFilter::update`] does it, with the
    /// statistics of the speed's own innovation (its row of `nu`, `S` and
    /// `R`): what its NIS and noise tuning read (docs/tuning.md, eq. T3).
    /// The unit norm is a constraint, not a sensor: its innovation says
    /// nothing about the speed log.
    ///
    /// # Errors
    /// As [`Ekf::update`]; the filter is unchanged on error.
    pub fn update_speed(
        &mut self,
        z: &SVector<f64, 2>,
        r: &SMatrix<f64, 2, 2>,
    ) -> Result<MeasurementOutcome, FilterError> {
        let report = self.recorded_update::<M::Moving, 2>(z, r)?;
        if self.upright {
            keep_upright(&mut self.ekf)?;
        }
        let mut outcome = MeasurementOutcome::from(&report);
        outcome.statistics = InnovationStatistics::of(
            &SVector::<f64, 1>::new(report.innovation[0]),
            &SMatrix::<f64, 1, 1>::new(report.innovation_covariance[(0, 0)]),
            &SMatrix::<f64, 1, 1>::new(r[(0, 0)]),
        );
        Ok(outcome)
    }

    /// An epoch of the recording at `t` (s, the filter's time), when
    /// recording: the smoother gives the state here a smoothed counterpart.
    pub fn mark_epoch(&mut self, t: f64) {
        if let Some(rec) = self.recorder.as_mut() {
            rec.mark(t, self.ekf.covariance(), *self.ekf.state());
        }
    }

    fn recorded_update<S, const K: usize>(
        &mut self,
        z: &SVector<f64, K>,
        r: &SMatrix<f64, K, K>,
    ) -> Result<UpdateReport<K>, FilterError>
    where
        S: Sensor<N, K, Model = M, Aux = ()>,
    {
        let Some(rec) = self.recorder.as_mut() else {
            return self.ekf.update::<S, K>(z, r, &());
        };
        let ekf = &mut self.ekf;
        let (x, p) = (*ekf.state(), *ekf.covariance());
        let h = S::jacobian(&x, ekf.input(), ekf.params(), &());
        let report = ekf.update::<S, K>(z, r, &())?;
        if report.accepted {
            rec.updating(&p, x);
            rec.updated(&(x - ekf.state()), ekf.covariance(), *ekf.state());
            if let Some(c) = r.cholesky() {
                rec.sensor_update(S::NAME, &h, &c.inverse());
            }
        }
        Ok(report)
    }
}

impl<M: LevelingModel<N>, const N: usize> Propagate for LevelingFilter<M, N> {
    type Input = ImuSample;

    fn check_input(imu: &ImuSample) -> Result<(), FilterError> {
        match (0..ImuSample::LEN).find(|&i| !imu.get(i).is_finite()) {
            Some(index) => Err(FilterError::NonFiniteInput {
                index,
                name: ImuSample::NAMES[index],
            }),
            None => Ok(()),
        }
    }

    /// The model's input from the sample and the Earth rate in body axes at
    /// the attitude estimated now (eq. 16), then the step, then the yaw.
    fn propagate(&mut self, dt: f64, imu: &ImuSample) -> Result<(), FilterError> {
        let x = *self.ekf.state();
        let (roll, pitch) = roll_pitch(&Vector3::new(x[3], x[4], x[5]));
        let earth_rate_body = Euler::new(roll, pitch, self.yaw).c_nb() * self.earth_rate_n;
        let input = M::input(imu.gyro, imu.accel, earth_rate_body);
        self.ekf.predict(dt, &input)?;
        if let Some(rec) = self.recorder.as_mut() {
            rec.propagated::<M>(&M::jacobian(&x, &input, self.ekf.params(), dt), dt);
        }
        let w = imu.gyro - earth_rate_body;
        self.yaw = wrap_angle(self.yaw + dt * (w.y * roll.sin() + w.z * roll.cos()) / pitch.cos());
        Ok(())
    }
}

/// Reflects `a3 -> -a3` (and its covariance row and column) when `a3 < 0`.
///
/// # Errors
/// The reflected state or covariance is refused by the filter.
pub fn keep_upright<M: Model<N>, const N: usize>(ekf: &mut Ekf<M, N>) -> Result<(), FilterError> {
    let mut x = *ekf.state();
    if x[5] >= 0.0 {
        return Ok(());
    }
    x[5] = -x[5];
    let mut p = *ekf.covariance();
    for i in 0..N {
        if i != 5 {
            p[(i, 5)] = -p[(i, 5)];
            p[(5, i)] = -p[(5, i)];
        }
    }
    ekf.set_state(x)?;
    Ok(ekf.set_covariance(p)?)
}
