//! The vehicle's own sensors, states and process noise, fed by their
//! declared names from the log's `replay.toml` (`docs/pipeline.md`,
//! "Sensors of your own"): the sensors no reading kind feeds (a block of the
//! user's crate), the states the nominal solution does not keep, and the
//! process noise beyond the INS core's. The sections and the reading of the
//! files are the model replay's, so one mapping language serves both.

use std::path::Path;

use nav_runtime::log::{LogSource, Strictness, Warning, WarningKind};
use nav_runtime::model::Record;

use crate::innovations::SensorInnovations;
use crate::model_replay::{
    parse_aiding, AidingMapping, Declared, DeclaredSensor as MappedSensor, MappedRows,
    ModelReplayError, MAPPING_FILE,
};
use crate::RunError;
use nav_ins::declared::{extra_noise, slot_file};
use nav_ins::vehicle::Layout;
use nav_ins::{Builder, DeclaredHandle, DeclaredSensor, InsVehicle, Navigator, SensorHealth};

/// What `replay.toml` gives for vehicle `V`, and the files of its sensors.
pub(super) struct OwnSensors<V: InsVehicle<N>, const N: usize> {
    sensors: Vec<DeclaredSensor<V, N>>,
    mapping: Option<AidingMapping>,
    /// Names of the states and noise scalars the mapping's values are for.
    states: Vec<&'static str>,
    noise: Vec<&'static str>,
    feeds: Vec<Feed>,
    pub(super) warnings: Vec<Warning>,
}

/// One declared sensor's file as the replay reads it.
struct Feed {
    name: &'static str,
    /// The sensor's sigma when it has one output.
    sigma: Option<f64>,
    handle: DeclaredHandle,
    rows: MappedRows,
    outputs: usize,
    /// The row read ahead: its time (s); its values wait in `rows`.
    next: Option<f64>,
    health: SensorHealth,
}

fn mapping_error(e: ModelReplayError) -> RunError {
    match e {
        ModelReplayError::Log(e) => RunError::Log(e),
        e => RunError::Invalid(e.to_string()),
    }
}

impl<V: InsVehicle<N>, const N: usize> OwnSensors<V, N> {
    /// Reads `replay.toml` of the log (if the log is a directory and has
    /// one) against vehicle `V`.
    ///
    /// # Errors
    /// The mapping's errors; a sensor a reading kind feeds named in it.
    pub(super) fn read(source: &LogSource<'_>) -> Result<Self, RunError> {
        let layout = Layout::of::<V, N>()?;
        let absorbed = layout.absorbed::<N>();
        let states: Vec<&'static str> = (0..N)
            .filter(|&i| !absorbed[i])
            .map(|i| V::STATE_NAMES[i])
            .collect();
        let noise_names = <V::Noise as Record>::NAMES;
        let noise: Vec<&'static str> = extra_noise::<V, N>()
            .into_iter()
            .map(|i| noise_names[i])
            .collect();
        let sensors = DeclaredSensor::<V, N>::unslotted();
        let mut own = OwnSensors {
            sensors,
            mapping: None,
            states,
            noise,
            feeds: Vec::new(),
            warnings: Vec::new(),
        };
        let LogSource::Files(files) = source else {
            return Ok(own);
        };
        let Some(text) = read_mapping(files.dir())? else {
            for s in &own.sensors {
                own.warnings.push(
                    Warning::about(
                        WarningKind::MissingSensorSection,
                        MAPPING_FILE,
                        format!(
                            "sensor {} of vehicle {} is fed by no file: the log has no {MAPPING_FILE} with [sensors.{}]",
                            s.name,
                            V::REPLAY_NAME,
                            s.name
                        ),
                    )
                    .with_key(&format!("sensors.{}", s.name)),
                );
            }
            return Ok(own);
        };
        // A sensor a reading kind feeds is not mapped here.
        if let Ok(table) = text.parse::<toml::Table>() {
            if let Some(toml::Value::Table(s)) = table.get("sensors") {
                for name in s.keys() {
                    if let Some(file) = slot_file::<V, N>(name) {
                        return Err(RunError::Invalid(format!(
                            "{MAPPING_FILE}: `sensors.{name}`: sensor {name} of vehicle {} is fed by {file} (its settings are in meta.toml), not by {MAPPING_FILE}",
                            V::REPLAY_NAME
                        )));
                    }
                }
            }
        }
        let declared = Declared {
            model: V::REPLAY_NAME,
            states: own.states.clone(),
            inputs: &[],
            params: &[],
            noise: own.noise.clone(),
            sensors: own
                .sensors
                .iter()
                .map(|s| MappedSensor {
                    name: s.name,
                    outputs: s.outputs,
                    aux: s.aux,
                })
                .collect(),
            // A vehicle's own sensors are its blocks': all registered.
            declared_sensors: &[],
        };
        let mapping = parse_aiding(&text, MAPPING_FILE, &declared).map_err(mapping_error)?;
        for w in &mapping.warnings {
            let mut w = w.clone();
            w.message = format!("{} (vehicle {})", w.message, V::REPLAY_NAME);
            own.warnings.push(w);
        }
        own.mapping = Some(mapping);
        Ok(own)
    }

    /// The sigmas (per output) `replay.toml` gives each sensor it feeds,
    /// and the values of its process noise.
    pub(super) fn own_mapping(&self) -> crate::OwnMapping {
        let Some(mapping) = &self.mapping else {
            return crate::OwnMapping::default();
        };
        crate::OwnMapping {
            sigmas: self
                .sensors
                .iter()
                .zip(&mapping.sensors)
                .filter_map(|(s, m)| Some((s.name.to_string(), m.as_ref()?.sigma.clone())))
                .collect(),
            noise: self
                .noise
                .iter()
                .zip(&mapping.noise)
                .map(|(n, q)| (n.to_string(), *q))
                .collect(),
            clocks: self
                .sensors
                .iter()
                .zip(&mapping.sensors)
                .filter_map(|(s, m)| Some((s.name.to_string(), m.as_ref()?.source.time_offset_s)))
                .collect(),
        }
    }

    /// Registers what the mapping gives with the navigator's builder and
    /// opens the sensors' files.
    ///
    /// # Errors
    /// The builder's setup errors; a mapped file that cannot be opened.
    pub(super) fn register(
        &mut self,
        builder: &mut Builder<V, N>,
        source: &LogSource<'_>,
    ) -> Result<(), RunError> {
        let Some(mapping) = &self.mapping else {
            return Ok(());
        };
        for (name, sigma) in self.states.iter().zip(&mapping.sigma) {
            builder.state_sigma(name, *sigma)?;
        }
        let files = match source {
            LogSource::Files(files) => Some(*files),
            LogSource::Memory(_) => None,
        };
        let mut noise = mapping.noise.clone();
        if let Some(files) = files {
            crate::tune::with_noise_values(&self.noise, &mut noise, |key| files.mapping_value(key));
        }
        for (name, q) in self.noise.iter().zip(&noise) {
            builder.process_noise(name, *q)?;
        }
        let Some(files) = files else {
            return Ok(());
        };
        let lenient = files.strictness() == Strictness::Lenient;
        for (sensor, m) in self.sensors.iter().zip(&mapping.sensors) {
            let Some(m) = m else { continue };
            let key = format!("sensors.{}.sigma", sensor.name);
            let sigma = scaled_sigma(&m.sigma, files.mapping_value(&key));
            let handle = builder.declared_sensor(sensor.name, &sigma)?;
            if m.gate != Some(crate::model_replay::DEFAULT_GATE) {
                self.warnings.push(
                    Warning::about(
                        WarningKind::Suspicious,
                        MAPPING_FILE,
                        format!(
                            "sensors.{}.gate: an INS vehicle's sensors share the replay's gate (--gate); the value is not used",
                            sensor.name
                        ),
                    )
                    .with_key(&format!("sensors.{}.gate", sensor.name)),
                );
            }
            // A clock offset a tuning replays with.
            let mut source = m.source.clone();
            if let Some(offset) = files.mapping_value(&crate::tune::mapped_clock_key(sensor.name)) {
                source.time_offset_s = offset;
            }
            let Some(mut rows) = MappedRows::open(files.dir(), &source, MAPPING_FILE, lenient)
                .map_err(mapping_error)?
            else {
                continue;
            };
            rows.check(sensor.outputs, true);
            let mut feed = Feed {
                name: sensor.name,
                sigma: (sigma.len() == 1).then(|| sigma[0]),
                handle,
                rows,
                outputs: sensor.outputs,
                next: None,
                health: SensorHealth::default(),
            };
            feed.advance()?;
            self.feeds.push(feed);
        }
        Ok(())
    }

    /// Pushes every row measured at or before `t` (s) into `nav`.
    ///
    /// # Errors
    /// A row that cannot be read (strict reading).
    #[inline]
    pub(super) fn push_due(&mut self, t: f64, nav: &mut Navigator<V, N>) -> Result<(), RunError> {
        if self.feeds.is_empty() {
            return Ok(());
        }
        for feed in &mut self.feeds {
            while feed.next.is_some_and(|tr| tr <= t) {
                feed.push(nav);
                feed.advance()?;
            }
        }
        Ok(())
    }

    /// Pushes every row left.
    ///
    /// # Errors
    /// As [`OwnSensors::push_due`].
    pub(super) fn push_rest(&mut self, nav: &mut Navigator<V, N>) -> Result<(), RunError> {
        self.push_due(f64::INFINITY, nav)?;
        // What the rows showed about their files (`row_checks`).
        for f in &self.feeds {
            self.warnings.extend(f.rows.row_warnings());
        }
        Ok(())
    }

    /// The innovations of each sensor fed by name (the noise sigma given
    /// for a sensor of one output; several outputs have no single one).
    pub(super) fn innovations(&self, nav: &Navigator<V, N>) -> Vec<SensorInnovations> {
        self.feeds
            .iter()
            .map(|f| {
                let r = nav.report_declared(f.handle);
                SensorInnovations {
                    sensor: f.name.to_string(),
                    noise_sigma: f.sigma,
                    gated: r.health.gated,
                    setting: ("replay.toml".into(), format!("sensors.{}.sigma", f.name)),
                    totals: r.innovations,
                }
            })
            .collect()
    }

    /// Per sensor fed by name: its health (rows read, and the navigator's
    /// counts).
    pub(super) fn health(&self, nav: &Navigator<V, N>) -> Vec<(&'static str, SensorHealth)> {
        self.feeds
            .iter()
            .map(|f| {
                let r = nav.report_declared(f.handle).health;
                let mut h = f.health;
                h.accepted = r.accepted;
                h.gated = r.gated;
                h.rejected += r.rejected;
                h.skipped += r.skipped + f.rows.skipped_rows;
                h.stuck = r.stuck;
                (f.name, h)
            })
            .collect()
    }
}

impl Feed {
    fn advance(&mut self) -> Result<(), RunError> {
        self.next = self.rows.next_row()?.map(|(_, t)| t);
        if self.next.is_some() {
            self.health.rows += 1;
        }
        Ok(())
    }

    fn push<V: InsVehicle<N>, const N: usize>(&self, nav: &mut Navigator<V, N>) {
        let Some(t) = self.next else { return };
        let values = self.rows.values();
        let (z, aux) = values.split_at(self.outputs.min(values.len()));
        nav.push_declared(self.handle, t, z, aux);
    }
}

/// `replay.toml` of the log directory, if it has one (confined to it).
/// The sigmas of `replay.toml` (per output) with the first set to
/// `first`, every output scaled by the same ratio (noise tuning's
/// [`LogFiles::with_mapping_value`](nav_runtime::log::LogFiles::with_mapping_value));
/// as given without one, or when the first is not positive.
fn scaled_sigma(given: &[f64], first: Option<f64>) -> Vec<f64> {
    match (first, given.first()) {
        (Some(v), Some(&g)) if g > 0.0 => crate::tune::scaled_sigmas(given, v),
        _ => given.to_vec(),
    }
}

/// The text of the log's `replay.toml`, `None` without one.
fn read_mapping(dir: &Path) -> Result<Option<String>, RunError> {
    let Some(mut file) = nav_runtime::log::open_confined(dir, MAPPING_FILE, MAPPING_FILE)? else {
        return Ok(None);
    };
    let mut text = String::new();
    std::io::Read::read_to_string(&mut file, &mut text).map_err(|e| RunError::Io {
        path: dir.join(MAPPING_FILE),
        source: e,
    })?;
    Ok(Some(text))
}
