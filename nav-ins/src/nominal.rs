//! The nominal solution of an INS vehicle (strapdown plus running sensor
//! corrections), the IMU sample it is driven by, and the estimate read from
//! its error-state filter. The error-state convention (navigation errors =
//! INS minus true, subtracted by the feedback; sensor errors added to the
//! running corrections) is the one of `docs/pipeline.md`, section "Error states".

use std::marker::PhantomData;

use nav_runtime::earth::{meridian_radius, transverse_radius};
use nav_runtime::error_state::{ErrorStateFilter, Mechanization, NominalState};
use nav_runtime::model::Record;
use nav_runtime::nalgebra::{Matrix3, SMatrix, SVector, Vector2, Vector3};
use nav_runtime::smoother::States;
use nav_runtime::strapdown::{NavError, NavState, Strapdown};

use super::vehicle::{InsVehicle, Layout};
use crate::navigator::NavigatorError;

/// The error-state filter of vehicle `V` (`N` states).
pub type InsFilter<V, const N: usize> = ErrorStateFilter<V, InsNominal<V, N>, N>;

/// One IMU sample as the scheduler holds it: body rate (rad/s) and specific
/// force (m/s^2), before the bias corrections.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImuSample {
    /// Gyro output.
    pub gyro: Vector3<f64>,
    /// Accelerometer output.
    pub accel: Vector3<f64>,
}

impl Record for ImuSample {
    const LEN: usize = 6;
    const NAMES: &'static [&'static str] = &["gx", "gy", "gz", "ax", "ay", "az"];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        Self {
            gyro: Vector3::new(f(0), f(1), f(2)),
            accel: Vector3::new(f(3), f(4), f(5)),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0..=2 => self.gyro[i],
            3..=5 => self.accel[i - 3],
            _ => f64::NAN,
        }
    }
}

/// The nominal solution of vehicle `V`: strapdown INS plus the running
/// sensor corrections (those of sensors `V` lacks stay zero).
pub struct InsNominal<V, const N: usize> {
    /// The strapdown INS.
    pub ins: Strapdown,
    /// Accelerometer bias correction, subtracted from the samples (m/s^2).
    pub accel_bias: Vector3<f64>,
    /// Gyro bias correction, subtracted from the samples (rad/s).
    pub gyro_bias: Vector3<f64>,
    /// USBL horizontal bias correction (m, N/E).
    pub usbl_bias: Vector2<f64>,
    /// Depth-meter bias correction (m, height convention: `h_meas = h + b`).
    pub depth_bias: f64,
    /// DVL bias correction (m/s, body).
    pub dvl_bias: Vector3<f64>,
    /// Compass bias correction (rad).
    pub compass_bias: f64,
    /// USBL misalignment correction (rad).
    pub usbl_misalignment: Vector3<f64>,
    /// Barometer bias correction (m: barometric altitude minus height).
    pub baro_bias: f64,
    /// Bias-corrected body rate of the IMU sample being integrated (rad/s):
    /// the `omega` of a sensor's `omega x r` lever-arm velocity.
    pub body_rate: Vector3<f64>,
    /// Bias-corrected specific force of that sample (m/s^2).
    pub specific_force: Vector3<f64>,
    /// The innovation of the latest DVL reading (m/s) and the filter's
    /// clock at it (s): its growth to the next reading is the tilt of a
    /// recovery's eq. R3 (docs/lockout.md).
    pub dvl_innovation: Option<(f64, Vector3<f64>)>,
    /// The position error (NED, m) the velocity errors seen by the DVL's
    /// refused readings since its last accepted one have built: the
    /// innovation, in NED, integrated between readings. A
    /// recovery adds it to the position covariance (eq. R4 of
    /// docs/lockout.md); an accepted reading sets it to zero.
    pub dvl_refused_drift: Vector3<f64>,
    /// Where `V` keeps each error state.
    layout: Layout,
    /// Per error state: kept by this nominal ([`Layout::absorbed`]).
    absorbed: [bool; N],
    /// Every error state kept (no state of a block the nominal does not know).
    absorbs_all: bool,
    vehicle: PhantomData<fn() -> V>,
}

// By hand: a derive would ask `V: Copy` of the vehicle marker. A copy is
// one block move (the error-state filter keeps one before every step).
impl<V, const N: usize> Clone for InsNominal<V, N> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<V, const N: usize> Copy for InsNominal<V, N> {}

impl<V, const N: usize> core::fmt::Debug for InsNominal<V, N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("InsNominal")
            .field("ins", &self.ins)
            .field("accel_bias", &self.accel_bias)
            .field("gyro_bias", &self.gyro_bias)
            .field("usbl_bias", &self.usbl_bias)
            .field("depth_bias", &self.depth_bias)
            .field("dvl_bias", &self.dvl_bias)
            .field("compass_bias", &self.compass_bias)
            .field("usbl_misalignment", &self.usbl_misalignment)
            .field("baro_bias", &self.baro_bias)
            .field("body_rate", &self.body_rate)
            .field("specific_force", &self.specific_force)
            .field("dvl_innovation", &self.dvl_innovation)
            .field("dvl_refused_drift", &self.dvl_refused_drift)
            .field("layout", &self.layout)
            .finish()
    }
}

impl<V: InsVehicle<N>, const N: usize> InsNominal<V, N> {
    /// A nominal solution at `state` with zero corrections.
    ///
    /// # Panics
    /// If `V` does not fit the replay loop ([`Layout::of`] fails); use
    /// [`InsNominal::try_new`] to get the error.
    pub fn new(ins: Strapdown) -> Self {
        match Self::try_new(ins) {
            Ok(n) => n,
            Err(e) => panic!("{e}"),
        }
    }

    /// A nominal solution at `state` with zero corrections.
    ///
    /// # Errors
    /// As [`Layout::of`].
    pub fn try_new(ins: Strapdown) -> Result<Self, NavigatorError> {
        let layout = Layout::of::<V, N>()?;
        Ok(Self {
            ins,
            accel_bias: Vector3::zeros(),
            gyro_bias: Vector3::zeros(),
            usbl_bias: Vector2::zeros(),
            depth_bias: 0.0,
            dvl_bias: Vector3::zeros(),
            compass_bias: 0.0,
            usbl_misalignment: Vector3::zeros(),
            baro_bias: 0.0,
            body_rate: Vector3::zeros(),
            specific_force: Vector3::zeros(),
            dvl_innovation: None,
            dvl_refused_drift: Vector3::zeros(),
            layout,
            absorbed: layout.absorbed(),
            absorbs_all: layout.absorbed::<N>().iter().all(|a| *a),
            vehicle: PhantomData,
        })
    }

    /// Where `V` keeps each error state.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
}

impl<V: InsVehicle<N>, const N: usize> NominalState<N> for InsNominal<V, N> {
    fn absorbs(&self, i: usize) -> bool {
        self.absorbed.get(i).copied().unwrap_or(true)
    }

    fn absorbs_all(&self) -> bool {
        self.absorbs_all
    }

    fn inject(&mut self, e: &SVector<f64, N>) {
        let l = &self.layout;
        let nav = l.navigation().map(|i| e[i]);
        self.ins.inject(&NavError::from_slice(&nav));
        let v3 = |i: usize| Vector3::new(e[i], e[i + 1], e[i + 2]);
        self.accel_bias += v3(l.accel_bias);
        self.gyro_bias += v3(l.gyro_bias);
        if let Some(i) = l.usbl_bias {
            self.usbl_bias += Vector2::new(e[i], e[i + 1]);
        }
        if let Some(i) = l.depth_bias {
            self.depth_bias += e[i];
        }
        if let Some(i) = l.dvl_bias {
            self.dvl_bias += v3(i);
        }
        if let Some(i) = l.compass_bias {
            self.compass_bias += e[i];
        }
        if let Some(i) = l.usbl_misalignment {
            self.usbl_misalignment += v3(i);
        }
        if let Some(i) = l.baro_bias {
            self.baro_bias += e[i];
        }
    }
}

impl<V: InsVehicle<N>, const N: usize> Mechanization<V, N> for InsNominal<V, N> {
    type Imu = ImuSample;
    fn mechanize(&mut self, dt: f64, imu: &ImuSample) -> V::Input {
        let w = imu.gyro - self.gyro_bias;
        let f = imu.accel - self.accel_bias;
        let input = Self::input_at(&self.ins.state, &f);
        self.body_rate = w;
        self.specific_force = f;
        self.ins.update_rates(&w, &f, dt);
        input
    }
}

impl<V: InsVehicle<N>, const N: usize> InsNominal<V, N> {
    /// The error model's input at this nominal solution as it stands (after
    /// every feedback so far), with the specific force of the latest
    /// sample: what the sensors read (`ErrorStateFilter::with_sensor_input`),
    /// so that readings of one epoch (a GNSS fix, a compass and a speed log)
    /// are each linearized about the solution the earlier ones corrected.
    pub fn sensor_input(&self) -> V::Input {
        Self::input_at(&self.ins.state, &self.specific_force)
    }

    /// The INS core's inputs in record order (checked by `Layout::of`).
    fn input_at(s: &NavState, f: &Vector3<f64>) -> V::Input {
        let c = &s.c_bn;
        let values: [f64; 17] = [
            s.lat,
            s.h,
            s.v_n.x,
            s.v_n.y,
            s.v_n.z,
            c[(0, 0)],
            c[(0, 1)],
            c[(0, 2)],
            c[(1, 0)],
            c[(1, 1)],
            c[(1, 2)],
            c[(2, 0)],
            c[(2, 1)],
            c[(2, 2)],
            f.x,
            f.y,
            f.z,
        ];
        <V::Input as Record>::from_fn(|i| values[i])
    }
}

/// The filter's estimate at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Time (s).
    pub t: f64,
    /// Corrected navigation solution.
    pub nav: NavState,
    /// Covariance of the 9 navigation errors with position in metres (N, E, D),
    /// velocity (m/s) and attitude (rad).
    pub cov: SMatrix<f64, 9, 9>,
    /// Compass bias estimate (rad) and its sigma.
    pub compass_bias: (f64, f64),
    /// USBL bias estimate (m, N) and its sigma.
    pub usbl_bias_n: (f64, f64),
    /// Barometer bias estimate (m) and its sigma.
    pub baro_bias: (f64, f64),
}

impl Estimate {
    /// The estimate of filter `f` at time `t`. A bias the vehicle does not
    /// estimate is reported as zero with a NaN sigma.
    pub fn of<V: InsVehicle<N>, const N: usize>(t: f64, f: &InsFilter<V, N>) -> Self {
        let n = f.nominal();
        Self::from_parts(
            t,
            n.ins.state,
            f.covariance(),
            n.layout(),
            n.compass_bias,
            n.usbl_bias[0],
            n.baro_bias,
        )
    }

    /// This (forward) estimate with the smoothed error `error` of its error
    /// state removed, and the smoothed error covariance `p` (the injection of
    /// [`InsNominal::inject`], applied to the estimate's parts).
    pub fn smoothed<const N: usize>(
        &self,
        error: &SVector<f64, N>,
        p: &SMatrix<f64, N, N>,
        layout: &Layout,
    ) -> Self {
        let nav = layout.navigation().map(|i| error[i]);
        let compass = layout.compass_bias.map_or(0.0, |i| error[i]);
        let usbl_n = layout.usbl_bias.map_or(0.0, |i| error[i]);
        let baro = layout.baro_bias.map_or(0.0, |i| error[i]);
        Self::from_parts(
            self.t,
            self.nav.corrected(&NavError::from_slice(&nav)),
            p,
            layout,
            self.compass_bias.0 + compass,
            self.usbl_bias_n.0 + usbl_n,
            self.baro_bias.0 + baro,
        )
    }

    /// The states whose smoothed covariance [`Estimate::smoothed`] reads
    /// (the navigation errors and the reported biases), for
    /// [`nav_runtime::smoother::smooth_states`].
    pub fn covariance_states<const N: usize>(layout: &Layout) -> States<N> {
        let mut chosen = [false; N];
        let biases = [layout.compass_bias, layout.usbl_bias, layout.baro_bias];
        for i in layout
            .navigation()
            .into_iter()
            .chain(biases.into_iter().flatten())
        {
            chosen[i] = true;
        }
        States::from_mask(chosen)
    }

    fn from_parts<const N: usize>(
        t: f64,
        nav: NavState,
        p: &SMatrix<f64, N, N>,
        layout: &Layout,
        compass_bias: f64,
        usbl_bias_n: f64,
        baro_bias: f64,
    ) -> Self {
        let idx = layout.navigation();
        let (rm, rn) = (
            meridian_radius(nav.lat) + nav.h,
            transverse_radius(nav.lat) + nav.h,
        );
        let mut scale = [1.0; 9];
        scale[0] = rm;
        scale[1] = rn * nav.lat.cos();
        scale[2] = -1.0;
        let cov = SMatrix::<f64, 9, 9>::from_fn(|i, j| scale[i] * p[(idx[i], idx[j])] * scale[j]);
        let sigma = |i: Option<usize>| i.map_or(f64::NAN, |i| p[(i, i)].sqrt());
        Self {
            t,
            nav,
            cov,
            compass_bias: (compass_bias, sigma(layout.compass_bias)),
            usbl_bias_n: (usbl_bias_n, sigma(layout.usbl_bias)),
            baro_bias: (baro_bias, sigma(layout.baro_bias)),
        }
    }
}

/// Scalars of an `Option<Estimate>` in a [`nav_runtime::smoother::SpillFile`]
/// record: a presence flag, the time, the solution (latitude, longitude,
/// height, velocity, attitude matrix), the covariance and the three biases
/// with their sigmas.
/// Scalars of an [`Estimate`] in its bit-exact form (the smoother's epoch file).
pub const ESTIMATE_SCALARS: usize = 1 + 1 + 3 + 3 + 9 + 81 + 6;

impl Estimate {
    /// `e` as [`ESTIMATE_SCALARS`] scalars, bit for bit.
    pub fn to_scalars(e: Option<&Estimate>) -> [f64; ESTIMATE_SCALARS] {
        let mut out = [0.0; ESTIMATE_SCALARS];
        let Some(e) = e else {
            return out;
        };
        let s = &e.nav;
        // Slice copies in the layout of `from_scalars` (a chain of
        // iterators here cost 50 instructions a scalar).
        out[..5].copy_from_slice(&[1.0, e.t, s.lat, s.lon, s.h]);
        out[5..8].copy_from_slice(s.v_n.as_slice());
        out[8..17].copy_from_slice(s.c_bn.as_slice());
        out[17..98].copy_from_slice(e.cov.as_slice());
        out[98..].copy_from_slice(&[
            e.compass_bias.0,
            e.compass_bias.1,
            e.usbl_bias_n.0,
            e.usbl_bias_n.1,
            e.baro_bias.0,
            e.baro_bias.1,
        ]);
        out
    }

    /// The estimate written by [`Estimate::to_scalars`].
    pub fn from_scalars(v: &[f64; ESTIMATE_SCALARS]) -> Option<Estimate> {
        if v[0] != 1.0 {
            return None;
        }
        let nav = NavState {
            lat: v[2],
            lon: v[3],
            h: v[4],
            v_n: Vector3::from_column_slice(&v[5..8]),
            c_bn: Matrix3::from_column_slice(&v[8..17]),
        };
        Some(Estimate {
            t: v[1],
            nav,
            cov: SMatrix::<f64, 9, 9>::from_column_slice(&v[17..98]),
            compass_bias: (v[98], v[99]),
            usbl_bias_n: (v[100], v[101]),
            baro_bias: (v[102], v[103]),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An estimate survives its spill-file record bit for bit; no estimate
    /// stays none.
    #[test]
    fn estimate_scalars_round_trip_bit_for_bit() {
        let e = Estimate {
            t: 12.3,
            nav: NavState {
                lat: 0.7,
                lon: -1.2,
                h: -40.5,
                v_n: Vector3::new(1.5, -0.2, 0.01),
                c_bn: Matrix3::from_fn(|r, c| (r * 3 + c) as f64 * 0.1 - 0.4),
            },
            cov: SMatrix::<f64, 9, 9>::from_fn(|r, c| 1e-3 * (r as f64 - 2.0 * c as f64)),
            compass_bias: (0.01, f64::NAN),
            usbl_bias_n: (-0.5, 0.25),
            baro_bias: (3.5, 0.125),
        };
        let back = Estimate::from_scalars(&Estimate::to_scalars(Some(&e))).unwrap();
        let bits = |e: &Estimate| Estimate::to_scalars(Some(e)).map(f64::to_bits);
        assert_eq!(bits(&back), bits(&e));
        assert_eq!(back.nav.c_bn, e.nav.c_bn);
        assert_eq!(back.cov, e.cov);
        assert!(Estimate::from_scalars(&Estimate::to_scalars(None)).is_none());
    }
}
