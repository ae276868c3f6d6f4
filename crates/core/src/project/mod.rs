//! Projects: a directory with `plc.toml` and its program files (contract §1, §4).
//!
//! Not implemented yet.
