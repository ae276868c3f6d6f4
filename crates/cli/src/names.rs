//! The `--dialect` option; device names are `softplc_core::names::DevName`.

/// How a single program file is read (`--dialect`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DialectArg {
    Melsec,
    Aplc,
}
