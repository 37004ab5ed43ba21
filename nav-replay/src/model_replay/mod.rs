//! Replay of any declared model over a log: not only INS vehicles. A model
//! declared with `nav_runtime::model!` (a ground robot, an attitude filter,
//! a tracking filter) and a `replay.toml` in the log directory saying which
//! CSV file and columns feed its inputs and each of its sensors give a
//! program that replays logs for it:
//!
//! ```no_run
//! # nav_runtime::model! {
//! #     pub model Cart {
//! #         states { position, velocity }
//! #         inputs { acceleration }
//! #         noise { accel_noise }
//! #         continuous {
//! #             d/dt position = velocity;
//! #             d/dt velocity = acceleration + accel_noise;
//! #         }
//! #         sensor Fix: 1 { h = [position]; }
//! #     }
//! # }
//! use nav_replay::model_replay::ModelReplay;
//!
//! fn main() -> std::process::ExitCode {
//!     ModelReplay::<Cart, 2>::new("cart")
//!         .sensor::<CartFix, 1>()
//!         .main()
//! }
//! ```
//!
//! `cart replay DIR [--json] [--out OUT] [--lenient]` runs the filter and
//! reports, per sensor, the rows applied, gated and refused and their mean
//! NIS, the final state with its sigma and, with a truth file, the RMS error
//! of each state and the NEES; `cart check DIR` checks the mapping against
//! the declaration and reads every row. A sensor of another model does not
//! compile; a mapping that names what the declaration lacks is an error
//! naming the key. See `docs/model-replay.md`.
//!
//! INS vehicles (the INS core and the log sensors of [`nav_ins`])
//! have their own program, [`crate::program::replay_main`], with the standard
//! log format, lever arms, the preflight and the smoother.

mod declared;
mod error;
mod feed;
mod mapping;
mod plots;
mod program;
mod row_checks;
mod run;
mod smoothing;
mod table;
mod tuning;
pub mod units;

use std::path::Path;

use nav_runtime::ekf::Ekf;
use nav_runtime::error_state::{ErrorStateFilter, TotalState};
use nav_runtime::model::{Model, Sensor};

/// The filter a declared model is replayed with: its EKF behind the
/// error-state filter's interface over [`TotalState`] (every state a
/// total-state estimate; the same numbers as the plain EKF), so that the
/// run can be recorded as an INS vehicle's is (`--observability`).
pub type ModelFilter<M, const N: usize> = ErrorStateFilter<M, TotalState<M>, N>;

pub use declared::{Declared, DeclaredSensor};
pub use error::ModelReplayError;
pub use feed::{Feed, FeedOf};
pub use mapping::{
    parse as parse_mapping, parse_aiding, AidingMapping, Cell, Column, InitialEstimate, Mapping,
    SensorMapping, Source, DEFAULT_GATE, MAPPING_FILE, TRUTH_FILE,
};
pub use plots::file_name as plot_file_name;
pub use program::run_json;
pub use run::{
    angle_states, quaternion_blocks, ModelRun, RunOptions, SensorSummary, SmoothedRun, TruthScore,
    ESTIMATES_TABLE, SMOOTHED_TABLE,
};
pub(crate) use table::MappedRows;
pub use tuning::MappingTuning;

/// The replay of declared model `M` (`N` states) and its registered
/// sensors (see the module docs).
pub struct ModelReplay<M: Model<N>, const N: usize> {
    name: &'static str,
    feeds: Vec<Box<dyn Feed<M, N>>>,
}

impl<M: Model<N>, const N: usize> ModelReplay<M, N>
where
    Ekf<M, N>: Clone,
{
    /// A replay named `name` (the program's name in messages and JSON).
    pub fn new(name: &'static str) -> Self {
        ModelReplay {
            name,
            feeds: Vec::new(),
        }
    }

    /// Registers sensor `S` (`K` outputs) of the model, fed by the
    /// `[sensors.<its declared name>]` section of the mapping.
    #[must_use]
    pub fn sensor<S: Sensor<N, K, Model = M>, const K: usize>(mut self) -> Self {
        self.feeds.push(Box::new(FeedOf::<S, K>::default()));
        self
    }

    /// The replay's name.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// The names the mapping may use.
    pub fn declared(&self) -> Declared {
        let mut d = Declared::of::<M, N>();
        d.sensors = self.feeds.iter().map(|f| f.declared()).collect();
        d
    }

    /// Reads and checks the mapping: `mapping` if given, else `replay.toml`
    /// in `dir`. Returns its file name (for messages) and the mapping.
    ///
    /// # Errors
    /// A sensor registered twice, an unreadable file, or a mapping that
    /// does not fit the declaration.
    pub fn mapping(
        &self,
        dir: &Path,
        mapping: Option<&Path>,
    ) -> Result<(String, Mapping), ModelReplayError> {
        // A sensor registered twice would be fed once and reported twice,
        // the second time as not fed.
        let declared = self.declared();
        for (k, s) in declared.sensors.iter().enumerate() {
            if declared.sensors[..k].iter().any(|d| d.name == s.name) {
                return Err(ModelReplayError::Setup(format!(
                    "program {}: sensor {} of model {} is registered twice (`.sensor::<{}{}, {}>()`): register each sensor once",
                    self.name, s.name, M::NAME, M::NAME, s.name, s.outputs
                )));
            }
        }
        // A log directory that is not there is said as such, not as a
        // missing mapping in it.
        if let Err(e) = std::fs::read_dir(dir) {
            return Err(nav_runtime::log::LogError::Io {
                path: dir.to_path_buf(),
                source: e,
            }
            .into());
        }
        let path = mapping.map_or_else(|| dir.join(MAPPING_FILE), Path::to_path_buf);
        let name = path.file_name().map_or_else(
            || MAPPING_FILE.to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        // The log directory's own mapping is confined to it (a symbolic link
        // out of it is refused, its target never read); a mapping the user
        // names with --mapping is theirs to point anywhere.
        if mapping.is_none() {
            if let Err(e) = nav_runtime::log::open_confined(dir, MAPPING_FILE, MAPPING_FILE) {
                return Err(e.into());
            }
        }
        let text = std::fs::read_to_string(&path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                ModelReplayError::Mapping {
                    file: name.clone(),
                    key: String::new(),
                    line: None,
                    problem: format!(
                        "no mapping at {}: it says which files feed model {}'s inputs and sensors (docs/model-replay.md)",
                        path.display(),
                        M::NAME
                    ),
                }
            } else {
                nav_runtime::log::LogError::Io {
                    path: path.clone(),
                    source: e,
                }
                .into()
            }
        })?;
        let m = mapping::parse(&text, &name, &self.declared())?;
        Ok((name, m))
    }

    /// Replays the log in `dir` (mapping as [`ModelReplay::mapping`]); with
    /// `out`, writes `estimates.csv` there.
    ///
    /// # Errors
    /// As [`ModelReplay::mapping`], a file or row the mapping cannot read, a
    /// filter set-up error, an input row the filter refuses.
    pub fn replay(
        &self,
        dir: &Path,
        mapping: Option<&Path>,
        options: &RunOptions,
        out: Option<&Path>,
    ) -> Result<ModelRun, ModelReplayError> {
        let (name, m) = self.mapping(dir, mapping)?;
        run::run::<M, N>(dir, &name, &m, &self.feeds, options, out)
    }

    /// What `check DIR` reports (mapping as [`ModelReplay::mapping`]):
    /// every mapped file read through, with its rows and time span, and the
    /// warnings of what the replay would not use (the JSON of `check
    /// --json` but for the replay's own refusals, which `check` adds by
    /// running it).
    ///
    /// # Errors
    /// As [`ModelReplay::mapping`], and a file or row the mapping cannot
    /// read.
    pub fn check(
        &self,
        dir: &Path,
        mapping: Option<&Path>,
        lenient: bool,
    ) -> Result<serde_json::Value, ModelReplayError> {
        let (name, m) = self.mapping(dir, mapping)?;
        program::check_json(self, dir, &name, &m, lenient)
    }

    /// The replay program on the process's arguments: `replay` and `check`
    /// (see the module docs).
    pub fn main(self) -> std::process::ExitCode {
        self.main_with(std::env::args_os())
    }

    /// [`ModelReplay::main`] with explicit arguments (the first is the
    /// program name).
    pub fn main_with<I, T>(self, args: I) -> std::process::ExitCode
    where
        I: IntoIterator<Item = T>,
        T: Into<std::ffi::OsString> + Clone,
    {
        program::main_with(&self, args)
    }
}
