//! A TOML document as a tree in which every key and value knows its byte span,
//! so that every diagnostic can point at the offending text.
//!
//! `toml::Spanned` cannot be used directly: values without a span of their own
//! (the implicit `a` of a `[a.b]` header) and TOML date-times make it fail. The
//! small deserializers below speak the same private protocol `toml::Spanned`
//! uses (serde_spanned's field names) and fall back to "no span" where toml
//! gives none; [`parse`] then fills every missing span from the nearest key or
//! parent, so the tree handed out always has positions.

use std::fmt;
use std::ops::Range;

use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};

/// serde_spanned's protocol (toml 0.8 / serde_spanned 0.6): a value is asked for
/// as this struct, and a deserializer that knows the span answers with a map of
/// start, end and value.
const SPANNED_NAME: &str = "$__serde_spanned_private_Spanned";
const SPANNED_START: &str = "$__serde_spanned_private_start";
const SPANNED_END: &str = "$__serde_spanned_private_end";
const SPANNED_VALUE: &str = "$__serde_spanned_private_value";
const SPANNED_FIELDS: &[&str] = &[SPANNED_START, SPANNED_END, SPANNED_VALUE];
/// toml_datetime's protocol: a date-time arrives as a one-entry map with this key.
const DATETIME_FIELD: &str = "$__toml_private_datetime";

/// A TOML value with its byte span in the source.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Item {
    pub span: Range<usize>,
    pub value: Value,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Value {
    Str(String),
    Int(i64),
    Float(f64),
    Bool(bool),
    /// A TOML date-time, as its text (`2000-01-01T00:00:00`).
    Datetime(String),
    Array(Vec<Item>),
    /// Entries in document order.
    Table(Vec<Entry>),
}

/// One `key = value` of a table.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Entry {
    pub key: String,
    pub key_span: Range<usize>,
    pub item: Item,
}

impl Value {
    /// The TOML type name, for "must be a …" messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Str(_) => "a string",
            Value::Int(_) => "an integer",
            Value::Float(_) => "a float",
            Value::Bool(_) => "a boolean",
            Value::Datetime(_) => "a date-time",
            Value::Array(_) => "an array",
            Value::Table(_) => "a table",
        }
    }
}

/// A TOML syntax error: message and byte span.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct SyntaxError {
    pub message: String,
    pub span: Range<usize>,
}

/// Parses a TOML document into a fully spanned tree (the root is a table).
pub(crate) fn parse(src: &str) -> Result<Item, SyntaxError> {
    let raw: RawNode = toml::from_str(src).map_err(|e| SyntaxError {
        message: e
            .message()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join("; "),
        span: e.span().unwrap_or(0..0),
    })?;
    Ok(raw.finish(0..0))
}

/// A node as deserialized: spans may be missing.
#[derive(Debug)]
struct RawNode {
    span: Option<Range<usize>>,
    value: RawValue,
}

#[derive(Debug)]
enum RawValue {
    Str(String),
    Int(i64),
    Float(f64),
    Bool(bool),
    Datetime(String),
    Array(Vec<RawNode>),
    Table(Vec<(RawKey, RawNode)>),
}

#[derive(Debug)]
struct RawKey {
    text: String,
    span: Option<Range<usize>>,
}

impl RawNode {
    fn finish(self, fallback: Range<usize>) -> Item {
        let span = self.span.unwrap_or(fallback);
        let value = match self.value {
            RawValue::Str(s) => Value::Str(s),
            RawValue::Int(i) => Value::Int(i),
            RawValue::Float(f) => Value::Float(f),
            RawValue::Bool(b) => Value::Bool(b),
            RawValue::Datetime(s) => Value::Datetime(s),
            RawValue::Array(a) => {
                Value::Array(a.into_iter().map(|n| n.finish(span.clone())).collect())
            }
            RawValue::Table(t) => Value::Table(
                t.into_iter()
                    .map(|(k, v)| {
                        let key_span = k
                            .span
                            .or_else(|| v.span.clone())
                            .unwrap_or_else(|| span.clone());
                        let item = v.finish(key_span.clone());
                        Entry {
                            key: k.text,
                            key_span,
                            item,
                        }
                    })
                    .collect(),
            ),
        };
        Item { span, value }
    }
}

impl<'de> Deserialize<'de> for RawNode {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_struct(SPANNED_NAME, SPANNED_FIELDS, NodeVisitor)
    }
}

/// The value inside a spanned wrapper: asked for with `deserialize_any`, since
/// asking for a spanned struct again would wrap it again.
struct Bare(RawNode);

impl<'de> Deserialize<'de> for Bare {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NodeVisitor).map(Bare)
    }
}

struct NodeVisitor;

fn bare(value: RawValue) -> RawNode {
    RawNode { span: None, value }
}

impl<'de> Visitor<'de> for NodeVisitor {
    type Value = RawNode;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a TOML value")
    }

    fn visit_bool<E>(self, v: bool) -> Result<RawNode, E> {
        Ok(bare(RawValue::Bool(v)))
    }

    fn visit_i64<E>(self, v: i64) -> Result<RawNode, E> {
        Ok(bare(RawValue::Int(v)))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<RawNode, E> {
        i64::try_from(v)
            .map(|v| bare(RawValue::Int(v)))
            .map_err(|_| E::custom("integer out of range"))
    }

    fn visit_f64<E>(self, v: f64) -> Result<RawNode, E> {
        Ok(bare(RawValue::Float(v)))
    }

    fn visit_str<E>(self, v: &str) -> Result<RawNode, E> {
        Ok(bare(RawValue::Str(v.to_string())))
    }

    fn visit_string<E>(self, v: String) -> Result<RawNode, E> {
        Ok(bare(RawValue::Str(v)))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RawNode, A::Error> {
        let mut items = Vec::new();
        while let Some(n) = seq.next_element::<RawNode>()? {
            items.push(n);
        }
        Ok(bare(RawValue::Array(items)))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<RawNode, A::Error> {
        let Some(first) = map.next_key::<RawKey>()? else {
            return Ok(bare(RawValue::Table(Vec::new())));
        };
        match first.text.as_str() {
            SPANNED_START => {
                let start: usize = map.next_value()?;
                expect_key(&mut map, SPANNED_END)?;
                let end: usize = map.next_value()?;
                expect_key(&mut map, SPANNED_VALUE)?;
                let Bare(mut node) = map.next_value()?;
                node.span = Some(start..end);
                Ok(node)
            }
            DATETIME_FIELD => {
                let text: String = map.next_value()?;
                Ok(bare(RawValue::Datetime(text)))
            }
            _ => {
                let mut entries = vec![(first, map.next_value::<RawNode>()?)];
                while let Some(k) = map.next_key::<RawKey>()? {
                    let v = map.next_value::<RawNode>()?;
                    entries.push((k, v));
                }
                Ok(bare(RawValue::Table(entries)))
            }
        }
    }
}

fn expect_key<'de, A: MapAccess<'de>>(map: &mut A, want: &str) -> Result<(), A::Error> {
    match map.next_key::<RawKey>()? {
        Some(k) if k.text == want => Ok(()),
        _ => Err(de::Error::custom("malformed spanned value")),
    }
}

impl<'de> Deserialize<'de> for RawKey {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_struct(SPANNED_NAME, SPANNED_FIELDS, KeyVisitor)
    }
}

struct KeyVisitor;

impl<'de> Visitor<'de> for KeyVisitor {
    type Value = RawKey;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a key")
    }

    fn visit_str<E>(self, v: &str) -> Result<RawKey, E> {
        Ok(RawKey {
            text: v.to_string(),
            span: None,
        })
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<RawKey, A::Error> {
        expect_key(&mut map, SPANNED_START)?;
        let start: usize = map.next_value()?;
        expect_key(&mut map, SPANNED_END)?;
        let end: usize = map.next_value()?;
        expect_key(&mut map, SPANNED_VALUE)?;
        let text: String = map.next_value()?;
        Ok(RawKey {
            text,
            span: Some(start..end),
        })
    }
}

/// 1-based line and character column of byte `offset` in `src`.
/// Line and column (1-based, in characters) of byte `offset` of `src`.
pub fn line_col(src: &str, offset: usize) -> (u32, u32) {
    let mut offset = offset.min(src.len());
    while !src.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &src[..offset];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = before.matches('\n').count() as u32 + 1;
    let col = before[line_start..].chars().count() as u32 + 1;
    (line, col)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(item: &Item) -> &[Entry] {
        match &item.value {
            Value::Table(t) => t,
            v => panic!("not a table: {v:?}"),
        }
    }

    fn text<'a>(src: &'a str, span: &Range<usize>) -> &'a str {
        &src[span.clone()]
    }

    #[test]
    fn spans_of_keys_and_values() {
        let src = "[cpu]\nmodel = \"Q06HCPU\"\n[[program]]\nfile = \"a.il\"\n\
                   [[program]]\nfile = \"b.il\"\n[a.b]\nc = 2\nd.e = [1, 2.5]\n\
                   [clock]\nstart = 2000-01-01T00:00:00\n";
        let root = parse(src).unwrap();
        let t = table(&root);
        assert_eq!(t[0].key, "cpu");
        assert_eq!(text(src, &t[0].key_span), "cpu");
        let cpu = table(&t[0].item);
        assert_eq!(text(src, &cpu[0].key_span), "model");
        assert_eq!(text(src, &cpu[0].item.span), "\"Q06HCPU\"");
        assert_eq!(cpu[0].item.value, Value::Str("Q06HCPU".into()));
        let Value::Array(progs) = &t[1].item.value else {
            panic!()
        };
        assert_eq!(progs.len(), 2);
        let p1 = table(&progs[1]);
        assert_eq!(text(src, &p1[0].item.span), "\"b.il\"");
        let a = table(&t[2].item);
        assert_eq!(a[0].key, "b");
        let b = table(&a[0].item);
        assert_eq!(b[0].key, "c");
        assert_eq!(text(src, &b[0].item.span), "2");
        assert_eq!(b[1].key, "d");
        let clock = table(&t[3].item);
        assert_eq!(
            clock[0].item.value,
            Value::Datetime("2000-01-01T00:00:00".into())
        );
        assert_eq!(text(src, &clock[0].item.span), "2000-01-01T00:00:00");
    }

    #[test]
    fn syntax_error_has_a_span() {
        let e = parse("a = 1\nb = \n").unwrap_err();
        assert_eq!(line_col("a = 1\nb = \n", e.span.start).0, 2);
    }

    #[test]
    fn columns_count_characters() {
        let src = "# é\nkey = \"ü\" x";
        assert_eq!(line_col(src, 0), (1, 1));
        assert_eq!(line_col(src, src.find("key").unwrap()), (2, 1));
        assert_eq!(line_col(src, src.find('x').unwrap()), (2, 11));
        assert_eq!(line_col("é = 1", 2), (1, 2));
    }
}
