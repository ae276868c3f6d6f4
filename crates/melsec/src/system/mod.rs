//! MELSEC-Q's system: its error numbering ([`codes`]).

pub mod codes;
