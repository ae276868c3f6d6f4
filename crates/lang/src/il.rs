//! The `.il` text mnemonic list (contract §1).

use super::source::{is_label, Diagnostic, Source, SourceInstr, SourceItem, Token};

/// Splits `.il` text into labels and instructions. Only lexical errors (an
/// unterminated string) are reported here; everything else is the compiler's.
pub fn parse_il(file: &str, text: &str) -> Result<Source, Vec<Diagnostic>> {
    let mut items = Vec::new();
    let mut diags = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = n as u32 + 1;
        let toks = match tokenize(raw, line) {
            Ok(t) => t,
            Err(tok) => {
                diags.push(Diagnostic::at(
                    file,
                    &tok,
                    format!("unterminated string `{}`", tok.text),
                ));
                continue;
            }
        };
        let mut it = toks.into_iter();
        let Some(first) = it.next() else { continue };
        let operands: Vec<Token> = it.collect();
        if operands.is_empty() && is_label(&first.text) {
            items.push(SourceItem::Label(first));
        } else {
            items.push(SourceItem::Instr(SourceInstr {
                mnemonic: first,
                operands,
                step: None,
            }));
        }
    }
    if diags.is_empty() {
        Ok(Source {
            file: file.to_string(),
            items,
            model: None,
        })
    } else {
        Err(diags)
    }
}

/// Splits one line on spaces/tabs, keeping `"quoted strings"` whole and stopping at
/// a `;` comment outside quotes. Columns count characters from 1.
pub(crate) fn tokenize(raw: &str, line: u32) -> Result<Vec<Token>, Token> {
    let chars: Vec<char> = raw.chars().collect();
    let mut toks = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == ';' {
            break;
        }
        if c.is_whitespace() || c == '\u{feff}' {
            i += 1;
            continue;
        }
        let start = i;
        let mut in_str = false;
        while i < chars.len() {
            let c = chars[i];
            if c == '"' {
                in_str = !in_str;
            } else if !in_str && (c.is_whitespace() || c == ';') {
                break;
            }
            i += 1;
        }
        let tok = Token {
            text: chars[start..i].iter().collect(),
            line,
            col: start as u32 + 1,
        };
        if in_str {
            return Err(tok);
        }
        toks.push(tok);
    }
    Ok(toks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_comments_and_strings() {
        let s = parse_il("t.il", "; head\nP10\n  LD X0 ; c\n$MOV \"A B;C\" D0\n\n").unwrap();
        assert_eq!(s.items.len(), 3);
        assert!(matches!(&s.items[0], SourceItem::Label(t) if t.text == "P10" && t.line == 2));
        match &s.items[1] {
            SourceItem::Instr(i) => {
                assert_eq!(i.mnemonic.text, "LD");
                assert_eq!((i.mnemonic.line, i.mnemonic.col), (3, 3));
                assert_eq!(i.operands[0].text, "X0");
                assert_eq!(i.operands[0].col, 6);
            }
            _ => panic!(),
        }
        match &s.items[2] {
            SourceItem::Instr(i) => assert_eq!(i.operands[0].text, "\"A B;C\""),
            _ => panic!(),
        }
    }

    #[test]
    fn unterminated_string_is_reported_with_position() {
        let e = parse_il("t.il", "LD X0\n$MOV \"AB D0\n").unwrap_err();
        assert_eq!(e[0].to_string(), "t.il:2:6: unterminated string `\"AB D0`");
    }

    /// Mnemonics with relation signs (the process CPU's `S.>=`, `LD<>`) are
    /// one token, like any other.
    #[test]
    fn relation_signs_stay_in_the_mnemonic() {
        let s = parse_il("t.il", "S.>= D0 D100 D10 SD1506\nS.< D0 D1 D2 D3\n").unwrap();
        let m: Vec<&str> = s
            .items
            .iter()
            .map(|i| match i {
                SourceItem::Instr(i) => i.mnemonic.text.as_str(),
                _ => panic!(),
            })
            .collect();
        assert_eq!(m, ["S.>=", "S.<"]);
        match &s.items[0] {
            SourceItem::Instr(i) => assert_eq!(i.operands[0].text, "D0"),
            _ => panic!(),
        }
    }
}
