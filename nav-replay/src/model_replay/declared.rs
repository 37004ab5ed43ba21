//! The names a declaration gives its model and sensors, which a
//! `replay.toml` refers to: read once from the generated types, so the
//! mapping is checked against exactly what was declared.

use nav_runtime::model::{Model, Record, Sensor};

/// A declared model's scalar names.
#[derive(Debug, Clone)]
pub struct Declared {
    /// The declared model name.
    pub model: &'static str,
    /// State scalars, in vector order (`position[0]`, `heading`, ...).
    pub states: Vec<&'static str>,
    /// Input scalars, in [`Record`] order.
    pub inputs: &'static [&'static str],
    /// Parameter scalars.
    pub params: &'static [&'static str],
    /// Process-noise scalars.
    pub noise: Vec<&'static str>,
    /// The registered sensors, in registration order.
    pub sensors: Vec<DeclaredSensor>,
    /// Every sensor the declaration has, registered or not.
    pub declared_sensors: &'static [&'static str],
}

/// A registered sensor's names.
#[derive(Debug, Clone, Copy)]
pub struct DeclaredSensor {
    /// The declared sensor name (`Fix` of `sensor Fix: 2`).
    pub name: &'static str,
    /// Its number of outputs `M`.
    pub outputs: usize,
    /// Its auxiliary-input scalars.
    pub aux: &'static [&'static str],
}

impl Declared {
    /// The names of model `M` (no sensors yet).
    pub fn of<M: Model<N>, const N: usize>() -> Declared {
        Declared {
            model: M::NAME,
            states: M::STATE_NAMES.to_vec(),
            inputs: <M::Input as Record>::NAMES,
            params: <M::Params as Record>::NAMES,
            noise: <M::Noise as Record>::NAMES.to_vec(),
            sensors: Vec::new(),
            declared_sensors: M::DECLARED_SENSORS,
        }
    }
}

impl DeclaredSensor {
    /// The names of sensor `S`.
    pub fn of<S: Sensor<N, K>, const N: usize, const K: usize>() -> DeclaredSensor {
        DeclaredSensor {
            name: S::NAME,
            outputs: K,
            aux: <S::Aux as Record>::NAMES,
        }
    }
}

pub use nav_runtime::model::{block_of, blocks, scalars_of};
