//! MARKER-9 (MODELS.md section 4).

pub mod model;
