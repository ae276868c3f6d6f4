//! `CPUn/` device names of a multi-CPU system (contract §6): `CPU2/D0` is
//! CPU 2's D0; a name without a prefix (or `CPU1/`) is CPU 1's.

/// The CPU (0-based) a name addresses and the name without its prefix;
/// `cpus` is the number of CPUs (a single CPU takes `CPU1/` only).
pub fn split(text: &str, cpus: usize) -> Result<(usize, &str), String> {
    if !text.contains('/') {
        return Ok((0, text));
    }
    match prefix(text) {
        Some((n, rest)) if (1..=cpus).contains(&n) => Ok((n - 1, rest)),
        Some((n, _)) => Err(format!(
            "`{text}`: there is no CPU {n} (the system has CPU 1-{cpus})"
        )),
        None => Err(format!(
            "`{text}`: a CPU prefix is CPU1/ to CPU4/ (as in CPU2/D0)"
        )),
    }
}

/// The number `n` a `CPUn/` prefix writes (not checked against any system)
/// and the name after the prefix; `None` when `text` has no such prefix.
pub fn prefix(text: &str) -> Option<(usize, &str)> {
    let (head, rest) = text.split_once('/')?;
    let digits = head
        .get(..3)
        .filter(|p| p.eq_ignore_ascii_case("CPU"))
        .map(|_| &head[3..])?;
    Some((digits.parse::<usize>().ok()?, rest))
}

#[cfg(test)]
mod tests {
    use super::{prefix, split};

    #[test]
    fn prefixes() {
        assert_eq!(split("D0", 2), Ok((0, "D0")));
        assert_eq!(split("CPU1/D0", 2), Ok((0, "D0")));
        assert_eq!(split("cpu2/D10:f32", 2), Ok((1, "D10:f32")));
        assert!(split("CPU3/D0", 2).unwrap_err().contains("no CPU 3"));
        assert!(split("CPX/D0", 2).unwrap_err().contains("CPU1/"));
        assert_eq!(split("U3E0\\G0", 2), Ok((0, "U3E0\\G0")));
        assert_eq!(prefix("cpu7/D0"), Some((7, "D0")));
        assert_eq!(prefix("CPU/D0"), None);
        assert_eq!(prefix("D0"), None);
    }
}
