//! The estimators of the source papers (MODELS.md), declared with `nav_runtime::model!`.
