//! The encoding of a CPU's state in a state file (contract §7): one
//! description of each piece of state, [`Snap`], walked in three modes —
//! save (write the values), check (read and validate them, change
//! nothing) and load (read them into place). A load first checks the whole
//! file, so a file that is refused leaves the CPU untouched, and the load
//! that follows reads exactly the bytes the check accepted.
//!
//! Little-endian, explicit: scalars in their width, arrays as a count and
//! their elements (the big device arrays copied in bulk), sections as a
//! four-byte tag and a byte length, so a damaged file is refused naming the
//! section where it stops making sense. The file's header, identity and
//! checksum are `softplc_core::snapshot`'s.

use thiserror::Error;

/// Why a state file cannot be loaded into this CPU.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum StateError {
    #[error("the state file ends early (in {0})")]
    Truncated(&'static str),
    #[error("{what}: the state file holds {found}, this CPU has {expected}")]
    Mismatch {
        what: &'static str,
        found: u64,
        expected: u64,
    },
    #[error("{what}: {value} is not a valid value")]
    Invalid { what: &'static str, value: u64 },
    #[error("section {found:?} where {expected:?} belongs")]
    Section { expected: String, found: String },
    #[error("{0} extra bytes after the last section")]
    Trailing(usize),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Save,
    Check,
    Load,
}

/// The walker over a CPU's state: see the module documentation.
#[derive(Debug)]
pub struct Snap<'a> {
    mode: Mode,
    out: Vec<u8>,
    input: &'a [u8],
    pos: usize,
    err: Option<StateError>,
    /// The section being read, for errors.
    what: &'static str,
}

impl Snap<'static> {
    /// Writes the state it is walked over, after `header`.
    pub fn save(header: Vec<u8>) -> Snap<'static> {
        Snap {
            mode: Mode::Save,
            out: header,
            input: &[],
            pos: 0,
            err: None,
            what: "state",
        }
    }
}

impl<'a> Snap<'a> {
    /// Reads and validates `input` without changing what it is walked over.
    pub fn check(input: &'a [u8]) -> Snap<'a> {
        Snap::reading(Mode::Check, input)
    }

    /// Reads `input` into what it is walked over (after a [`Snap::check`]
    /// of the same bytes and the same state succeeded).
    pub fn load(input: &'a [u8]) -> Snap<'a> {
        Snap::reading(Mode::Load, input)
    }

    fn reading(mode: Mode, input: &'a [u8]) -> Snap<'a> {
        Snap {
            mode,
            out: Vec::new(),
            input,
            pos: 0,
            err: None,
            what: "state",
        }
    }

    pub fn saving(&self) -> bool {
        self.mode == Mode::Save
    }

    /// Values read are to be stored.
    pub fn loading(&self) -> bool {
        self.mode == Mode::Load && self.err.is_none()
    }

    /// The bytes written (save), or whether the input was read whole and
    /// valid (check, load).
    pub fn finish(self) -> Result<Vec<u8>, StateError> {
        if let Some(e) = self.err {
            return Err(e);
        }
        if self.mode != Mode::Save && self.pos != self.input.len() {
            return Err(StateError::Trailing(self.input.len() - self.pos));
        }
        Ok(self.out)
    }

    /// Records the first error; everything after it reads nothing.
    pub fn fail(&mut self, e: StateError) {
        self.err.get_or_insert(e);
    }

    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        if self.err.is_some() {
            return None;
        }
        let Some(b) = self.input.get(self.pos..self.pos.saturating_add(n)) else {
            self.fail(StateError::Truncated(self.what));
            return None;
        };
        self.pos += n;
        Some(b)
    }

    /// Saves `cur`, or reads the bytes that stand for it.
    fn scalar<const N: usize>(&mut self, cur: [u8; N]) -> Option<[u8; N]> {
        if self.saving() {
            self.out.extend_from_slice(&cur);
            return None;
        }
        self.take(N).and_then(|b| <[u8; N]>::try_from(b).ok())
    }

    /// A section: `tag` and the byte length of what `f` walks, checked on
    /// reading (`name` is what errors call it).
    pub fn section(&mut self, tag: [u8; 4], name: &'static str, f: impl FnOnce(&mut Self)) {
        let outer = std::mem::replace(&mut self.what, name);
        if self.saving() {
            self.out.extend_from_slice(&tag);
            let at = self.out.len();
            self.out.extend_from_slice(&[0; 8]);
            f(self);
            let len = (self.out.len() - at - 8) as u64;
            self.out[at..at + 8].copy_from_slice(&len.to_le_bytes());
        } else if let Some(found) = self.scalar([0u8; 4]) {
            if found != tag {
                let text = |t: [u8; 4]| String::from_utf8_lossy(&t).into_owned();
                self.fail(StateError::Section {
                    expected: text(tag),
                    found: text(found),
                });
            }
            let len = self.scalar([0; 8]).map(u64::from_le_bytes);
            let start = self.pos;
            f(self);
            if let Some(len) = len {
                if self.err.is_none() && (self.pos - start) as u64 != len {
                    self.fail(StateError::Mismatch {
                        what: name,
                        found: len,
                        expected: (self.pos - start) as u64,
                    });
                }
            }
        }
        self.what = outer;
    }

    /// Saves `cur`, or reads the value in the file (even when only
    /// checking: it decides what follows); `cur` after an error.
    fn value_u64(&mut self, cur: u64) -> u64 {
        self.scalar(cur.to_le_bytes())
            .map_or(cur, u64::from_le_bytes)
    }

    fn value_u8(&mut self, cur: u8) -> u8 {
        self.scalar([cur]).map_or(cur, |[b]| b)
    }

    /// A flag as [`Self::value_u8`]; a byte above 1 is damage.
    fn value_bool(&mut self, cur: bool) -> bool {
        match self.value_u8(cur as u8) {
            0 => false,
            1 => true,
            b => {
                self.invalid(u64::from(b));
                cur
            }
        }
    }

    /// A part the saving CPU may have had and this one may not: saved
    /// when `here` holds it (its `key` — what it is of — and the section
    /// `f` walks); on reading walked when the file has one with the same
    /// key and `here` is true, else skipped. False when it was not walked.
    pub fn optional(
        &mut self,
        tag: [u8; 4],
        name: &'static str,
        here: bool,
        key: &str,
        f: impl FnOnce(&mut Self),
    ) -> bool {
        let in_file = self.value_bool(here);
        if !in_file || self.err.is_some() {
            return false;
        }
        let file_key = self.value_string(key, 1 << 20);
        if self.saving() || (here && file_key == key) {
            self.section(tag, name, f);
            return self.err.is_none();
        }
        // Not for this CPU: over its bytes.
        let outer = std::mem::replace(&mut self.what, name);
        if let Some(found) = self.scalar([0u8; 4]) {
            if found != tag {
                self.fail(StateError::Section {
                    expected: String::from_utf8_lossy(&tag).into_owned(),
                    found: String::from_utf8_lossy(&found).into_owned(),
                });
            }
        }
        let len = self.value_u64(0);
        match usize::try_from(len) {
            Ok(n) => {
                self.take(n);
            }
            Err(_) => self.invalid(len),
        }
        self.what = outer;
        false
    }

    /// A `u64` that decides what follows or bounds later values: saves
    /// `cur`, or reads the file's value even when only checking.
    pub fn value(&mut self, cur: u64) -> u64 {
        self.value_u64(cur)
    }

    /// A `u64` that must be at most `max` (a time that cannot be after the
    /// clock, a time not far beyond it).
    pub fn at_most(&mut self, x: &mut u64, max: u64) {
        let v = self.value_u64(*x);
        if !self.saving() && v > max {
            self.invalid(v);
        } else if self.loading() {
            *x = v;
        }
    }

    pub fn u8(&mut self, x: &mut u8) {
        if let Some(b) = self.scalar([*x]) {
            if self.loading() {
                *x = b[0];
            }
        }
    }

    pub fn bool(&mut self, x: &mut bool) {
        let v = self.value_bool(*x);
        if self.loading() {
            *x = v;
        }
    }

    pub fn u16(&mut self, x: &mut u16) {
        if let Some(b) = self.scalar(x.to_le_bytes()) {
            if self.loading() {
                *x = u16::from_le_bytes(b);
            }
        }
    }

    pub fn u32(&mut self, x: &mut u32) {
        if let Some(b) = self.scalar(x.to_le_bytes()) {
            if self.loading() {
                *x = u32::from_le_bytes(b);
            }
        }
    }

    pub fn u64(&mut self, x: &mut u64) {
        if let Some(b) = self.scalar(x.to_le_bytes()) {
            if self.loading() {
                *x = u64::from_le_bytes(b);
            }
        }
    }

    pub fn i32(&mut self, x: &mut i32) {
        if let Some(b) = self.scalar(x.to_le_bytes()) {
            if self.loading() {
                *x = i32::from_le_bytes(b);
            }
        }
    }

    pub fn i64(&mut self, x: &mut i64) {
        if let Some(b) = self.scalar(x.to_le_bytes()) {
            if self.loading() {
                *x = i64::from_le_bytes(b);
            }
        }
    }

    pub fn usize(&mut self, x: &mut usize) {
        let v = self.value_u64(*x as u64);
        match usize::try_from(v) {
            Ok(v) if self.loading() => *x = v,
            Ok(_) => {}
            Err(_) => self.invalid(v),
        }
    }

    /// An `f64` bit for bit.
    pub fn f64(&mut self, x: &mut f64) {
        let mut bits = x.to_bits();
        self.u64(&mut bits);
        if self.loading() {
            *x = f64::from_bits(bits);
        }
    }

    /// A `usize` that must stay below `bound` (an index).
    pub fn index(&mut self, x: &mut usize, bound: usize) {
        let v = self.value_u64(*x as u64);
        if !self.saving() && v >= bound as u64 {
            self.invalid(v);
        } else if self.loading() {
            *x = v as usize;
        }
    }

    /// One of `all` (an enum without data), stored as its position.
    pub fn one_of<T: Copy + PartialEq>(&mut self, x: &mut T, all: &[T]) {
        let i = self.value_u8(all.iter().position(|a| a == x).unwrap_or(0) as u8);
        if !self.saving() {
            match all.get(i as usize) {
                Some(v) if self.loading() => *x = *v,
                Some(_) => {}
                None => self.invalid(i as u64),
            }
        }
    }

    fn invalid(&mut self, value: u64) {
        let what = self.what;
        self.fail(StateError::Invalid { what, value });
    }

    /// A count that must equal `expected` (an array this CPU sized at
    /// load); false when it does not, or after an error.
    pub fn same_len(&mut self, expected: usize) -> bool {
        let n = self.value_u64(expected as u64);
        if self.saving() {
            return true;
        }
        if self.err.is_none() && n != expected as u64 {
            let what = self.what;
            self.fail(StateError::Mismatch {
                what,
                found: n,
                expected: expected as u64,
            });
        }
        self.err.is_none()
    }

    /// A flag that must be as this CPU has it (a part present or not by
    /// its configuration).
    pub fn same(&mut self, present: bool) -> bool {
        let read = self.value_bool(present);
        if self.err.is_none() && read != present {
            let what = self.what;
            self.fail(StateError::Mismatch {
                what,
                found: read as u64,
                expected: present as u64,
            });
        }
        present && self.err.is_none()
    }

    /// Reads `n` bytes of an array and decodes each `N`-byte element.
    fn bulk<T, const N: usize>(
        &mut self,
        x: &mut [T],
        enc: impl Fn(&T) -> [u8; N],
        dec: impl Fn([u8; N]) -> Option<T>,
    ) {
        if !self.same_len(x.len()) {
            return;
        }
        if self.saving() {
            self.out.reserve(x.len() * N);
            for v in x.iter() {
                self.out.extend_from_slice(&enc(v));
            }
            return;
        }
        let Some(bytes) = self.take(x.len() * N) else {
            return;
        };
        let load = self.mode == Mode::Load;
        for (i, c) in bytes.chunks_exact(N).enumerate() {
            let Ok(a) = <[u8; N]>::try_from(c) else {
                return;
            };
            match dec(a) {
                Some(v) if load => x[i] = v,
                Some(_) => {}
                None => return self.invalid(u64::from(c[0])),
            }
        }
    }

    pub fn bools(&mut self, x: &mut [bool]) {
        self.bulk(x, |b| [*b as u8], |[b]| (b <= 1).then_some(b == 1));
    }

    pub fn words(&mut self, x: &mut [u16]) {
        self.bulk(x, |w| w.to_le_bytes(), |b| Some(u16::from_le_bytes(b)));
    }

    pub fn u32s(&mut self, x: &mut [u32]) {
        self.bulk(x, |w| w.to_le_bytes(), |b| Some(u32::from_le_bytes(b)));
    }

    pub fn u64s(&mut self, x: &mut [u64]) {
        self.bulk(x, |w| w.to_le_bytes(), |b| Some(u64::from_le_bytes(b)));
    }

    /// An optional value; `T::default()` is what a check reads into.
    pub fn option<T: Default>(&mut self, x: &mut Option<T>, f: impl FnOnce(&mut Self, &mut T)) {
        let some = self.value_bool(x.is_some());
        if self.saving() {
            if let Some(v) = x {
                f(self, v);
            }
            return;
        }
        if some {
            let mut v = T::default();
            f(self, &mut v);
            if self.loading() {
                *x = Some(v);
            }
        } else if self.loading() {
            *x = None;
        }
    }

    /// A list of at most `max` items: saved from `cur`; read into a new
    /// vector, returned when loading.
    pub fn list<'x, T: Default + 'x>(
        &mut self,
        cur: impl ExactSizeIterator<Item = &'x mut T>,
        max: usize,
        mut f: impl FnMut(&mut Self, &mut T),
    ) -> Option<Vec<T>> {
        let n = self.value_u64(cur.len() as u64);
        if self.saving() {
            for v in cur {
                f(self, v);
            }
            return None;
        }
        if n > max as u64 {
            self.invalid(n);
            return None;
        }
        let mut items = Vec::with_capacity(n as usize);
        for _ in 0..n {
            let mut v = T::default();
            f(self, &mut v);
            items.push(v);
        }
        self.loading().then_some(items)
    }

    /// A string of at most `max` bytes of UTF-8.
    pub fn string(&mut self, x: &mut String, max: usize) {
        let v = self.value_string(x, max);
        if self.loading() {
            *x = v;
        }
    }

    /// Saves `cur`, or reads the string in the file (even when only
    /// checking); `cur` after an error.
    fn value_string(&mut self, cur: &str, max: usize) -> String {
        let n = self.value_u64(cur.len() as u64);
        if self.saving() {
            self.out.extend_from_slice(cur.as_bytes());
            return cur.to_string();
        }
        if n > max as u64 {
            self.invalid(n);
            return cur.to_string();
        }
        let Some(b) = self.take(n as usize) else {
            return cur.to_string();
        };
        match std::str::from_utf8(b) {
            Ok(s) => s.to_string(),
            Err(_) => {
                self.invalid(n);
                cur.to_string()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Default, PartialEq)]
    struct Thing {
        a: u32,
        flag: bool,
        words: Vec<u16>,
        name: String,
        opt: Option<u64>,
    }

    fn walk(s: &mut Snap, t: &mut Thing) {
        s.section(*b"THNG", "thing", |s| {
            s.u32(&mut t.a);
            s.bool(&mut t.flag);
            s.words(&mut t.words);
            s.string(&mut t.name, 16);
            s.option(&mut t.opt, |s, v| s.u64(v));
        });
    }

    fn thing() -> Thing {
        Thing {
            a: 0x1234_5678,
            flag: true,
            words: vec![1, 0xFFFF, 3],
            name: "ab".into(),
            opt: Some(7),
        }
    }

    #[test]
    fn saves_little_endian_and_loads_back() {
        let mut t = thing();
        let mut s = Snap::save(Vec::new());
        walk(&mut s, &mut t);
        let bytes = s.finish().unwrap();
        // Tag, length, then a = 0x12345678 low byte first.
        assert_eq!(&bytes[..4], b"THNG");
        assert_eq!(&bytes[12..16], &[0x78, 0x56, 0x34, 0x12]);
        let mut back = Thing {
            words: vec![0; 3],
            ..Default::default()
        };
        let mut c = Snap::check(&bytes);
        walk(&mut c, &mut back);
        c.finish().unwrap();
        assert_eq!(back.a, 0, "a check changes nothing");
        let mut l = Snap::load(&bytes);
        walk(&mut l, &mut back);
        l.finish().unwrap();
        assert_eq!(back, thing());
    }

    #[test]
    fn refuses_another_size_a_bad_bool_and_a_short_file() {
        let mut t = thing();
        let mut s = Snap::save(Vec::new());
        walk(&mut s, &mut t);
        let bytes = s.finish().unwrap();
        let mut other = Thing {
            words: vec![0; 4],
            ..Default::default()
        };
        let mut c = Snap::check(&bytes);
        walk(&mut c, &mut other);
        assert_eq!(
            c.finish(),
            Err(StateError::Mismatch {
                what: "thing",
                found: 3,
                expected: 4
            })
        );
        let mut bad = bytes.clone();
        bad[16] = 2; // the flag
        let mut same = Thing {
            words: vec![0; 3],
            ..Default::default()
        };
        let mut c = Snap::check(&bad);
        walk(&mut c, &mut same);
        assert_eq!(
            c.finish(),
            Err(StateError::Invalid {
                what: "thing",
                value: 2
            })
        );
        let mut c = Snap::check(&bytes[..bytes.len() - 1]);
        walk(&mut c, &mut same);
        assert_eq!(c.finish(), Err(StateError::Truncated("thing")));
    }
}
