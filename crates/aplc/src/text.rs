//! The text of an `.apl` file (contract §1.1 items 1-4): UTF-8 with an
//! optional BOM, LF or CRLF, GB18030 when not UTF-8; `//` line comments and
//! `/* … */` block comments (not nested); blank lines ignored. Produces the
//! tokens of each line with their 1-based line and character column.

use softplc_lang::{Diagnostic, Token};

/// Decodes the bytes of a program file: UTF-8 (a leading BOM ignored), else
/// GB18030, the programming software's encoding (L1-19).
pub fn decode(bytes: &[u8]) -> String {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => {
            let (s, _) = encoding_rs::GB18030.decode_without_bom_handling(bytes);
            s.into_owned()
        }
    }
}

/// The text of a comment on one line (a block comment over several lines is
/// one piece per line), for tools that show the program.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Comment {
    pub line: u32,
    /// Without the `//`, `/*` and `*/` marks, trimmed.
    pub text: String,
}

/// Splits the text into lines of tokens, comments removed. Lines without
/// tokens are left out. An unterminated block comment is a diagnostic.
pub fn lines(file: &str, text: &str) -> Result<Vec<Vec<Token>>, Diagnostic> {
    lines_and_comments(file, text).map(|(lines, _)| lines)
}

/// [`lines`], and the comments with their lines.
pub fn lines_and_comments(
    file: &str,
    text: &str,
) -> Result<(Vec<Vec<Token>>, Vec<Comment>), Diagnostic> {
    let mut out = Vec::new();
    let mut comments = Vec::new();
    let mut in_block: Option<(u32, u32)> = None;
    for (n, raw) in text.split('\n').enumerate() {
        let line = n as u32 + 1;
        let chars: Vec<char> = raw.trim_end_matches('\r').chars().collect();
        let mut toks = Vec::new();
        let mut cur: Option<(usize, String)> = None;
        let mut i = 0;
        let mut note = String::new();
        let flush = |cur: &mut Option<(usize, String)>, toks: &mut Vec<Token>| {
            if let Some((col, text)) = cur.take() {
                toks.push(Token {
                    text,
                    line,
                    col: col as u32 + 1,
                });
            }
        };
        while i < chars.len() {
            let c = chars[i];
            let next = chars.get(i + 1).copied();
            if in_block.is_some() {
                if c == '*' && next == Some('/') {
                    in_block = None;
                    note.push(' ');
                    i += 2;
                } else {
                    note.push(c);
                    i += 1;
                }
                continue;
            }
            if c == '/' && next == Some('*') {
                flush(&mut cur, &mut toks);
                in_block = Some((line, i as u32 + 1));
                i += 2;
                continue;
            }
            if c == '/' && next == Some('/') {
                note.extend(&chars[i + 2..]);
                break;
            }
            if c.is_whitespace() || c == '\u{feff}' {
                flush(&mut cur, &mut toks);
            } else {
                cur.get_or_insert_with(|| (i, String::new())).1.push(c);
            }
            i += 1;
        }
        flush(&mut cur, &mut toks);
        if !toks.is_empty() {
            out.push(toks);
        }
        let note = note.trim();
        if !note.is_empty() {
            comments.push(Comment {
                line,
                text: note.to_string(),
            });
        }
    }
    if let Some((line, col)) = in_block {
        return Err(Diagnostic {
            file: file.to_string(),
            line,
            col,
            message: "`/*`: block comment without `*/`".into(),
        });
    }
    Ok((out, comments))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_columns_crlf() {
        let t = "LD X0 // c\r\n/* a\nb */ OUT Y0\n\n\tMOV 1 /*x*/ D0\n";
        let l = lines("f.apl", t).unwrap();
        assert_eq!(l.len(), 3);
        assert_eq!(l[1][0].text, "OUT");
        assert_eq!((l[1][0].line, l[1][0].col), (3, 6));
        assert_eq!(l[2].len(), 3);
        assert_eq!(l[2][2].text, "D0");
        let (_, notes) = lines_and_comments("f.apl", t).unwrap();
        let notes: Vec<(u32, &str)> = notes.iter().map(|c| (c.line, c.text.as_str())).collect();
        assert_eq!(notes, [(1, "c"), (2, "a"), (3, "b"), (5, "x")]);
        let e = lines("f.apl", "LD X0\n  /* open\n").unwrap_err();
        assert_eq!(e.to_string(), "f.apl:2:3: `/*`: block comment without `*/`");
    }

    #[test]
    fn gb18030_and_bom() {
        assert_eq!(decode(b"\xEF\xBB\xBFLD X0"), "LD X0");
        let text = "水压    X0\n告警灯 Y1";
        let (gb, _, _) = encoding_rs::GB18030.encode(text);
        assert!(std::str::from_utf8(&gb).is_err());
        assert_eq!(decode(&gb), text);
    }
}
