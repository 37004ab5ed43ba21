//! `replay.toml`: which log file and columns feed a declared model's inputs
//! and each of its sensors, in which units, with which parameters, noise,
//! initial state and truth (`docs/model-replay.md`, "The mapping").
//!
//! Everything is named as declared: `[inputs.columns] yaw_rate = ...` for
//! the input `yaw_rate`, `[sensors.Fix]` for `sensor Fix`. A key names one
//! scalar (`"gyro[1]"`) or a whole block (`gyro`, one value per scalar). The
//! mapping is checked against the declaration before any row is read: a name
//! the declaration does not have, a missing value, an unknown unit or a path
//! outside the log directory is a [`ModelReplayError::Mapping`] naming the
//! key (and what it may be).

use std::path::Path;

use nav_runtime::log::{closest_name, relative_log_path, Warning, WarningKind};
use toml::{Table, Value};

use super::declared::{blocks, scalars_of, Declared};
use super::units;
use super::ModelReplayError;

/// The mapping file a log directory holds.
pub const MAPPING_FILE: &str = "replay.toml";

/// The time column when a section does not name one.
pub const TIME_COLUMN: &str = "t";

/// The truth file when `[truth]` does not name one.
pub const TRUTH_FILE: &str = "truth.csv";

/// A column of a log file and the factor its values are multiplied by.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// Its header name.
    pub header: String,
    /// Unit factor times `scale`.
    pub factor: f64,
    /// The mapping key that names it (for messages).
    pub key: String,
    /// `false` for a column taken by name that may be absent (truth).
    pub required: bool,
}

/// Where one declared scalar comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// A column of the file, converted.
    Column(Column),
    /// The same value at every row.
    Constant(f64),
}

/// The largest time offset of a file, s (ten years: anything larger is a
/// time in other units, not an offset).
pub const MAX_TIME_OFFSET_S: f64 = 3.2e8;

/// A file and where each of its declared scalars comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct Source {
    /// The file, relative to the log directory.
    pub file: String,
    /// The mapping section (`inputs`, `sensors.Fix`, `truth`).
    pub section: String,
    /// The time column, s after conversion.
    pub time: Column,
    /// Added to every time of the file, s (`time = { .., offset_s = .. }`):
    /// a sensor whose clock runs 0.3 s ahead of the input's takes -0.3.
    pub time_offset_s: f64,
    /// One cell per scalar.
    pub cells: Vec<Cell>,
    /// `false` for a file that may be absent (the default truth file).
    pub required: bool,
}

/// A registered sensor's mapping.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorMapping {
    /// Its file; the cells are the `M` outputs, then the auxiliary inputs.
    pub source: Source,
    /// Measurement noise sigma per output, in the output's SI unit.
    pub sigma: Vec<f64>,
    /// Gate probability (`None`: no gate).
    pub gate: Option<f64>,
}

/// The initial estimate.
#[derive(Debug, Clone, PartialEq)]
pub struct InitialEstimate {
    /// Its epoch, s (`None`: the first input row's time).
    pub t: Option<f64>,
    /// The state, per state scalar.
    pub state: Vec<f64>,
    /// Its sigma, per state scalar.
    pub sigma: Vec<f64>,
}

/// A checked `replay.toml`.
#[derive(Debug, Clone, PartialEq)]
pub struct Mapping {
    /// What feeds the process model's inputs.
    pub inputs: Source,
    /// The parameters, in declaration order.
    pub params: Vec<f64>,
    /// The process noise, in declaration order.
    pub noise: Vec<f64>,
    /// The initial estimate.
    pub initial: InitialEstimate,
    /// Per registered sensor, its mapping (`None`: not fed; said in the
    /// warnings).
    pub sensors: Vec<Option<SensorMapping>>,
    /// The truth to score against, per state.
    pub truth: Source,
    /// What the mapping leaves out.
    pub warnings: Vec<Warning>,
}

impl Mapping {
    /// A warning for each CSV file (`.csv`, `.csv.gz`) at the top of the log
    /// directory `dir` that no section maps (a sensor left out of the
    /// mapping, or a file under another name): its rows feed nothing.
    /// Sorted by name; nothing when the directory cannot be listed (the
    /// files the mapping names are checked when they are opened).
    pub fn unmapped_files(&self, dir: &Path) -> Vec<Warning> {
        let mapped: Vec<&str> = std::iter::once(&self.inputs)
            .chain(self.sensors.iter().flatten().map(|s| &s.source))
            .chain(std::iter::once(&self.truth))
            .map(|s| s.file.trim_start_matches("./"))
            .collect();
        let Ok(entries) = std::fs::read_dir(dir) else {
            return Vec::new();
        };
        let mut names: Vec<String> = entries
            .flatten()
            .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
            .filter_map(|e| e.file_name().into_string().ok())
            .filter(|n| n.ends_with(".csv") || n.ends_with(".csv.gz"))
            .filter(|n| !mapped.contains(&n.as_str()))
            .collect();
        names.sort();
        names
            .into_iter()
            .map(|n| {
                Warning::about(
                    WarningKind::UnusedFile,
                    &n,
                    format!("{n} is in the log directory but no section of the mapping names it: its rows feed nothing"),
                )
            })
            .collect()
    }
}

/// The gate probability when a sensor's section gives none.
pub const DEFAULT_GATE: f64 = 0.9999;

type Result<T> = std::result::Result<T, ModelReplayError>;

/// Checks `text` (the mapping file `file`) against `declared`.
///
/// # Errors
/// See the module docs.
pub fn parse(text: &str, file: &str, declared: &Declared) -> Result<Mapping> {
    let err = mapping_error(file);
    let table = read_table(text, file)?;
    let cx = Cx { err: &err };
    cx.known_keys(
        "",
        &table,
        &[
            "inputs",
            "parameters",
            "noise",
            "initial",
            "sensors",
            "truth",
        ],
    )?;
    let mut warnings = Vec::new();

    // [inputs]
    let inputs = cx.table(&table, "inputs")?.ok_or_else(|| {
        err(
            "inputs",
            format!(
                "missing section: which file feeds the inputs of model {} ({})",
                declared.model,
                blocks(declared.inputs).join(", ")
            ),
        )
    })?;
    cx.known_keys("inputs", inputs, &["file", "time", "columns"])?;
    let inputs = cx.source(
        "inputs",
        inputs,
        None,
        declared.inputs,
        "input",
        declared.model,
        true,
    )?;

    let params = cx.values(&table, "parameters", declared.params, declared.model)?;
    let noise = cx.values(&table, "noise", &declared.noise, declared.model)?;
    // A noise input is a variance (or a density): never negative. The
    // filter would refuse it without naming the key.
    for (i, q) in noise.iter().enumerate() {
        if *q < 0.0 {
            return Err(err(
                &format!("noise.{}", declared.noise[i]),
                format!("{q} is negative: a noise intensity (variance or density) is >= 0"),
            ));
        }
    }

    // [initial]
    let initial = cx.table(&table, "initial")?.ok_or_else(|| {
        err(
            "initial",
            "missing section: the initial state and its sigma (`[initial.state]`, `[initial.sigma]`)"
                .into(),
        )
    })?;
    cx.known_keys("initial", initial, &["t", "state", "sigma"])?;
    let t = initial
        .get("t")
        .map(|v| cx.number("initial.t", v))
        .transpose()?;
    let states: Vec<&str> = declared.states.to_vec();
    let state = cx.values(initial, "state", &states, declared.model)?;
    let sigma = cx.values(initial, "sigma", &states, declared.model)?;
    for (i, s) in sigma.iter().enumerate() {
        // Its square is the initial variance: it must be finite too.
        if *s < 0.0 || !(s * s).is_finite() {
            return Err(err(
                "initial.sigma",
                format!(
                    "`{}`: {s} is not a sigma (finite, >= 0, its square finite)",
                    states[i]
                ),
            ));
        }
    }

    let sensors = cx.sensors(&table, declared, file, &mut warnings)?;

    // [truth]
    let truth = match cx.table(&table, "truth")? {
        Some(t) => {
            cx.known_keys("truth", t, &["file", "time", "columns"])?;
            let mut s = cx.source(
                "truth",
                t,
                Some(TRUTH_FILE),
                &states,
                "state",
                declared.model,
                false,
            )?;
            s.required = t.contains_key("file");
            s
        }
        None => Source {
            file: TRUTH_FILE.into(),
            section: "truth".into(),
            time: Column {
                header: TIME_COLUMN.into(),
                factor: 1.0,
                key: "truth.time".into(),
                required: true,
            },
            time_offset_s: 0.0,
            cells: by_name("truth", &states, false),
            required: false,
        },
    };

    Ok(Mapping {
        inputs,
        params,
        noise,
        initial: InitialEstimate { t, state, sigma },
        sensors,
        truth,
        warnings,
    })
}

/// The error of mapping file `file` at a key.
fn mapping_error(file: &str) -> impl Fn(&str, String) -> ModelReplayError + '_ {
    move |key: &str, problem: String| ModelReplayError::Mapping {
        file: file.to_string(),
        key: key.to_string(),
        line: None,
        problem,
    }
}

/// `text` as TOML, a syntax error placed at its line.
fn read_table(text: &str, file: &str) -> Result<Table> {
    text.parse().map_err(|e: toml::de::Error| {
        let line = e.span().map(|s| {
            let before = &text.as_bytes()[..s.start.min(text.len())];
            1 + before.iter().filter(|b| **b == b'\n').count() as u64
        });
        ModelReplayError::Mapping {
            file: file.to_string(),
            key: String::new(),
            line,
            problem: e.message().to_string(),
        }
    })
}

/// The part of a mapping file an INS vehicle's replay reads
/// (`docs/pipeline.md`, "Sensors of your own"): what the navigator does
/// not know by kind, named as declared.
#[derive(Debug, Clone, PartialEq)]
pub struct AidingMapping {
    /// `[noise]`: the declared process noise beyond the INS core's, per
    /// scalar of `Declared::noise`.
    pub noise: Vec<f64>,
    /// `[initial.sigma]`: per scalar of `Declared::states` (the states the
    /// nominal solution does not keep).
    pub sigma: Vec<f64>,
    /// Per sensor of `Declared::sensors` (those no reading kind feeds).
    pub sensors: Vec<Option<SensorMapping>>,
    /// What the mapping leaves out.
    pub warnings: Vec<Warning>,
}

/// Checks `text` (the mapping file `file` of an INS vehicle's log) against
/// `declared`: its sensors fed by name, its noise and states beyond the
/// navigator's. Sections: `[sensors.<name>]` as in [`parse`], `[noise]`,
/// `[initial.sigma]`.
///
/// # Errors
/// As [`parse`].
pub fn parse_aiding(text: &str, file: &str, declared: &Declared) -> Result<AidingMapping> {
    let err = mapping_error(file);
    let table = read_table(text, file)?;
    let cx = Cx { err: &err };
    cx.known_keys("", &table, &["noise", "initial", "sensors"])?;
    let noise = cx.values(&table, "noise", &declared.noise, declared.model)?;
    if let Some((i, q)) = noise.iter().enumerate().find(|(_, q)| **q < 0.0) {
        return Err(err(
            &format!("noise.{}", declared.noise[i]),
            format!("{q} is negative: a noise intensity (variance or density) is >= 0"),
        ));
    }
    let empty = Table::new();
    let initial = cx.table(&table, "initial")?.unwrap_or(&empty);
    cx.known_keys("initial", initial, &["sigma"])?;
    let sigma = cx.values(initial, "sigma", &declared.states, declared.model)?;
    if let Some((i, s)) = sigma
        .iter()
        .enumerate()
        .find(|(_, s)| **s < 0.0 || !(**s * **s).is_finite())
    {
        return Err(err(
            "initial.sigma",
            format!(
                "`{}`: {s} is not a sigma (finite, >= 0, its square finite)",
                declared.states[i]
            ),
        ));
    }
    let mut warnings = Vec::new();
    let sensors = cx.sensors(&table, declared, file, &mut warnings)?;
    Ok(AidingMapping {
        noise,
        sigma,
        sensors,
        warnings,
    })
}

/// Each scalar from the column of its own name.
fn by_name(section: &str, names: &[&str], required: bool) -> Vec<Cell> {
    names
        .iter()
        .map(|n| {
            Cell::Column(Column {
                header: (*n).to_string(),
                factor: 1.0,
                key: format!("{section}.columns.{}", n),
                required,
            })
        })
        .collect()
}

/// The error maker of one mapping file.
struct Cx<'a> {
    err: &'a dyn Fn(&str, String) -> ModelReplayError,
}

fn join(section: &str, key: &str) -> String {
    if section.is_empty() {
        key.to_string()
    } else {
        format!("{section}.{key}")
    }
}

impl Cx<'_> {
    /// `[sensors.<name>]`: per sensor of `declared`, its mapping (`None`:
    /// not fed, with a warning naming the sensor).
    fn sensors(
        &self,
        table: &Table,
        declared: &Declared,
        file: &str,
        warnings: &mut Vec<Warning>,
    ) -> Result<Vec<Option<SensorMapping>>> {
        let cx = self;
        let err = self.err;
        let mut sensors: Vec<Option<SensorMapping>> = vec![None; declared.sensors.len()];
        if let Some(section) = cx.table(table, "sensors")? {
            let names: Vec<&str> = declared.sensors.iter().map(|s| s.name).collect();
            for (name, value) in section {
                let key = format!("sensors.{name}");
                let Some(k) = names.iter().position(|n| n == name) else {
                    if declared.declared_sensors.contains(&name.as_str()) {
                        return Err(err(
                            &key,
                            format!(
                                "sensor `{name}` of model {} is declared but this program does not register it (registered: {}): add `.sensor::<{}{name}, M>()` (M its outputs) to the program",
                                declared.model,
                                names.join(", "),
                                declared.model
                            ),
                        ));
                    }
                    let mut problem = format!(
                        "model {} has no registered sensor `{name}` (sensors: {})",
                        declared.model,
                        names.join(", ")
                    );
                    if let Some(close) = closest_name(name, &names) {
                        problem.push_str(&format!("; did you mean `{close}`?"));
                    }
                    return Err(err(&key, problem));
                };
                let Value::Table(s) = value else {
                    return Err(err(&key, "expected a table".into()));
                };
                cx.known_keys(&key, s, &["file", "time", "z", "sigma", "gate", "aux"])?;
                let sensor = declared.sensors[k];
                let outputs: Vec<String> = (0..sensor.outputs).map(|i| format!("z[{i}]")).collect();
                let outputs: Vec<&str> = outputs.iter().map(String::as_str).collect();
                let z = s.get("z").ok_or_else(|| {
                    err(
                        &format!("{key}.z"),
                        format!(
                            "missing: one column per output of sensor {name} ({} outputs)",
                            sensor.outputs
                        ),
                    )
                })?;
                let mut cells = cx.cells(&format!("{key}.z"), z, sensor.outputs)?;
                let aux = cx.table(s, "aux")?;
                let mut aux_cells: Vec<Option<Cell>> = vec![None; sensor.aux.len()];
                if let Some(aux) = aux {
                    cx.fill(
                        &format!("{key}.aux"),
                        aux,
                        sensor.aux,
                        "auxiliary input",
                        name,
                        &mut aux_cells,
                    )?;
                }
                for (i, c) in aux_cells.into_iter().enumerate() {
                    match c {
                        Some(c) => cells.push(c),
                        None => {
                            return Err(err(
                                &format!("{key}.aux"),
                                format!(
                            "sensor {name} needs its auxiliary input `{}` (a value or a column)",
                            sensor.aux[i]
                        ),
                            ))
                        }
                    }
                }
                let sigma_value = s.get("sigma").ok_or_else(|| {
                    err(
                        &format!("{key}.sigma"),
                        "missing: the measurement noise sigma (a number, or one per output)".into(),
                    )
                })?;
                let sigma = cx.numbers(&format!("{key}.sigma"), sigma_value, outputs.len())?;
                if let Some(bad) = sigma
                    .iter()
                    .find(|s| !(**s > 0.0 && **s * **s > 0.0 && (**s * **s).is_finite()))
                {
                    // 1e-300 squares to a zero noise: the same as 0.
                    return Err(err(
                        &format!("{key}.sigma"),
                        format!(
                            "{bad} is not a sigma (finite, > 0, its square finite and above 0)"
                        ),
                    ));
                }
                let gate = match s.get("gate") {
                    None => Some(DEFAULT_GATE),
                    Some(Value::Boolean(false)) => None,
                    Some(v) => {
                        let p = cx.number(&format!("{key}.gate"), v)?;
                        if !(p > 0.0 && p < 1.0) {
                            return Err(err(
                                &format!("{key}.gate"),
                                format!("{p} is not a probability in (0, 1) (or `false`: no gate)"),
                            ));
                        }
                        Some(p)
                    }
                };
                let file = cx.file(&key, s)?;
                let (time, time_offset_s) = cx.time(&key, s)?;
                sensors[k] = Some(SensorMapping {
                    source: Source {
                        file,
                        section: key,
                        time,
                        time_offset_s,
                        cells,
                        required: true,
                    },
                    sigma,
                    gate,
                });
            }
        }
        for (s, m) in declared.sensors.iter().zip(&sensors) {
            if m.is_none() {
                warnings.push(Warning {
                    kind: WarningKind::MissingSensorSection,
                    file: Some(file.to_string()),
                    line: None,
                    key: Some(format!("sensors.{}", s.name)),
                    message: format!(
                        "{file} has no [sensors.{}]: sensor {} is not fed by the log",
                        s.name, s.name
                    ),
                });
            }
        }
        Ok(sensors)
    }

    fn known_keys(&self, section: &str, table: &Table, allowed: &[&str]) -> Result<()> {
        for k in table.keys() {
            if !allowed.contains(&k.as_str()) {
                let mut problem = format!("unknown key (allowed: {})", allowed.join(", "));
                if let Some(close) = closest_name(k, allowed) {
                    problem.push_str(&format!("; did you mean `{close}`?"));
                }
                return Err((self.err)(&join(section, k), problem));
            }
        }
        Ok(())
    }

    fn table<'t>(&self, table: &'t Table, key: &str) -> Result<Option<&'t Table>> {
        match table.get(key) {
            None => Ok(None),
            Some(Value::Table(t)) => Ok(Some(t)),
            Some(_) => Err((self.err)(key, "expected a table".into())),
        }
    }

    fn number(&self, key: &str, v: &Value) -> Result<f64> {
        let x = match v {
            Value::Integer(i) => *i as f64,
            Value::Float(f) => *f,
            Value::Table(t) => {
                self.known_keys(key, t, &["value", "unit"])?;
                let value = t.get("value").ok_or_else(|| {
                    (self.err)(
                        key,
                        "expected a number or `{ value = .., unit = \"..\" }`".into(),
                    )
                })?;
                let x = self.number(&join(key, "value"), value)?;
                x * self.unit(key, t)?
            }
            _ => {
                return Err((self.err)(
                    key,
                    format!("expected a number, found {}", v.type_str()),
                ))
            }
        };
        if !x.is_finite() {
            return Err((self.err)(key, format!("{x} is not finite")));
        }
        Ok(x)
    }

    /// `count` numbers: an array of that length, or one number for all.
    fn numbers(&self, key: &str, v: &Value, count: usize) -> Result<Vec<f64>> {
        match v {
            Value::Array(a) => {
                if a.len() != count {
                    return Err((self.err)(
                        key,
                        format!(
                            "expected {count} values (or one for all), found {}",
                            a.len()
                        ),
                    ));
                }
                a.iter()
                    .enumerate()
                    .map(|(i, x)| self.number(&format!("{key}[{i}]"), x))
                    .collect()
            }
            v => Ok(vec![self.number(key, v)?; count]),
        }
    }

    fn unit(&self, key: &str, t: &Table) -> Result<f64> {
        let mut f = match t.get("unit") {
            None => 1.0,
            Some(Value::String(u)) => units::factor(u).ok_or_else(|| {
                (self.err)(
                    &join(key, "unit"),
                    format!(
                        "unknown unit `{u}` (known: {}; any other with `scale`)",
                        units::known()
                    ),
                )
            })?,
            Some(v) => {
                return Err((self.err)(
                    &join(key, "unit"),
                    format!("expected a unit name, found {}", v.type_str()),
                ))
            }
        };
        if let Some(s) = t.get("scale") {
            f *= self.number(&join(key, "scale"), s)?;
        }
        Ok(f)
    }

    /// One cell: a column name, `{ column, unit, scale }`, a number or
    /// `{ value, unit }`.
    fn cell(&self, key: &str, v: &Value) -> Result<Cell> {
        match v {
            Value::String(header) => Ok(Cell::Column(Column {
                header: header.clone(),
                factor: 1.0,
                key: key.to_string(),
                required: true,
            })),
            Value::Table(t) if t.contains_key("column") => {
                self.known_keys(key, t, &["column", "unit", "scale"])?;
                let Some(Value::String(header)) = t.get("column") else {
                    return Err((self.err)(
                        &join(key, "column"),
                        "expected a column name".into(),
                    ));
                };
                Ok(Cell::Column(Column {
                    header: header.clone(),
                    factor: self.unit(key, t)?,
                    key: key.to_string(),
                    required: true,
                }))
            }
            Value::Integer(_) | Value::Float(_) | Value::Table(_) => {
                Ok(Cell::Constant(self.number(key, v)?))
            }
            v => Err((self.err)(
                key,
                format!(
                    "expected a column name, `{{ column = .., unit = .. }}` or a number, found {}",
                    v.type_str()
                ),
            )),
        }
    }

    /// `count` cells: an array of that length, or one cell when `count` is 1
    /// (or a constant for all).
    fn cells(&self, key: &str, v: &Value, count: usize) -> Result<Vec<Cell>> {
        match v {
            Value::Array(a) => {
                if a.len() != count {
                    return Err((self.err)(
                        key,
                        format!(
                            "expected {count} {}, found {}",
                            if count == 1 { "column" } else { "columns" },
                            a.len()
                        ),
                    ));
                }
                a.iter()
                    .enumerate()
                    .map(|(i, x)| self.cell(&format!("{key}[{i}]"), x))
                    .collect()
            }
            v => {
                let c = self.cell(key, v)?;
                if count != 1 && matches!(c, Cell::Column(_)) {
                    return Err((self.err)(
                        key,
                        format!("expected {count} columns (an array), found one"),
                    ));
                }
                Ok(vec![c; count])
            }
        }
    }

    /// Fills `out` (one per declared scalar of `names`) from the keys of
    /// `table`, each naming a scalar or a block of them.
    fn fill(
        &self,
        section: &str,
        table: &Table,
        names: &[&str],
        what: &str,
        owner: &str,
        out: &mut [Option<Cell>],
    ) -> Result<()> {
        let mut given: Vec<Option<String>> = vec![None; names.len()];
        for (k, v) in table {
            let key = join(section, k);
            let scalars = scalars_of(names, k);
            if scalars.is_empty() {
                return Err(self.unknown(&key, k, names, what, owner));
            }
            for (i, c) in scalars.iter().zip(self.cells(&key, v, scalars.len())?) {
                self.once(&mut given, *i, names, &key)?;
                out[*i] = Some(c);
            }
        }
        Ok(())
    }

    /// Records that scalar `i` of `names` is given by `key`: a scalar given
    /// twice (a block and one of its elements, `position` and
    /// `"position[0]"`) is an error naming both keys, not a silent choice.
    fn once(
        &self,
        given: &mut [Option<String>],
        i: usize,
        names: &[&str],
        key: &str,
    ) -> Result<()> {
        if let Some(first) = &given[i] {
            return Err((self.err)(
                key,
                format!(
                    "`{}` is given twice (by `{first}` and by `{key}`): give it once",
                    names[i]
                ),
            ));
        }
        given[i] = Some(key.to_string());
        Ok(())
    }

    fn unknown(
        &self,
        key: &str,
        k: &str,
        names: &[&str],
        what: &str,
        owner: &str,
    ) -> ModelReplayError {
        let blocks = blocks(names);
        let mut problem = if blocks.is_empty() {
            format!("{owner} has no {what}s")
        } else {
            format!(
                "{owner} has no {what} `{k}` ({what}s: {})",
                blocks.join(", ")
            )
        };
        if let Some(close) = closest_name(k, &blocks) {
            problem.push_str(&format!("; did you mean `{close}`?"));
        }
        (self.err)(key, problem)
    }

    /// A value for every scalar of `names` from section `key` of `table`.
    fn values(&self, table: &Table, key: &str, names: &[&str], owner: &str) -> Result<Vec<f64>> {
        let full = |k: &str| {
            if key == "state" || key == "sigma" {
                format!("initial.{key}.{k}")
            } else {
                format!("{key}.{k}")
            }
        };
        let section_key = if key == "state" || key == "sigma" {
            format!("initial.{key}")
        } else {
            key.to_string()
        };
        let mut out: Vec<Option<f64>> = vec![None; names.len()];
        let mut given: Vec<Option<String>> = vec![None; names.len()];
        if let Some(t) = self.table(table, key)? {
            for (k, v) in t {
                let scalars = scalars_of(names, k);
                if scalars.is_empty() {
                    let what = match key {
                        "parameters" => "parameter",
                        "noise" => "noise input",
                        _ => "state",
                    };
                    return Err(self.unknown(&full(k), k, names, what, owner));
                }
                for (i, x) in scalars
                    .iter()
                    .zip(self.numbers(&full(k), v, scalars.len())?)
                {
                    self.once(&mut given, *i, names, &full(k))?;
                    out[*i] = Some(x);
                }
            }
        }
        let missing: Vec<&str> = names
            .iter()
            .zip(&out)
            .filter(|(_, v)| v.is_none())
            .map(|(n, _)| *n)
            .collect();
        if !missing.is_empty() {
            return Err((self.err)(
                &section_key,
                format!(
                    "model {owner} declares {}: give each a value",
                    missing
                        .iter()
                        .map(|n| format!("`{n}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
        Ok(out.into_iter().flatten().collect())
    }

    fn file(&self, section: &str, table: &Table) -> Result<String> {
        let key = join(section, "file");
        match table.get("file") {
            Some(Value::String(f)) => relative_log_path(f).map_err(|p| (self.err)(&key, p)),
            Some(v) => Err((self.err)(
                &key,
                format!("expected a file name, found {}", v.type_str()),
            )),
            None => Err((self.err)(
                &key,
                "missing: the CSV file, relative to the log directory".into(),
            )),
        }
    }

    /// The time column of a section and the offset added to its times:
    /// `time = "column"`, `time = { column = .., unit = .., scale = .. }`,
    /// either table with `offset_s`, or `time = { offset_s = .. }` for the
    /// default column.
    fn time(&self, section: &str, table: &Table) -> Result<(Column, f64)> {
        let key = join(section, "time");
        let default = Column {
            header: TIME_COLUMN.into(),
            factor: 1.0,
            key: key.clone(),
            required: true,
        };
        let Some(v) = table.get("time") else {
            return Ok((default, 0.0));
        };
        let (column, offset) = match v {
            Value::Table(t) if t.contains_key("offset_s") => {
                self.known_keys(&key, t, &["column", "unit", "scale", "offset_s"])?;
                let offset_key = join(&key, "offset_s");
                let offset = match t.get("offset_s") {
                    Some(Value::Integer(i)) => *i as f64,
                    Some(Value::Float(f)) => *f,
                    Some(v) => {
                        return Err((self.err)(
                            &offset_key,
                            format!("expected seconds (a number), found {}", v.type_str()),
                        ))
                    }
                    None => 0.0,
                };
                if !(offset.is_finite() && offset.abs() <= MAX_TIME_OFFSET_S) {
                    return Err((self.err)(
                        &offset_key,
                        format!("{offset} is not an offset in seconds (finite, at most {MAX_TIME_OFFSET_S:e} in size)"),
                    ));
                }
                let mut rest = t.clone();
                rest.remove("offset_s");
                let column = if rest.is_empty() {
                    default
                } else if rest.contains_key("column") {
                    match self.cell(&key, &Value::Table(rest))? {
                        Cell::Column(c) => c,
                        Cell::Constant(_) => default,
                    }
                } else {
                    return Err((self.err)(
                        &key,
                        "`unit` or `scale` without `column`: name the time column".into(),
                    ));
                };
                (column, offset)
            }
            v => match self.cell(&key, v)? {
                Cell::Column(c) => (c, 0.0),
                Cell::Constant(_) => return Err((self.err)(
                    &key,
                    "expected a column name, `{ column = .., unit = .. }` or `{ offset_s = .. }`"
                        .into(),
                )),
            },
        };
        Ok((column, offset))
    }

    /// A `[inputs]`-like section: `file`, `time` and `columns`, every scalar
    /// of `names` not in `columns` taken from the column of its own name.
    #[allow(clippy::too_many_arguments)]
    fn source(
        &self,
        section: &str,
        table: &Table,
        default_file: Option<&str>,
        names: &[&str],
        what: &str,
        owner: &str,
        required: bool,
    ) -> Result<Source> {
        let file = match (table.get("file"), default_file) {
            (None, Some(f)) => f.to_string(),
            _ => self.file(section, table)?,
        };
        let (time, time_offset_s) = self.time(section, table)?;
        let mut cells: Vec<Option<Cell>> = vec![None; names.len()];
        if let Some(columns) = self.table(table, "columns")? {
            self.fill(
                &join(section, "columns"),
                columns,
                names,
                what,
                &format!("model {owner}"),
                &mut cells,
            )?;
        }
        let defaults = by_name(section, names, required);
        let cells = cells
            .into_iter()
            .zip(defaults)
            .map(|(c, d)| c.unwrap_or(d))
            .collect();
        Ok(Source {
            file,
            section: section.to_string(),
            time,
            time_offset_s,
            cells,
            required: true,
        })
    }
}
