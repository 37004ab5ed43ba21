//! The forward-pass side of the smoother: epochs into the epoch file.

use std::cell::RefCell;
use std::rc::Rc;

use nalgebra::{SMatrix, SVector};

use super::epoch::Epoch;
use super::sensor_information::SensorInformation;
use super::store::{EpochFile, SmootherError};
use crate::model::Model;

/// Records a forward run for [`super::smooth`].
///
/// Drive it beside the filter: [`Recorder::propagated`] for every prediction
/// step (with the step's Jacobian), [`Recorder::updating`] before the first
/// update at a time and [`Recorder::updated`] after each update,
/// [`Recorder::mark`] at a time an output is wanted without an update, and
/// [`Recorder::finish`] at the end. An epoch is written when the first
/// prediction after it starts (or at `finish`), so every update of one time
/// lands in one epoch. The recorder keeps the time itself (the start plus
/// every step) and [`Recorder::mark`] re-synchronizes it.
///
/// Recording never fails in the forward pass (so a filter's predict and
/// update keep their error contract): the first failure is kept and returned
/// by [`Recorder::finish`].
///
/// A clone shares the file but keeps its own history: cloned with a filter
/// checkpoint and resumed after a rollback, it truncates the file to the
/// epochs of its own history before writing, so the re-propagated span
/// replaces the old one.
#[derive(Debug)]
pub struct Recorder<const N: usize, const S: usize> {
    store: Rc<RefCell<EpochFile<N, S>>>,
    /// Epochs of this history already in the file.
    written: usize,
    /// Time now, s.
    time: f64,
    /// `Phi^T` from the last epoch to now: column `i` is row `i` of `Phi`,
    /// so a row is contiguous.
    rows: SMatrix<f64, N, N>,
    /// The epoch reached and not yet written.
    open: Option<Epoch<N, S>>,
    /// The first failure.
    failure: Option<Rc<str>>,
    /// Work space of [`Recorder::propagated`] (the change of each row of
    /// `Phi` in one step; no meaning between calls, not copied by clones).
    scratch: [[f64; N]; N],
    /// The coefficients of the step in progress ([`Recorder::stage`]), in a
    /// buffer reserved at the start ([`Recorder::reserve_stage`]); not copied
    /// by clones.
    staged: Vec<f64>,
    /// `true` while [`Recorder::staged`] holds the step in progress.
    staged_valid: bool,
    /// Each sensor's information about the start, when tracked
    /// ([`Recorder::track_sensor_information`]); part of the history, so a
    /// clone copies it.
    information: Option<Box<SensorInformation<N>>>,
}

impl<const N: usize, const S: usize> Clone for Recorder<N, S> {
    fn clone(&self) -> Self {
        Self {
            store: Rc::clone(&self.store),
            written: self.written,
            time: self.time,
            rows: self.rows,
            open: self.open,
            failure: self.failure.clone(),
            scratch: [[0.0; N]; N],
            staged: Vec::with_capacity(self.staged.capacity()),
            staged_valid: false,
            information: self.information.clone(),
        }
    }

    /// Field by field, without the work space: a checkpoint copy costs the
    /// recording's state only.
    fn clone_from(&mut self, source: &Self) {
        self.store.clone_from(&source.store);
        self.written = source.written;
        self.time = source.time;
        self.rows = source.rows;
        // Most checkpoints have no open epoch: then only the tag is written.
        match &source.open {
            None => self.open = None,
            Some(epoch) => match self.open.as_mut() {
                Some(open) => open.clone_from(epoch),
                None => self.open = Some(*epoch),
            },
        }
        self.failure.clone_from(&source.failure);
        // The stage buffer's capacity only (allocates once, if ever).
        self.staged.clear();
        self.staged.reserve_exact(source.staged.capacity());
        self.staged_valid = false;
        // In place: the box and its sensor list are reused.
        self.information.clone_from(&source.information);
    }
}

impl<const N: usize, const S: usize> Recorder<N, S> {
    /// Starts a recording at the filter's initial `time` (s), `covariance` and
    /// `snapshot`: the first epoch.
    pub fn new(
        store: EpochFile<N, S>,
        time: f64,
        covariance: &SMatrix<f64, N, N>,
        snapshot: SVector<f64, S>,
    ) -> Self {
        Self {
            store: Rc::new(RefCell::new(store)),
            written: 0,
            time,
            rows: SMatrix::identity(),
            open: Some(Epoch::at(time, SMatrix::identity(), *covariance, snapshot)),
            failure: None,
            scratch: [[0.0; N]; N],
            staged: Vec::new(),
            staged_valid: false,
            information: None,
        }
    }

    /// Keeps, from now on, the information each sensor's updates give about
    /// the state at the start ([`SensorInformation`]), fed by
    /// [`Recorder::sensor_update`]. Call it right after [`Recorder::new`],
    /// before any prediction step: the transition to the start is then the
    /// identity.
    pub fn track_sensor_information(&mut self) {
        self.information = Some(Box::new(SensorInformation::new()));
    }

    /// `true` when [`Recorder::track_sensor_information`] was called.
    pub fn tracks_sensor_information(&self) -> bool {
        self.information.is_some()
    }

    /// Each sensor's information about the start so far (`None` unless
    /// tracked).
    pub fn sensor_information(&self) -> Option<&SensorInformation<N>> {
        self.information.as_deref()
    }

    /// An accepted update of `sensor`, made with Jacobian `jacobian` and
    /// noise inverse `noise_inverse`, at the current time (call after
    /// [`Recorder::updating`]); nothing unless the information is tracked.
    /// No allocation.
    pub fn sensor_update<const M: usize>(
        &mut self,
        sensor: &'static str,
        jacobian: &SMatrix<f64, M, N>,
        noise_inverse: &SMatrix<f64, M, M>,
    ) {
        let Some(information) = self.information.as_deref_mut() else {
            return;
        };
        // After `updating` the steps since the epoch are the identity.
        if self.rows == SMatrix::<f64, N, N>::identity() {
            information.add(sensor, jacobian, noise_inverse, None);
        } else {
            let since = self.rows.transpose();
            information.add(sensor, jacobian, noise_inverse, Some(&since));
        }
    }

    /// Reserves room for `len` coefficients per step for [`Recorder::stage`]
    /// (a setup call: staging then never allocates).
    pub(crate) fn reserve_stage(&mut self, len: usize) {
        self.staged.reserve_exact(len);
    }

    /// Keeps a copy of the coefficients of the step in progress (as a
    /// filter's covariance propagation hands them over) for
    /// [`Recorder::propagated_staged`]. Never allocates: coefficients that do
    /// not fit the reserved buffer are not kept, and the step is then
    /// recorded from its Jacobian.
    pub(crate) fn stage(&mut self, coefficients: &[f64]) {
        self.staged.clear();
        self.staged_valid = coefficients.len() <= self.staged.capacity();
        if self.staged_valid {
            self.staged.extend_from_slice(coefficients);
        }
    }

    /// [`Recorder::propagated_step`] with the coefficients staged since the
    /// last step over `Mo::PROPAGATION`; `false`, and nothing recorded, if
    /// none were staged or they do not fit.
    pub(crate) fn propagated_staged<Mo: Model<N>>(&mut self, dt: f64) -> bool {
        let (Some(structure), true) = (Mo::PROPAGATION, core::mem::take(&mut self.staged_valid))
        else {
            return false;
        };
        let staged = core::mem::take(&mut self.staged);
        let recorded = self.propagated_step::<Mo>(&structure, &staged, dt);
        self.staged = staged;
        recorded
    }

    /// The epoch file (shared by every clone).
    pub fn store(&self) -> Rc<RefCell<EpochFile<N, S>>> {
        Rc::clone(&self.store)
    }

    /// Time of the recording now (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    fn fail(&mut self, reason: String) {
        if self.failure.is_none() {
            self.failure = Some(Rc::from(reason));
        }
    }

    fn close(&mut self) {
        // By reference: an epoch is large, and most steps have none to write.
        let Some(epoch) = self.open.as_ref() else {
            return;
        };
        let result = match self.store.try_borrow_mut() {
            Ok(mut store) => store
                .truncate(self.written)
                .and_then(|()| store.push(epoch))
                .map_err(|e| e.to_string()),
            Err(_) => Err("the epoch file was borrowed while recording".to_string()),
        };
        self.open = None;
        match result {
            Ok(()) => self.written += 1,
            Err(reason) => self.fail(reason),
        }
    }

    /// One prediction step of model `Mo` over `dt` seconds with the step's
    /// `jacobian` (`F` of a continuous model, so `Phi = I + F dt` as the
    /// filter's first-order step; `Phi` itself for a discrete model).
    ///
    /// For a continuous model only the rows of states with dynamics change:
    /// a state whose row of `Mo::JACOBIAN_SPARSITY` is structurally zero (a
    /// random-constant sensor bias) keeps its unit row in every product of
    /// steps, so it is neither updated nor read as a row; structural zeros of
    /// `F` cost nothing. No allocation.
    pub fn propagated<Mo: Model<N>>(&mut self, jacobian: &SMatrix<f64, N, N>, dt: f64) {
        self.close();
        self.time += dt;
        if Mo::DISCRETE {
            self.rows = (jacobian * self.rows.transpose()).transpose();
            return;
        }
        step_rows(
            &mut self.rows,
            &mut self.scratch,
            &Mo::JACOBIAN_SPARSITY,
            &Structure::<Mo, N>::MASKS,
            &Structure::<Mo, N>::DYNAMIC,
            jacobian,
            dt,
        );
    }

    /// [`Recorder::propagated`] for a continuous model with the step's
    /// transition `I + C` as the filter's covariance propagation used it
    /// (`structure` and the nonzeros `coefficients` of `C`, see
    /// [`Model::propagate_covariance_observed`]), so the Jacobian need not be
    /// evaluated again. `false`, and nothing recorded, if the step does not
    /// fit the model's sparsity (a changed row of a state without dynamics,
    /// a column outside the structure), is not of the form `I + C`, or the
    /// model is discrete: then call [`Recorder::propagated`].
    pub(crate) fn propagated_step<Mo: Model<N>>(
        &mut self,
        structure: &crate::propagation::Structure<'_>,
        coefficients: &[f64],
        dt: f64,
    ) -> bool {
        let dynamic = &Structure::<Mo, N>::DYNAMIC;
        let width = Structure::<Mo, N>::WIDTH;
        let (rows, start, columns) = (structure.rows, structure.start, structure.columns);
        let fits = !Mo::DISCRETE
            && structure.identity
            && start.len() == rows.len() + 1
            && start.first() == Some(&0)
            && start.windows(2).all(|w| w[0] <= w[1])
            && start.last() == Some(&columns.len())
            && coefficients.len() == columns.len()
            && rows.iter().all(|&i| i < N && dynamic[i])
            && columns.iter().all(|&j| j < width);
        if !fits {
            return false;
        }
        self.close();
        self.time += dt;
        // Whole vectors of four past the structure's width (the entries
        // there are zeros, in the rows of states with dynamics).
        let lanes = width.div_ceil(4) * 4;
        step_coefficients(
            &mut self.rows,
            &mut self.scratch,
            dynamic,
            lanes.min(N),
            structure,
            coefficients,
        );
        true
    }

    /// Opens the epoch at the current time before its first update, with the
    /// filter's covariance before the update; further calls at the same
    /// epoch change nothing.
    pub fn updating(&mut self, covariance: &SMatrix<f64, N, N>, snapshot: SVector<f64, S>) {
        if self.open.is_none() {
            let transition = self.rows.transpose();
            if let Some(information) = self.information.as_deref_mut() {
                information.to_start = transition * information.to_start;
            }
            self.open = Some(Epoch::at(self.time, transition, *covariance, snapshot));
            self.rows = SMatrix::identity();
        }
    }

    /// After an update of the open epoch: the `correction` it made (forward
    /// solution before minus after, in error-state coordinates: for an
    /// error-state filter the error estimate it fed back), the covariance
    /// after it and the snapshot of the corrected estimate.
    pub fn updated(
        &mut self,
        correction: &SVector<f64, N>,
        covariance: &SMatrix<f64, N, N>,
        snapshot: SVector<f64, S>,
    ) {
        if let Some(epoch) = self.open.as_mut() {
            epoch.correction += correction;
            epoch.filtered = *covariance;
            epoch.snapshot = snapshot;
        }
    }

    /// An epoch at `time` (s; an output time, re-synchronizing the
    /// recorder's clock), without update unless one follows.
    pub fn mark(&mut self, time: f64, covariance: &SMatrix<f64, N, N>, snapshot: SVector<f64, S>) {
        match self.open.as_mut() {
            Some(epoch) => epoch.time = time,
            None => {
                self.time = time;
                self.updating(covariance, snapshot);
            }
        }
        self.time = time;
    }

    /// Writes the open epoch and drops epochs of superseded histories; call
    /// at the end of the run (after a final [`Recorder::mark`] if the last
    /// prediction steps should be smoothed).
    ///
    /// # Errors
    /// [`SmootherError::Recording`] with the first failure of the run, or
    /// [`SmootherError::Io`] if the final write fails.
    pub fn finish(&mut self) -> Result<(), SmootherError> {
        self.close();
        if let Some(reason) = &self.failure {
            return Err(SmootherError::Recording {
                reason: reason.to_string(),
            });
        }
        self.store.borrow_mut().truncate(self.written)
    }
}

crate::dispatch::avx_dispatch! {
    /// `T <- T + dt F T` on `rows` (`T^T`) over the rows of the states with
    /// dynamics (`dynamic`) and the nonzeros of `sparsity`, with `scratch` as
    /// work space ([`Recorder::propagated`]). Compiled for AVX where the CPU
    /// has it (the same operations in the same order: bit-identical).
    fn step_rows<const N: usize>(
        rows: &mut SMatrix<f64, N, N>,
        scratch: &mut [[f64; N]; N],
        sparsity: &[[bool; N]; N],
        masks: &[u128; N],
        dynamic: &[bool; N],
        jacobian: &SMatrix<f64, N, N>,
        dt: f64,
    ) => step_rows_portable;
}

/// The body of [`step_rows`].
#[inline(always)]
fn step_rows_portable<const N: usize, const AVX: bool>(
    rows: &mut SMatrix<f64, N, N>,
    scratch: &mut [[f64; N]; N],
    sparsity: &[[bool; N]; N],
    masks: &[u128; N],
    dynamic: &[bool; N],
    jacobian: &SMatrix<f64, N, N>,
    dt: f64,
) {
    // T <- T + dt F T, row by row: row i of T changes by
    // sum_j dt F_ij (row j of T), where row j of a state without
    // dynamics is e_j. Rows are contiguous (`rows` holds T^T).
    let (t, _) = rows.as_slice().as_chunks::<N>();
    for (i, (d, sparsity)) in scratch
        .iter_mut()
        .zip(sparsity)
        .enumerate()
        .filter(|(i, _)| dynamic[*i])
    {
        d.fill(0.0);
        let mut step = |j: usize| {
            let a = dt * jacobian[(i, j)];
            if dynamic[j] {
                for (x, &t) in d.iter_mut().zip(&t[j]) {
                    *x += a * t;
                }
            } else {
                d[j] += a;
            }
        };
        if N <= 128 {
            // The nonzeros of row i, in order, from its bit mask.
            let mut mask = masks[i];
            while mask != 0 {
                step(mask.trailing_zeros() as usize);
                mask &= mask - 1;
            }
        } else {
            for (j, _) in sparsity.iter().enumerate().filter(|(_, &nz)| nz) {
                step(j);
            }
        }
    }
    let (t, _) = rows.as_mut_slice().as_chunks_mut::<N>();
    for ((row, d), _) in t
        .iter_mut()
        .zip(scratch.iter())
        .zip(dynamic)
        .filter(|(_, &dynamic)| dynamic)
    {
        for (x, dx) in row.iter_mut().zip(d) {
            *x += dx;
        }
    }
}

crate::dispatch::avx_dispatch! {
    /// `T <- T + C T` on `rows` (`T^T`) for the step `I + C` given by
    /// `structure` and `coefficients` (its changed rows, their nonzeros and coefficients; checked
    /// against the model's structure), over the first `width` columns (past
    /// them the rows of states with dynamics are zero), with `scratch` as
    /// work space ([`Recorder::propagated_step`]). Compiled for AVX where
    /// the CPU has it (the same operations in the same order:
    /// bit-identical).
    fn step_coefficients<const N: usize>(
        rows: &mut SMatrix<f64, N, N>,
        scratch: &mut [[f64; N]; N],
        dynamic: &[bool; N],
        width: usize,
        structure: &crate::propagation::Structure<'_>,
        coefficients: &[f64],
    ) => step_coefficients_portable;
}

/// The body of [`step_coefficients`].
#[inline(always)]
fn step_coefficients_portable<const N: usize, const AVX: bool>(
    rows: &mut SMatrix<f64, N, N>,
    scratch: &mut [[f64; N]; N],
    dynamic: &[bool; N],
    width: usize,
    structure: &crate::propagation::Structure<'_>,
    coefficients: &[f64],
) {
    let (changed, start, columns) = (structure.rows, structure.start, structure.columns);
    // Row i of T changes by sum_j C_ij (row j of T), where row j of a state
    // without dynamics is e_j. Rows are contiguous (`rows` holds T^T).
    let (t, _) = rows.as_slice().as_chunks::<N>();
    for ((d, range), _) in scratch
        .iter_mut()
        .zip(start.windows(2).map(|w| w[0]..w[1]))
        .zip(changed)
    {
        let d = &mut d[..width];
        d.fill(0.0);
        for (&j, &a) in columns[range.clone()].iter().zip(&coefficients[range]) {
            if dynamic[j] {
                for (x, &t) in d.iter_mut().zip(&t[j][..width]) {
                    *x += a * t;
                }
            } else {
                d[j] += a;
            }
        }
    }
    let (t, _) = rows.as_mut_slice().as_chunks_mut::<N>();
    for (d, &i) in scratch.iter().zip(changed) {
        for (x, dx) in t[i][..width].iter_mut().zip(&d[..width]) {
            *x += dx;
        }
    }
}

/// Structure of model `Mo`'s transition matrices, from its generated sparsity.
struct Structure<Mo, const N: usize>(core::marker::PhantomData<Mo>);

impl<Mo: Model<N>, const N: usize> Structure<Mo, N> {
    /// `true` for the states with dynamics: a row of `F` with a structural
    /// nonzero. The others keep unit rows in every `prod (I + F dt)`.
    const DYNAMIC: [bool; N] = dynamic_rows(&Mo::JACOBIAN_SPARSITY);
    /// The structural nonzeros of each row of `F` as a bit mask (bit `j`
    /// for column `j`; used for `N <= 128`).
    const MASKS: [u128; N] = row_masks(&Mo::JACOBIAN_SPARSITY);
    /// One past the last column a row of a state with dynamics can have a
    /// nonzero in, in any product of steps: its own index or a structural
    /// nonzero of its row of `F`.
    const WIDTH: usize = width(&Mo::JACOBIAN_SPARSITY);
}

/// [`Structure::WIDTH`] of `sparsity`.
const fn width<const N: usize>(sparsity: &[[bool; N]; N]) -> usize {
    let mut out = 0;
    let mut i = 0;
    while i < N {
        let mut j = 0;
        while j < N {
            if sparsity[i][j] {
                if i + 1 > out {
                    out = i + 1;
                }
                if j + 1 > out {
                    out = j + 1;
                }
            }
            j += 1;
        }
        i += 1;
    }
    out
}

/// Bit `j` of entry `i`: `sparsity[i][j]` (columns below 128).
const fn row_masks<const N: usize>(sparsity: &[[bool; N]; N]) -> [u128; N] {
    let mut out = [0u128; N];
    let mut i = 0;
    while i < N {
        let mut j = 0;
        while j < N && j < 128 {
            if sparsity[i][j] {
                out[i] |= 1u128 << j;
            }
            j += 1;
        }
        i += 1;
    }
    out
}

/// Rows of `sparsity` with at least one structural nonzero.
const fn dynamic_rows<const N: usize>(sparsity: &[[bool; N]; N]) -> [bool; N] {
    let mut out = [false; N];
    let mut i = 0;
    while i < N {
        let mut j = 0;
        while j < N {
            out[i] |= sparsity[i][j];
            j += 1;
        }
        i += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A continuous 4-state model: two states with dynamics (0 and 2), one
    /// bias feeding them (1), one state that nothing touches (3).
    struct Four;

    impl Model<4> for Four {
        type Input = ();
        type Params = ();
        type Noise = ();
        type State = ();
        const NAME: &'static str = "four";
        const DISCRETE: bool = false;
        const STATE_NAMES: [&'static str; 4] = ["a", "b", "c", "d"];
        const JACOBIAN_SPARSITY: [[bool; 4]; 4] = [
            [true, true, true, false],
            [false; 4],
            [true, false, false, true],
            [false; 4],
        ];
        const OPS_PROPAGATE_COVARIANCE: usize = 0;
        const OPS_JACOBIAN: usize = 0;
        // The layout of `captured`.
        const PROPAGATION: Option<crate::propagation::Structure<'static>> =
            Some(crate::propagation::Structure {
                identity: true,
                rows: &[0, 2],
                start: &[0, 3, 5],
                columns: &[0, 1, 2, 0, 3],
                noise: &[],
            });
        fn transition(x: &SVector<f64, 4>, _: &(), _: &(), _: f64) -> SVector<f64, 4> {
            *x
        }
        fn jacobian(_: &SVector<f64, 4>, _: &(), _: &(), _: f64) -> SMatrix<f64, 4, 4> {
            SMatrix::zeros()
        }
        fn process_noise(
            _: &SVector<f64, 4>,
            _: &(),
            _: &(),
            _: &(),
            _: f64,
        ) -> SMatrix<f64, 4, 4> {
            SMatrix::zeros()
        }
        fn propagate_covariance(
            _: &mut SMatrix<f64, 4, 4>,
            _: &SVector<f64, 4>,
            _: &(),
            _: &(),
            _: &(),
            _: f64,
        ) {
        }
    }

    #[test]
    fn dynamic_rows_are_the_rows_with_a_nonzero() {
        assert_eq!(Structure::<Four, 4>::DYNAMIC, [true, false, true, false]);
        assert_eq!(Structure::<Four, 4>::MASKS, [0b0111, 0, 0b1001, 0]);
        assert_eq!(Structure::<Four, 4>::WIDTH, 4);
        let mut sparsity = [[false; 6]; 6];
        assert_eq!(width(&sparsity), 0);
        sparsity[2][0] = true;
        assert_eq!(width(&sparsity), 3);
        sparsity[1][4] = true;
        assert_eq!(width(&sparsity), 5);
    }

    /// The Jacobian of step `k` of the tests (nonzero at Four's sparsity).
    fn jacobian(k: usize) -> SMatrix<f64, 4, 4> {
        let x = k as f64;
        SMatrix::<f64, 4, 4>::from_fn(|i, j| {
            if Four::JACOBIAN_SPARSITY[i][j] {
                0.3 + 0.1 * x - 0.2 * i as f64 + 0.05 * j as f64
            } else {
                0.0
            }
        })
    }

    /// A step `I + C` in the layout of the covariance propagation.
    #[derive(Clone, Default)]
    struct Step {
        rows: Vec<usize>,
        start: Vec<usize>,
        columns: Vec<usize>,
        coefficients: Vec<f64>,
        identity: bool,
    }

    impl Step {
        fn structure(&self) -> crate::propagation::Structure<'_> {
            crate::propagation::Structure {
                identity: self.identity,
                rows: &self.rows,
                start: &self.start,
                columns: &self.columns,
                noise: &[],
            }
        }
    }

    /// `I + C` of a step in the layout of the covariance propagation, with
    /// `C = dt F` over Four's sparsity.
    fn captured(f: &SMatrix<f64, 4, 4>, dt: f64) -> Step {
        let mut step = Step {
            identity: true,
            ..Step::default()
        };
        step.start.push(0);
        for i in [0, 2] {
            step.rows.push(i);
            for j in 0..4 {
                if Four::JACOBIAN_SPARSITY[i][j] {
                    step.columns.push(j);
                    step.coefficients.push(dt * f[(i, j)]);
                }
            }
            step.start.push(step.columns.len());
        }
        step
    }

    /// Steps given by the propagation's coefficients record the same bits
    /// as steps given by the Jacobian; a step that does not fit the
    /// sparsity is refused and records nothing.
    #[test]
    fn coefficient_steps_equal_jacobian_steps_bit_for_bit() {
        let p = SMatrix::<f64, 4, 4>::identity();
        let start = |t| {
            Recorder::new(
                EpochFile::<4, 0>::create(None).unwrap(),
                t,
                &p,
                SVector::zeros(),
            )
        };
        let (mut by_jacobian, mut by_coefficients) = (start(0.0), start(0.0));
        for k in 0..7 {
            let (f, dt) = (jacobian(k), 0.1 + 0.01 * k as f64);
            by_jacobian.propagated::<Four>(&f, dt);
            let step = captured(&f, dt);
            assert!(by_coefficients.propagated_step::<Four>(
                &step.structure(),
                &step.coefficients,
                dt
            ));
        }
        assert_eq!(
            by_jacobian.rows.map(f64::to_bits),
            by_coefficients.rows.map(f64::to_bits)
        );
        assert_eq!(by_jacobian.time, by_coefficients.time);
        assert_ne!(
            by_jacobian.rows,
            SMatrix::<f64, 4, 4>::identity(),
            "the steps ran"
        );
        let rows = by_coefficients.rows;
        for bad in [
            |s: &mut Step| s.rows[1] = 1,
            |s: &mut Step| s.columns[0] = 4,
            |s: &mut Step| s.start[1] = 9,
            |s: &mut Step| {
                s.coefficients.pop();
            },
            |s: &mut Step| s.identity = false,
        ] {
            let mut step = captured(&jacobian(0), 0.1);
            bad(&mut step);
            assert!(!by_coefficients.propagated_step::<Four>(
                &step.structure(),
                &step.coefficients,
                0.1
            ));
        }
        assert_eq!(by_coefficients.rows, rows);
        assert_eq!(by_coefficients.time, by_jacobian.time);
    }

    /// Staged coefficients record the step as given directly, only within
    /// the reserved buffer (staging never allocates), and only once.
    #[test]
    fn staged_steps_are_recorded_once_and_only_within_the_reserve() {
        let p = SMatrix::<f64, 4, 4>::identity();
        let start = || {
            Recorder::new(
                EpochFile::<4, 0>::create(None).unwrap(),
                0.0,
                &p,
                SVector::zeros(),
            )
        };
        let (mut direct, mut staged, mut unreserved) = (start(), start(), start());
        staged.reserve_stage(5);
        let capacity = staged.staged.capacity();
        for k in 0..5 {
            let (f, dt) = (jacobian(k), 0.1 + 0.01 * k as f64);
            let step = captured(&f, dt);
            assert!(direct.propagated_step::<Four>(&step.structure(), &step.coefficients, dt));
            staged.stage(&step.coefficients);
            assert!(staged.propagated_staged::<Four>(dt));
            assert!(
                !staged.propagated_staged::<Four>(dt),
                "a staged step is used once"
            );
            unreserved.stage(&step.coefficients);
            assert!(!unreserved.propagated_staged::<Four>(dt));
        }
        assert_eq!(staged.staged.capacity(), capacity, "no growth");
        assert_eq!(unreserved.staged.capacity(), 0, "nothing allocated");
        assert_eq!(direct.rows.map(f64::to_bits), staged.rows.map(f64::to_bits));
        assert_eq!(direct.time, staged.time);
        assert_eq!(unreserved.rows, p, "nothing recorded");
    }

    /// A transition product with unit rows 1 and 3 (the states without
    /// dynamics) and distinct entries elsewhere.
    fn partial_transition() -> SMatrix<f64, 4, 4> {
        SMatrix::<f64, 4, 4>::from_fn(|r, c| {
            if r == 1 || r == 3 {
                f64::from(u8::from(r == c))
            } else {
                0.1 * (r * 4 + c) as f64 + 1.0
            }
        })
    }

    /// The dispatched coefficient step (AVX where the CPU has it) and the
    /// portable build give the same bits.
    #[test]
    fn dispatched_coefficient_step_equals_the_portable_one_bit_for_bit() {
        let step = captured(&jacobian(3), 0.013);
        let start = partial_transition();
        let (mut a, mut b) = (start, start);
        let mut scratch = [[0.0; 4]; 4];
        let dynamic = &Structure::<Four, 4>::DYNAMIC;
        let (structure, c) = (step.structure(), &step.coefficients);
        step_coefficients(&mut a, &mut scratch, dynamic, 4, &structure, c);
        step_coefficients_portable::<4, false>(&mut b, &mut scratch, dynamic, 4, &structure, c);
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        assert_ne!(a, start, "the step ran");
    }

    /// The dispatched row step (AVX where the CPU has it) and the portable
    /// build give the same bits.
    #[test]
    fn dispatched_rows_equal_the_portable_ones_bit_for_bit() {
        let f = SMatrix::<f64, 4, 4>::from_fn(|i, j| {
            if Four::JACOBIAN_SPARSITY[i][j] {
                0.7 - 0.3 * i as f64 + 0.11 * j as f64
            } else {
                0.0
            }
        });
        let start = partial_transition();
        let (mut a, mut b) = (start, start);
        let mut scratch = [[0.0; 4]; 4];
        let (sparsity, masks, dynamic) = (
            &Four::JACOBIAN_SPARSITY,
            &Structure::<Four, 4>::MASKS,
            &Structure::<Four, 4>::DYNAMIC,
        );
        step_rows(&mut a, &mut scratch, sparsity, masks, dynamic, &f, 0.013);
        step_rows_portable::<4, false>(&mut b, &mut scratch, sparsity, masks, dynamic, &f, 0.013);
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        assert_ne!(a, start, "the step ran");
    }

    /// The row-wise product over the states with dynamics equals the dense
    /// product of the steps `I + F dt`, entry for entry.
    #[test]
    fn transition_equals_the_dense_product_of_steps() {
        let file = EpochFile::<4, 0>::create(None).unwrap();
        let p = SMatrix::<f64, 4, 4>::identity();
        let mut rec = Recorder::new(file, 0.0, &p, SVector::zeros());
        let mut dense = SMatrix::<f64, 4, 4>::identity();
        for k in 0..7 {
            let x = k as f64;
            let f = SMatrix::<f64, 4, 4>::from_fn(|i, j| {
                if Four::JACOBIAN_SPARSITY[i][j] {
                    0.3 + 0.1 * x - 0.2 * i as f64 + 0.05 * j as f64
                } else {
                    0.0
                }
            });
            let dt = 0.1 + 0.01 * x;
            rec.propagated::<Four>(&f, dt);
            dense = (SMatrix::identity() + f * dt) * dense;
        }
        let got = rec.rows.transpose();
        for (g, d) in got.iter().zip(dense.iter()) {
            assert!(
                (g - d).abs() <= 1e-14 * d.abs().max(1.0),
                "{got} != {dense}"
            );
        }
        assert_eq!(got.row(1), SMatrix::<f64, 4, 4>::identity().row(1));
        assert_eq!(got.row(3), SMatrix::<f64, 4, 4>::identity().row(3));
        assert_ne!(got.column(3), SMatrix::<f64, 4, 4>::identity().column(3));
    }
}
