//! Diagnostics collection and the typed accessors every section reader uses.

use std::ops::Range;
use std::time::Duration;

use super::tree::{Entry, Item, Value};
use super::units::{self, parse_duration};
use crate::program::{Diagnostic, Diagnostics};

/// The file being read and the diagnostics found so far.
pub(crate) struct Ctx<'a> {
    file: String,
    src: &'a str,
    diags: Vec<(usize, Diagnostic)>,
    /// Byte offset of the start of every line: diagnostics find their line by
    /// binary search, so thousands of errors cost O(n log n), not O(n²).
    line_starts: Vec<usize>,
}

impl<'a> Ctx<'a> {
    pub fn new(file: &str, src: &'a str) -> Self {
        let line_starts = std::iter::once(0)
            .chain(src.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Ctx {
            file: file.to_string(),
            src,
            diags: Vec::new(),
            line_starts,
        }
    }

    /// 1-based line and column (in characters) of a byte offset.
    fn line_col(&self, offset: usize) -> (u32, u32) {
        let mut offset = offset.min(self.src.len());
        while !self.src.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.line_starts.partition_point(|&s| s <= offset).max(1);
        let start = self.line_starts[line - 1];
        let col = self.src[start..offset].chars().count();
        (
            u32::try_from(line).unwrap_or(u32::MAX),
            u32::try_from(col + 1).unwrap_or(u32::MAX),
        )
    }

    /// Reports an error at the start of `span`.
    pub fn error(&mut self, span: &Range<usize>, message: impl Into<String>) {
        let (line, col) = self.line_col(span.start);
        self.diags.push((
            span.start,
            Diagnostic {
                file: self.file.clone(),
                line,
                col,
                message: message.into(),
            },
        ));
    }

    pub fn has_errors(&self) -> bool {
        !self.diags.is_empty()
    }

    /// Every diagnostic, in file order.
    pub fn finish(mut self) -> Diagnostics {
        self.diags.sort_by_key(|(at, _)| *at);
        Diagnostics(self.diags.into_iter().map(|(_, d)| d).collect())
    }

    /// Reports every key of `entries` not in `known`; `section` names the table
    /// (`[ras]`) or is `None` at the top level.
    pub fn unknown_keys(&mut self, entries: &[Entry], section: Option<&str>, known: &[&str]) {
        for e in entries {
            if !known.contains(&e.key.as_str()) {
                self.unknown_key(e, section, known);
            }
        }
    }

    pub fn unknown_key(&mut self, e: &Entry, section: Option<&str>, known: &[&str]) {
        let place = section.map(|s| format!(" in {s}")).unwrap_or_default();
        let msg = match suggest(&e.key, known) {
            Some(s) => format!("unknown key \"{}\"{place}; did you mean \"{s}\"?", e.key),
            None => format!(
                "unknown key \"{}\"{place} (expected {})",
                e.key,
                known.join(", ")
            ),
        };
        self.error(&e.key_span, msg);
    }

    /// The entry's value as a table, or an error.
    pub fn table<'t>(&mut self, e: &'t Entry, what: &str) -> Option<&'t [Entry]> {
        match &e.item.value {
            Value::Table(t) => Some(t),
            Value::Array(a) if a.iter().all(|i| matches!(i.value, Value::Table(_))) => {
                self.error(
                    &e.item.span,
                    format!("{what} must be a single table; write [{}] once", e.key),
                );
                None
            }
            v => {
                self.error(
                    &e.item.span,
                    format!("{what} must be a table, not {}", v.type_name()),
                );
                None
            }
        }
    }

    /// The entry's value as an array of tables (`[[name]]`), each with its
    /// item; an empty array or any other value is the error `message`.
    pub fn tables<'t>(
        &mut self,
        e: &'t Entry,
        message: &str,
    ) -> Option<Vec<(&'t Item, &'t [Entry])>> {
        let tables: Vec<(&Item, &[Entry])> = match &e.item.value {
            Value::Array(items) => items
                .iter()
                .filter_map(|i| match &i.value {
                    Value::Table(t) => Some((i, t.as_slice())),
                    _ => None,
                })
                .collect(),
            _ => Vec::new(),
        };
        if matches!(&e.item.value, Value::Array(a) if a.len() == tables.len() && !a.is_empty()) {
            Some(tables)
        } else {
            self.error(&e.item.span, message);
            None
        }
    }

    /// The entry's value as a string, or an error saying what was expected.
    pub fn string<'t>(&mut self, e: &'t Entry, expected: &str) -> Option<&'t str> {
        self.item_string(&e.key, &e.item, expected)
    }

    pub fn item_string<'t>(
        &mut self,
        what: &str,
        item: &'t Item,
        expected: &str,
    ) -> Option<&'t str> {
        match &item.value {
            Value::Str(s) => Some(s),
            v => {
                self.error(
                    &item.span,
                    format!("{what} must be {expected}, not {}", v.type_name()),
                );
                None
            }
        }
    }

    /// The entry's value as a boolean, or an error saying what was expected.
    pub fn bool(&mut self, e: &Entry, expected: &str) -> Option<bool> {
        match &e.item.value {
            Value::Bool(b) => Some(*b),
            v => {
                self.error(
                    &e.item.span,
                    format!("{} must be {expected}, not {}", e.key, v.type_name()),
                );
                None
            }
        }
    }

    /// A duration string checked against a setting range.
    pub fn duration(&mut self, e: &Entry, range: units::Range) -> Option<Duration> {
        let text = self.string(e, "a duration string such as \"100ms\"")?;
        let d = self.parse_duration(e, text)?;
        if range.contains(d) {
            Some(d)
        } else {
            self.error(
                &e.item.span,
                format!(
                    "{} \"{text}\" is out of range ({})",
                    e.key,
                    range.describe()
                ),
            );
            None
        }
    }

    /// A duration string, or an error at the value.
    pub fn parse_duration(&mut self, e: &Entry, text: &str) -> Option<Duration> {
        let d = parse_duration(text);
        if d.is_none() {
            self.error(
                &e.item.span,
                format!(
                    "{} \"{text}\" is not a duration (write a number and a unit: \"100ms\", \"0.5ms\", \"2s\", \"500us\")",
                    e.key
                ),
            );
        }
        d
    }

    /// One of a fixed set of words.
    pub fn choice<T: Copy>(&mut self, e: &Entry, choices: &[(&str, T)]) -> Option<T> {
        let names: Vec<&str> = choices.iter().map(|(n, _)| *n).collect();
        let list = names.join(", ");
        let text = self.string(e, &format!("one of {list} (a string)"))?;
        match choices.iter().find(|(n, _)| *n == text) {
            Some((_, v)) => Some(*v),
            None => {
                self.error(
                    &e.item.span,
                    format!("{} \"{text}\" is not one of {list}", e.key),
                );
                None
            }
        }
    }
}

/// The known key closest to `key` (case-insensitive edit distance ≤ 2, or ≤ 1
/// for short keys), for "did you mean" hints.
fn suggest<'k>(key: &str, known: &[&'k str]) -> Option<&'k str> {
    let key = key.to_ascii_lowercase();
    let len = key.chars().count();
    // A one-letter key is "near" every other one-letter key: no hint then.
    let limit = if len <= 3 { 1 } else { 2 }.min(len.saturating_sub(1));
    known
        .iter()
        .map(|k| (distance(&key, &k.to_ascii_lowercase()), *k))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// Levenshtein distance over characters.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions() {
        let known = ["watchdog", "constant_scan", "operation_error"];
        assert_eq!(suggest("watchdg", &known), Some("watchdog"));
        assert_eq!(suggest("Constant_Scan", &known), Some("constant_scan"));
        assert_eq!(suggest("constantscan", &known), Some("constant_scan"));
        assert_eq!(suggest("xyz", &known), None);
        assert_eq!(suggest("cpy", &["cpu", "ras"]), Some("cpu"));
        assert_eq!(suggest("Q", &["M", "ST"]), None);
        assert_eq!(distance("kitten", "sitting"), 3);
    }

    #[test]
    fn line_col_by_binary_search_matches_the_scan() {
        let src = "a = 1\n[x]\nkey = \"é\" x\n\nlast";
        let cx = Ctx::new("f", src);
        for off in 0..=src.len() + 2 {
            assert_eq!(
                cx.line_col(off),
                super::super::tree::line_col(src, off),
                "{off}"
            );
        }
    }
}
