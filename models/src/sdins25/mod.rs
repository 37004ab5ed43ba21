//! SDINS-25 (MODELS.md section 1).

pub mod model;
