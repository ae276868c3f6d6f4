//! The `.il` text mnemonic list (contract §1).

use super::source::{is_label, Diagnostic, Source, SourceInstr, SourceItem, Token};

/// Splits `.il` text into labels and instructions. Only lexical errors (an
/// unterminated string) are reported here; everything else is the compiler's.
/// A comment line `; PLC Information: Q06PHCPU` before the first
/// instruction names the CPU model the file is written for, as the row of a
/// GX Works2 export does ([`plc_information`]).
pub fn parse_il(file: &str, text: &str) -> Result<Source, Vec<Diagnostic>> {
    let mut items = Vec::new();
    let mut diags = Vec::new();
    let mut model = None;
    for (n, raw) in text.lines().enumerate() {
        let line = n as u32 + 1;
        if items.is_empty() && model.is_none() {
            model = plc_information(raw, line);
        }
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
            model,
        })
    } else {
        Err(diags)
    }
}

/// The model a comment line `; PLC Information: QCPU (Q mode) Q06PH` names:
/// its last word (`Q06PH`; `Q06PHCPU` too), like the `PLC Information:` row
/// of a GX Works2 CSV export.
fn plc_information(raw: &str, line: u32) -> Option<Token> {
    let comment = raw.trim_start().strip_prefix(';')?;
    let info = comment.trim_start().strip_prefix("PLC Information:")?;
    let word = info.split_whitespace().last()?;
    // The word ends the line's text.
    let start = raw.trim_end().len() - word.len();
    Some(Token {
        text: word.to_string(),
        line,
        col: raw[..start].chars().count() as u32 + 1,
    })
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
    fn a_plc_information_comment_names_the_model() {
        let s = parse_il(
            "t.il",
            "; Flow loop\n; PLC Information: Q06PHCPU  \nLD X0\n",
        )
        .unwrap();
        let m = s.model.unwrap();
        assert_eq!((m.text.as_str(), m.line, m.col), ("Q06PHCPU", 2, 20));
        let s = parse_il("t.il", ";PLC Information: QCPU (Q mode) Q04UDEH\nEND\n").unwrap();
        assert_eq!(s.model.unwrap().text, "Q04UDEH");
        // Only before the first instruction, and only that exact title.
        let s = parse_il("t.il", "LD X0\n; PLC Information: Q06PHCPU\n").unwrap();
        assert!(s.model.is_none());
        let s = parse_il("t.il", "; PLC information Q06PHCPU\nLD X0\n").unwrap();
        assert!(s.model.is_none());
        assert_eq!(s.items.len(), 1);
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
