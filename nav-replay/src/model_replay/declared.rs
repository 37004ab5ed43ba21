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
    pub noise: &'static [&'static str],
    /// The registered sensors, in registration order.
    pub sensors: Vec<DeclaredSensor>,
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
            noise: <M::Noise as Record>::NAMES,
            sensors: Vec::new(),
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

/// The scalars of `names` a key stands for: the scalar of that exact name
/// (`"gyro[1]"`, `heading`), or every scalar of the block of that name
/// (`gyro` for `gyro[0]`..`gyro[2]`, `c_bn` for its nine entries), in order.
pub fn scalars_of(names: &[&str], key: &str) -> Vec<usize> {
    if let Some(i) = names.iter().position(|n| *n == key) {
        return vec![i];
    }
    names
        .iter()
        .enumerate()
        .filter(|(_, n)| block_of(n) == key)
        .map(|(i, _)| i)
        .collect()
}

/// The block a scalar name belongs to: `gyro` of `gyro[1]`, `c_bn` of
/// `c_bn[0][2]`, the name itself for a scalar.
pub fn block_of(name: &str) -> &str {
    name.split('[').next().unwrap_or(name)
}

/// The distinct block names of `names`, in order (for messages).
pub fn blocks<'a>(names: &[&'a str]) -> Vec<&'a str> {
    let mut out: Vec<&'a str> = Vec::new();
    for n in names {
        let b = block_of(n);
        if !out.contains(&b) {
            out.push(b);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{blocks, scalars_of};

    #[test]
    fn keys_stand_for_a_scalar_or_a_whole_block() {
        let names = [
            "speed", "gyro[0]", "gyro[1]", "gyro[2]", "c[0][0]", "c[0][1]",
        ];
        let cases: [(&str, &[usize]); 5] = [
            ("speed", &[0]),
            ("gyro", &[1, 2, 3]),
            ("gyro[2]", &[3]),
            ("c", &[4, 5]),
            ("gyr", &[]),
        ];
        for (key, expected) in cases {
            assert_eq!(scalars_of(&names, key), expected, "{key}");
        }
        assert_eq!(blocks(&names), ["speed", "gyro", "c"]);
    }
}
