//! Battery-backed memory: latched devices, file registers, error history and the
//! clock offset, kept in a state directory across process exits and crashes.
//!
//! Not implemented yet.
