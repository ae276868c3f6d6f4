//! The FMU state's bytes (FMI 3.0 §2.3.6): what `fmi3GetFMUState` keeps
//! and `fmi3SerializeFMUState` hands out. Little-endian:
//!
//! - magic `SPLCFMU1`;
//! - the instance: start time and time of the last step (f64), scans of a
//!   single CPU and the scan time in µs (u64);
//! - the variables: their number (u32), then for each whether it is set
//!   but not yet written (u8) and its value (a tag byte 0 bool, 1 integer,
//!   2 float and 8 bytes);
//! - the CPU's or system's state file (softplc-core's snapshot, with its own
//!   header, checksum and identity of the programs), to the end.
//!
//! A load checks all of it before it changes anything.

use softplc_core::access::Value;

const MAGIC: &[u8; 8] = b"SPLCFMU1";

/// The instance's part of a state, besides the variables' and the CPUs'.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Times {
    pub start: f64,
    pub now: f64,
    pub scans: u64,
    pub scan_us: u64,
}

/// A state read back: checked, not yet applied.
pub struct Decoded<'a> {
    pub times: Times,
    pub vars: Vec<(bool, Value)>,
    pub cpus: &'a [u8],
}

pub fn encode(times: Times, vars: &[(bool, &Value)], cpus: &[u8]) -> Vec<u8> {
    let mut b = Vec::with_capacity(64 + vars.len() * 10 + cpus.len());
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&times.start.to_le_bytes());
    b.extend_from_slice(&times.now.to_le_bytes());
    b.extend_from_slice(&times.scans.to_le_bytes());
    b.extend_from_slice(&times.scan_us.to_le_bytes());
    b.extend_from_slice(&(vars.len() as u32).to_le_bytes());
    for (pending, v) in vars {
        b.push(*pending as u8);
        let (tag, bits) = match v {
            Value::Bool(x) => (0u8, *x as u64),
            Value::Int(i) => (1, *i as u64),
            Value::Float(f) => (2, f.to_bits()),
            // No variable is a string (refused at export).
            Value::Str(_) => (1, 0),
        };
        b.push(tag);
        b.extend_from_slice(&bits.to_le_bytes());
    }
    b.extend_from_slice(cpus);
    b
}

/// Reads a state of [`encode`] for `nvars` variables.
pub fn decode(bytes: &[u8], nvars: usize) -> Result<Decoded<'_>, String> {
    let bad = |why: &str| format!("not a state of this FMU: {why}");
    let mut at = 0usize;
    let mut take = |n: usize| -> Result<&[u8], String> {
        let s = bytes
            .get(at..at + n)
            .ok_or_else(|| bad(&format!("it ends after {} bytes", bytes.len())))?;
        at += n;
        Ok(s)
    };
    if take(8)? != MAGIC {
        return Err(bad("it does not start with SPLCFMU1"));
    }
    let mut u64_ = || -> Result<u64, String> {
        Ok(u64::from_le_bytes(take(8)?.try_into().unwrap_or_default()))
    };
    let times = Times {
        start: f64::from_bits(u64_()?),
        now: f64::from_bits(u64_()?),
        scans: u64_()?,
        scan_us: u64_()?,
    };
    if !(times.start.is_finite() && times.now.is_finite()) || times.scan_us == 0 {
        return Err(bad("its times are not valid"));
    }
    let n = u32::from_le_bytes(take(4)?.try_into().unwrap_or_default()) as usize;
    if n != nvars {
        return Err(bad(&format!("it has {n} variables, the FMU {nvars}")));
    }
    let mut vars = Vec::with_capacity(n);
    for _ in 0..n {
        let head = take(2)?;
        let (pending, tag) = (head[0] != 0, head[1]);
        let bits = u64::from_le_bytes(take(8)?.try_into().unwrap_or_default());
        let v = match tag {
            0 => Value::Bool(bits != 0),
            1 => Value::Int(bits as i64),
            2 => Value::Float(f64::from_bits(bits)),
            t => return Err(bad(&format!("unknown value tag {t}"))),
        };
        vars.push((pending, v));
    }
    Ok(Decoded {
        times,
        vars,
        cpus: &bytes[at..],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_state_reads_back_as_written_and_a_short_or_foreign_one_is_refused() {
        let times = Times {
            start: 0.5,
            now: 1.25,
            scans: 75,
            scan_us: 10_000,
        };
        let (a, b) = (Value::Bool(true), Value::Float(-1.5));
        let bytes = encode(times, &[(true, &a), (false, &b)], b"CPUS");
        assert_eq!(bytes.len(), 8 + 32 + 4 + 2 * 10 + 4);
        let d = decode(&bytes, 2).unwrap();
        assert_eq!(d.times, times);
        assert_eq!(d.vars, vec![(true, a), (false, b)]);
        assert_eq!(d.cpus, b"CPUS");
        let e = decode(&bytes, 3).err().unwrap();
        assert!(e.contains("it has 2 variables, the FMU 3"), "{e}");
        let e = decode(&bytes[..30], 2).err().unwrap();
        assert!(e.contains("it ends after 30 bytes"), "{e}");
        let e = decode(b"SPLCSTAT and more", 2).err().unwrap();
        assert!(e.contains("does not start with SPLCFMU1"), "{e}");
    }
}
