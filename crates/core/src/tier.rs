//! Which tier executes the programs (issue #17): `[cpu] exec` in plc.toml,
//! `--exec` on the command line and `SOFTPLC_EXEC` for test harnesses, in
//! that order of precedence: `--exec` > `SOFTPLC_EXEC` > `[cpu] exec` > auto.

use crate::engine::tier::TierStats;
use crate::engine::Cpu;
pub use softplc_jit::Jit;

/// The environment variable that chooses the tier for harnesses and runs.
pub const ENV: &str = "SOFTPLC_EXEC";

/// The environment variable that sets the JIT's shortest native run
/// ([`Jit::with_min_run`]; default `plan::MIN_RUN`): for measuring the
/// trade-off (docs/performance.md) and for tests that want the most native
/// code (1).
pub const MIN_RUN_ENV: &str = "SOFTPLC_JIT_MIN_RUN";

/// The JIT, with `SOFTPLC_JIT_MIN_RUN` if set: a number from 1 (an invalid
/// value is an error naming it).
fn jit_from_env() -> Result<Jit, String> {
    let Ok(v) = std::env::var(MIN_RUN_ENV) else {
        return Ok(Jit::default());
    };
    match v.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(Jit::with_min_run(n)),
        _ => Err(format!("{MIN_RUN_ENV}={v}: not a number from 1")),
    }
}

/// An execution tier choice.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Exec {
    /// The JIT where the host supports it, else the interpreter.
    #[default]
    Auto,
    /// Native code (Cranelift); an error where the host has none.
    Jit,
    /// The interpreter alone (the reference).
    Interp,
}

impl Exec {
    /// The names of `[cpu] exec`, `--exec` and `SOFTPLC_EXEC`.
    pub const CHOICES: [(&'static str, Exec); 3] = [
        ("auto", Exec::Auto),
        ("jit", Exec::Jit),
        ("interp", Exec::Interp),
    ];

    pub fn parse(s: &str) -> Result<Exec, String> {
        Exec::CHOICES
            .iter()
            .find(|(n, _)| *n == s)
            .map(|(_, e)| *e)
            .ok_or_else(|| format!("exec \"{s}\" is not one of auto, jit, interp"))
    }

    /// `SOFTPLC_EXEC`, if set (an invalid value is an error naming it).
    pub fn from_env() -> Result<Option<Exec>, String> {
        match std::env::var(ENV) {
            Ok(v) => Exec::parse(v.trim())
                .map(Some)
                .map_err(|e| format!("{ENV}: {e}")),
            Err(_) => Ok(None),
        }
    }

    /// The choice in force: `flag` (`--exec`) > `SOFTPLC_EXEC` > `project`
    /// (`[cpu] exec`) > auto.
    pub fn choose(flag: Option<Exec>, project: Option<Exec>) -> Result<Exec, String> {
        if let Some(e) = flag {
            return Ok(e);
        }
        Ok(Exec::from_env()?.or(project).unwrap_or_default())
    }
}

/// Puts `cpu` on the tier `exec` chooses: `Some(stats)` when it runs native
/// code (its compile time), `None` on the interpreter.
pub fn apply(cpu: &mut Cpu, exec: Exec) -> Result<Option<TierStats>, String> {
    match exec {
        Exec::Interp => {
            cpu.use_interpreter();
            Ok(None)
        }
        Exec::Auto if softplc_jit::available().is_err() => Ok(None),
        Exec::Auto | Exec::Jit => {
            softplc_jit::available().map_err(|e| format!("exec = \"jit\": {e}"))?;
            cpu.use_tier(&jit_from_env()?).cloned().map(Some)
        }
    }
}

/// For test harnesses: the tier `SOFTPLC_EXEC` names, the interpreter when
/// it is unset, with `SOFTPLC_JIT_MIN_RUN` on the JIT (`.ci/run` runs the
/// golden tests with 1, the most native code). Panics on an invalid value or
/// a failed compile (a test failure, with the reason).
pub fn apply_env(cpu: &mut Cpu) {
    let exec = Exec::from_env()
        .unwrap_or_else(|e| panic!("{e}"))
        .unwrap_or(Exec::Interp);
    apply(cpu, exec).unwrap_or_else(|e| panic!("{e}"));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_the_flag_wins() {
        assert_eq!(Exec::parse("jit"), Ok(Exec::Jit));
        assert_eq!(Exec::parse("interp"), Ok(Exec::Interp));
        assert_eq!(Exec::parse("auto"), Ok(Exec::Auto));
        assert!(Exec::parse("fast").unwrap_err().contains("\"fast\""));
        assert_eq!(
            Exec::choose(Some(Exec::Interp), Some(Exec::Jit)),
            Ok(Exec::Interp)
        );
    }
}
