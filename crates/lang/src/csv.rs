//! The GX Works2 instruction-list CSV export (contract §1).
//!
//! UTF-16LE with BOM (UTF-16BE, UTF-8 and Shift-JIS also read), tab-separated
//! (comma accepted when the header row uses commas), double-quoted fields. Title
//! rows come first, then the header row `Step No.`, `Line Statement`,
//! `Instruction`, `I/O(Device)`, `Blank`, `PI Statement`, `Note`. Operands are
//! either all in the instruction's `I/O(Device)` cell separated by spaces, or one
//! per row on the following rows whose `Instruction` cell is empty.
//!
//! The Japanese and Chinese editions of GX Works2 write the header row in their
//! language: `ステップ番号`, `命令`, `I/O(デバイス)` and `步号`, `指令`,
//! `I/O(软元件)` (full-width parentheses accepted). Without a BOM a file that is
//! not UTF-8 is read as Shift-JIS, or as GBK when only that finds the header
//! (the Chinese edition saves in GBK).
//!
//! A title row before the header row whose first cell is `PLC Information:`
//! (any cell starting with `PLC` and ending with a colon, as the editions
//! write it) names the CPU model in its second cell, series first:
//! `QCPU (Q mode) Q04UDEH`. Its last word is the file's [`Source::model`].

use std::borrow::Cow;

use encoding_rs::{Encoding, GBK, SHIFT_JIS, UTF_16BE, UTF_16LE, UTF_8};

use super::source::{is_label, Diagnostic, Source, SourceInstr, SourceItem, Token};

/// Decodes the bytes (UTF-16LE with BOM, UTF-16BE with BOM, UTF-8 with or without BOM, else Shift-JIS via encoding_rs) and parses them.
pub fn parse_csv(file: &str, bytes: &[u8]) -> Result<Source, Vec<Diagnostic>> {
    parse_text(file, &decode(bytes))
}

/// Picks the encoding by BOM, then by UTF-8 validity, then Shift-JIS or GBK
/// (whichever finds the header row); malformed sequences become U+FFFD.
fn decode(bytes: &[u8]) -> Cow<'_, str> {
    if let Some(rest) = bytes.strip_prefix(&[0xFF, 0xFE]) {
        UTF_16LE.decode_without_bom_handling(rest).0
    } else if let Some(rest) = bytes.strip_prefix(&[0xFE, 0xFF]) {
        UTF_16BE.decode_without_bom_handling(rest).0
    } else if let Some(rest) = bytes.strip_prefix(&[0xEF, 0xBB, 0xBF]) {
        UTF_8.decode_without_bom_handling(rest).0
    } else if let Ok(text) = std::str::from_utf8(bytes) {
        Cow::Borrowed(text)
    } else {
        let try_in = |enc: &'static Encoding| {
            let (text, errors) = enc.decode_without_bom_handling(bytes);
            let found = text.split('\n').take(64).any(|l| header(l).is_some());
            (text, found, errors)
        };
        let sjis = try_in(SHIFT_JIS);
        if sjis.1 && !sjis.2 {
            return sjis.0;
        }
        let gbk = try_in(GBK);
        match (sjis.1, gbk.1) {
            (false, true) => gbk.0,
            (true, true) if !gbk.2 => gbk.0,
            _ => sjis.0,
        }
    }
}

/// Header names of the English, Japanese and Chinese editions, lower-cased and
/// with full-width parentheses folded.
const STEP_NAMES: [&str; 5] = ["step no.", "ステップ番号", "ステップno.", "步号", "步號"];
const INSTRUCTION_NAMES: [&str; 3] = ["instruction", "命令", "指令"];
const IO_NAMES: [&str; 4] = ["i/o(device)", "i/o(デバイス)", "i/o(软元件)", "i/o(軟元件)"];

/// Whether a (trimmed) cell is one of `names` once lower-cased and with
/// full-width parentheses, slash, `i` and `o` folded. Allocates nothing: the
/// rows before the header row are all tested.
fn is_header_name(cell: &[(char, u32)], names: &[&str]) -> bool {
    let folded = cell
        .iter()
        .flat_map(|&(ch, _)| ch.to_lowercase())
        .map(|ch| match ch {
            '（' => '(',
            '）' => ')',
            '／' => '/',
            'ｉ' => 'i',
            'ｏ' => 'o',
            other => other,
        });
    names.iter().any(|n| n.chars().eq(folded.clone()))
}

/// Every name of [`STEP_NAMES`] has one of these characters, and every name
/// of [`INSTRUCTION_NAMES`] one of [`INSTRUCTION_MARKS`]; lower-casing and
/// folding make none of them from other characters. A row with neither is not
/// the header row, which [`header`] sees without splitting it.
const STEP_MARKS: [char; 4] = ['p', 'P', 'プ', '步'];
const INSTRUCTION_MARKS: [char; 4] = ['t', 'T', '命', '指'];

/// A cell's unquoted text, each character with its 1-based column in the line.
type Cell = Vec<(char, u32)>;

/// Where the columns we read are, found by name in the header row.
struct Columns {
    sep: char,
    step: usize,
    instr: usize,
    io: Option<usize>,
}

fn parse_text(file: &str, text: &str) -> Result<Source, Vec<Diagnostic>> {
    let mut items = Vec::new();
    let mut diags = Vec::new();
    let mut cols: Option<Columns> = None;
    // True while continuation rows may still add operands to the last item.
    let mut open = false;
    let mut model = None;
    for (n, raw) in text.split('\n').enumerate() {
        let line = to_u32(n + 1);
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        let Some(c) = &cols else {
            cols = header(raw);
            if cols.is_none() && model.is_none() {
                model = plc_information(raw, line);
            }
            continue;
        };
        let cells = split_cells(raw, c.sep);
        let cell = |i: usize| cells.get(i).map_or(&[][..], |v| trim(v));
        let instr = cell(c.instr);
        let io = c.io.map_or(&[][..], cell);
        if instr.is_empty() {
            if io.is_empty() {
                continue; // empty or comment-only row
            }
            match items.last_mut() {
                Some(SourceItem::Instr(i)) if open => i.operands.extend(operands(io, line)),
                _ => diags.push(diag(file, line, io, "operand row without an instruction")),
            }
            continue;
        }
        let mnemonic = token(instr, line);
        if io.is_empty() && is_label(&mnemonic.text) {
            items.push(SourceItem::Label(mnemonic));
            open = false;
            continue;
        }
        let step_cell = cell(c.step);
        let step_text = string_of(step_cell);
        let step = if step_text.is_empty() {
            None
        } else if let Ok(s) = step_text.parse::<u32>() {
            Some(s)
        } else {
            let msg = format!("step number `{step_text}` is not a number");
            diags.push(diag(file, line, step_cell, msg));
            None
        };
        items.push(SourceItem::Instr(SourceInstr {
            mnemonic,
            operands: operands(io, line),
            step,
        }));
        open = true;
    }
    if cols.is_none() {
        diags.push(Diagnostic {
            file: file.to_string(),
            line: 1,
            col: 1,
            message: "not a GX Works2 instruction-list CSV: header row with `Step No.` and \
                      `Instruction` (ステップ番号 and 命令, or 步号 and 指令) not found"
                .to_string(),
        });
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

/// The column layout if `raw` is the header row (tab-separated, else comma-separated).
fn header(raw: &str) -> Option<Columns> {
    if !raw.contains(STEP_MARKS) || !raw.contains(INSTRUCTION_MARKS) {
        return None;
    }
    ['\t', ','].into_iter().find_map(|sep| {
        let cells = split_cells(raw, sep);
        let find = |any: &[&str]| cells.iter().position(|c| is_header_name(trim(c), any));
        Some(Columns {
            sep,
            step: find(&STEP_NAMES)?,
            instr: find(&INSTRUCTION_NAMES)?,
            io: find(&IO_NAMES),
        })
    })
}

/// The model of a `PLC Information:` row (tab- or comma-separated): the last
/// word of its second cell, `Q04UDEH` of `QCPU (Q mode) Q04UDEH`.
fn plc_information(raw: &str, line: u32) -> Option<Token> {
    if !raw.contains("PLC") {
        return None;
    }
    ['\t', ','].into_iter().find_map(|sep| {
        let cells = split_cells(raw, sep);
        let title = trim(cells.first()?);
        let named = title.len() > 3
            && string_of(&title[..3]) == "PLC"
            && matches!(title.last(), Some((':' | '：', _)));
        let info = trim(cells.get(1)?);
        let start = info
            .iter()
            .rposition(|(ch, _)| ch.is_whitespace())
            .map_or(0, |i| i + 1);
        (named && start < info.len()).then(|| token(&info[start..], line))
    })
}

/// Splits a line into cells on `sep`. A cell starting with `"` is quoted, `""`
/// inside it is a quote, and an unterminated quote takes the rest of the line.
fn split_cells(raw: &str, sep: char) -> Vec<Cell> {
    let chars: Vec<char> = raw.chars().collect();
    let at = |i: usize| chars.get(i).copied();
    let mut cells = Vec::new();
    let mut i = 0;
    loop {
        let mut cell = Cell::new();
        if at(i) == Some('"') {
            i += 1;
            while let Some(ch) = at(i) {
                cell.push((ch, to_u32(i + 1)));
                if ch == '"' {
                    if at(i + 1) != Some('"') {
                        cell.pop(); // the closing quote
                        i += 1;
                        break;
                    }
                    i += 1; // `""` is one quote, at the first one's column
                }
                i += 1;
            }
        }
        // Unquoted cell, or stray text after a closing quote: up to the separator.
        while let Some(ch) = at(i).filter(|&ch| ch != sep) {
            cell.push((ch, to_u32(i + 1)));
            i += 1;
        }
        cells.push(cell);
        if at(i).is_none() {
            return cells;
        }
        i += 1; // the separator
    }
}

/// Splits an `I/O(Device)` cell on whitespace, keeping `"quoted strings"` whole.
fn operands(cell: &[(char, u32)], line: u32) -> Vec<Token> {
    let mut toks = Vec::new();
    let mut i = 0;
    while i < cell.len() {
        if cell[i].0.is_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let mut in_str = false;
        while i < cell.len() && (in_str || !cell[i].0.is_whitespace()) {
            in_str ^= cell[i].0 == '"';
            i += 1;
        }
        toks.push(token(&cell[start..i], line));
    }
    toks
}

fn trim(cell: &[(char, u32)]) -> &[(char, u32)] {
    let keep = |&(ch, _): &(char, u32)| !ch.is_whitespace() && ch != '\u{feff}';
    let start = cell.iter().position(keep).unwrap_or(cell.len());
    let end = cell.iter().rposition(keep).map_or(start, |e| e + 1);
    &cell[start..end]
}

/// A token of the (trimmed, non-empty) characters, at the column of the first.
fn token(chars: &[(char, u32)], line: u32) -> Token {
    Token {
        text: string_of(chars),
        line,
        col: chars.first().map_or(1, |&(_, col)| col),
    }
}

fn string_of(chars: &[(char, u32)]) -> String {
    chars.iter().map(|&(ch, _)| ch).collect()
}

fn diag(file: &str, line: u32, at: &[(char, u32)], message: impl Into<String>) -> Diagnostic {
    Diagnostic::at(file, &token(at, line), message)
}

fn to_u32(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn header_marks_come_only_from_themselves() {
        // The quick test of `header` is exact: no other character lower-cases
        // to a mark (folding makes only `(`, `)`, `/`, `i` and `o`), and each
        // header name has one.
        for c in (0..=0x10FFFF).filter_map(char::from_u32) {
            for marks in [STEP_MARKS, INSTRUCTION_MARKS] {
                if c.to_lowercase().any(|l| marks.contains(&l)) {
                    assert!(marks.contains(&c), "{c:?} lower-cases to a mark");
                }
            }
        }
        assert!(STEP_NAMES.iter().all(|n| n.contains(STEP_MARKS)));
        assert!(INSTRUCTION_NAMES
            .iter()
            .all(|n| n.contains(INSTRUCTION_MARKS)));
    }

    #[test]
    fn header_names_fold_case_and_full_width() {
        let cell = |s: &str| s.chars().map(|c| (c, 1)).collect::<Vec<_>>();
        assert!(is_header_name(&cell("STEP NO."), &STEP_NAMES));
        assert!(is_header_name(&cell("ステップNo."), &STEP_NAMES));
        assert!(is_header_name(&cell("Ｉ／Ｏ（デバイス）"), &IO_NAMES));
        assert!(is_header_name(&cell("ｉ/ｏ（软元件）"), &IO_NAMES));
        assert!(!is_header_name(&cell("Step No"), &STEP_NAMES));
        assert!(!is_header_name(&cell("Instructions"), &INSTRUCTION_NAMES));
        assert!(!is_header_name(&cell(""), &INSTRUCTION_NAMES));
    }

    const HEADER: &str = "\"Step No.\"\t\"Line Statement\"\t\"Instruction\"\t\"I/O(Device)\"\t\"Blank\"\t\"PI Statement\"\t\"Note\"";

    fn utf16le(text: &str) -> Vec<u8> {
        let mut b = vec![0xFF, 0xFE];
        b.extend(text.encode_utf16().flat_map(u16::to_le_bytes));
        b
    }

    /// A file of tab-separated, quoted rows after the standard title and header rows.
    fn export(rows: &[&[&str]]) -> String {
        let mut s =
            format!("\"MAIN\"\r\n\"PLC Information:\"\t\"QCPU (Q mode) Q06H\"\r\n{HEADER}\r\n");
        for row in rows {
            let cells: Vec<String> = row
                .iter()
                .map(|c| format!("\"{}\"", c.replace('"', "\"\"")))
                .collect();
            s.push_str(&cells.join("\t"));
            s.push_str("\r\n");
        }
        s
    }

    fn instr(item: &SourceItem) -> &SourceInstr {
        match item {
            SourceItem::Instr(i) => i,
            SourceItem::Label(t) => panic!("label {t:?}, expected an instruction"),
        }
    }

    fn texts(toks: &[Token]) -> Vec<&str> {
        toks.iter().map(|t| t.text.as_str()).collect()
    }

    /// (mnemonic, operands, step) of every instruction.
    fn summary(s: &Source) -> Vec<(String, Vec<&str>, Option<u32>)> {
        s.items
            .iter()
            .map(|it| {
                let i = instr(it);
                (i.mnemonic.text.clone(), texts(&i.operands), i.step)
            })
            .collect()
    }

    /// An export of the Japanese or Chinese edition: its header row and rows.
    fn localized(header: &str) -> String {
        export(&[
            &["0", "", "LD", "X0", "", "", ""],
            &["1", "", "OUT", "Y0", "", "", ""],
        ])
        .replace(HEADER, header)
    }

    const JA: &str = "\"ステップ番号\"\t\"行間ステートメント\"\t\"命令\"\t\"I/O(デバイス)\"\t\"ブランク\"\t\"PIステートメント\"\t\"ノート\"";
    const ZH: &str =
        "\"步号\"\t\"行间声明\"\t\"指令\"\t\"I/O(软元件)\"\t\"空\"\t\"PI声明\"\t\"注解\"";

    fn check_two_rows(bytes: &[u8]) {
        let s = parse_csv("m.csv", bytes).unwrap_or_else(|d| panic!("{d:?}"));
        assert_eq!(
            summary(&s),
            [
                ("LD".to_string(), vec!["X0"], Some(0)),
                ("OUT".to_string(), vec!["Y0"], Some(1))
            ]
        );
    }

    #[test]
    fn japanese_header_in_utf16_and_shift_jis() {
        let text = localized(JA);
        check_two_rows(&utf16le(&text));
        let (sjis, _, errors) = SHIFT_JIS.encode(&text);
        assert!(!errors);
        check_two_rows(&sjis);
        // Full-width parentheses, as some editions write them.
        check_two_rows(&utf16le(&text.replace("I/O(デバイス)", "I/O（デバイス）")));
    }

    #[test]
    fn chinese_header_in_utf16_and_gbk() {
        let text = localized(ZH);
        check_two_rows(&utf16le(&text));
        check_two_rows(text.as_bytes());
        let (gbk, _, errors) = GBK.encode(&text);
        assert!(!errors);
        check_two_rows(&gbk);
    }

    #[test]
    fn utf16le_title_rows_skipped_and_operands_in_one_cell() {
        let text = export(&[
            &["0", "", "LD", "X0", "", "", ""],
            &["1", "", "OUT", "T0 K10", "", "", ""],
            &["5", "", "END", "", "", "", ""],
        ]);
        let s = parse_csv("p.csv", &utf16le(&text)).unwrap();
        assert_eq!(s.file, "p.csv");
        assert_eq!(
            summary(&s),
            vec![
                ("LD".to_string(), vec!["X0"], Some(0)),
                ("OUT".to_string(), vec!["T0", "K10"], Some(1)),
                ("END".to_string(), vec![], Some(5)),
            ]
        );
    }

    #[test]
    fn operands_on_continuation_rows() {
        let text = export(&[
            &["0", "", "OUT", "T0", "", "", ""],
            &["", "", "", "K5", "", "", ""],
            &["4", "", "MOV", "K1", "", "", ""],
            &["", "", "", "D0 D1", "", "", ""],
            &["", "", "", "", "", "", "just a note"],
            &["", "", "", "D2", "", "", ""],
        ]);
        let s = parse_csv("p.csv", text.as_bytes()).unwrap();
        assert_eq!(
            summary(&s),
            vec![
                ("OUT".to_string(), vec!["T0", "K5"], Some(0)),
                ("MOV".to_string(), vec!["K1", "D0", "D1", "D2"], Some(4)),
            ]
        );
        let k5 = &instr(&s.items[0]).operands[1];
        assert_eq!((k5.line, k5.col), (5, 11));
    }

    #[test]
    fn labels() {
        let text = export(&[
            &["0", "", "P10", "", "", "", ""],
            &["0", "", "LD", "X0", "", "", ""],
            &["", "", "I28", "", "", "", ""],
            &["1", "", "CALL", "P10", "", "", ""],
        ]);
        let s = parse_csv("p.csv", text.as_bytes()).unwrap();
        assert_eq!(s.items.len(), 4);
        assert!(
            matches!(&s.items[0], SourceItem::Label(t) if t.text == "P10" && (t.line, t.col) == (4, 9))
        );
        assert!(matches!(&s.items[2], SourceItem::Label(t) if t.text == "I28" && t.line == 6));
        assert_eq!(texts(&instr(&s.items[3]).operands), vec!["P10"]);
    }

    #[test]
    fn operand_row_after_label_is_reported() {
        let text = export(&[
            &["", "", "P10", "", "", "", ""],
            &["", "", "", "K5", "", "", ""],
        ]);
        let e = parse_csv("p.csv", text.as_bytes()).unwrap_err();
        assert_eq!(e.len(), 1);
        assert_eq!(
            e[0].to_string(),
            "p.csv:5:11: operand row without an instruction"
        );
    }

    #[test]
    fn step_numbers_taken_from_file() {
        let text = export(&[
            &["100", "", "LD", "X0", "", "", ""],
            &[" 205 ", "", "OUT", "Y0", "", "", ""],
            &["", "", "END", "", "", "", ""],
        ]);
        let s = parse_csv("p.csv", text.as_bytes()).unwrap();
        let steps: Vec<Option<u32>> = s.items.iter().map(|i| instr(i).step).collect();
        assert_eq!(steps, vec![Some(100), Some(205), None]);
    }

    #[test]
    fn bad_step_number_is_reported() {
        let text = export(&[
            &["0", "", "LD", "X0", "", "", ""],
            &["1x", "", "OUT", "Y0", "", "", ""],
        ]);
        let e = parse_csv("p.csv", text.as_bytes()).unwrap_err();
        assert_eq!(e.len(), 1);
        assert_eq!(
            e[0].to_string(),
            "p.csv:5:2: step number `1x` is not a number"
        );
    }

    #[test]
    fn comment_only_and_empty_rows_skipped() {
        let text = export(&[
            &["", "*** blink ***", "", "", "", "", ""],
            &["", "", "", "", "", "", ""],
            &["0", "", "LD", "X0", "", "", "start"],
            &["", "", "", "", "", "[ST]", ""],
            &["", "", "", "", "", "", "note"],
        ]) + "\r\n\r\n";
        let s = parse_csv("p.csv", text.as_bytes()).unwrap();
        assert_eq!(summary(&s), vec![("LD".to_string(), vec!["X0"], Some(0))]);
    }

    #[test]
    fn exact_line_and_column_of_tokens() {
        // Quoted, unquoted, padded and `""`-escaped cells; columns count characters.
        let text = format!(
            "\"タイトル\"\n{HEADER}\n\"0\"\t\"\"\t\"LD\"\t\"X0\"\n1\t\t  OUT \t T0  K10 \n\"2\"\t\"\"\t\"$MOV\"\t\"\"\"A \"\"\"\"B\"\" D0\"\n"
        );
        let s = parse_csv("p.csv", text.as_bytes()).unwrap();
        let pos = |t: &Token| (t.text.clone(), t.line, t.col);
        let ld = instr(&s.items[0]);
        assert_eq!(pos(&ld.mnemonic), ("LD".to_string(), 3, 9));
        assert_eq!(pos(&ld.operands[0]), ("X0".to_string(), 3, 14));
        let out = instr(&s.items[1]);
        assert_eq!(pos(&out.mnemonic), ("OUT".to_string(), 4, 6));
        assert_eq!(pos(&out.operands[0]), ("T0".to_string(), 4, 12));
        assert_eq!(pos(&out.operands[1]), ("K10".to_string(), 4, 16));
        let mov = instr(&s.items[2]);
        assert_eq!(pos(&mov.mnemonic), ("$MOV".to_string(), 5, 9));
        assert_eq!(pos(&mov.operands[0]), ("\"A \"\"B\"".to_string(), 5, 16));
        assert_eq!(pos(&mov.operands[1]), ("D0".to_string(), 5, 28));
    }

    #[test]
    fn columns_found_by_header_name_and_commas_accepted() {
        let text =
            "\"Instruction\",\"Note\",\"I/O(Device)\",\"STEP NO.\"\n\"LD\",\"\",\"X0\",\"7\"\n";
        let s = parse_csv("p.csv", text.as_bytes()).unwrap();
        assert_eq!(summary(&s), vec![("LD".to_string(), vec!["X0"], Some(7))]);
        let ld = instr(&s.items[0]);
        assert_eq!(
            (ld.mnemonic.line, ld.mnemonic.col, ld.operands[0].col),
            (2, 2, 10)
        );
    }

    #[test]
    fn shift_jis_utf8_bom_and_utf16be() {
        let text = export(&[&["0", "", "LD", "X0", "", "", "入力"]]).replace("MAIN", "プログラム");
        let (sjis, _, bad) = SHIFT_JIS.encode(&text);
        assert!(!bad);
        assert!(std::str::from_utf8(&sjis).is_err());
        let mut utf8 = vec![0xEF, 0xBB, 0xBF];
        utf8.extend(text.as_bytes());
        let mut be = vec![0xFE, 0xFF];
        be.extend(text.encode_utf16().flat_map(u16::to_be_bytes));
        for bytes in [&sjis[..], &utf8, &be, &utf16le(&text)] {
            let s = parse_csv("p.csv", bytes).unwrap();
            assert_eq!(summary(&s), vec![("LD".to_string(), vec!["X0"], Some(0))]);
            assert_eq!(instr(&s.items[0]).mnemonic.col, 9);
        }
    }

    #[test]
    fn missing_header_is_reported() {
        let e = parse_csv("p.csv", b"LD X0\nOUT Y0\n").unwrap_err();
        assert_eq!(
            e,
            vec![Diagnostic {
                file: "p.csv".to_string(),
                line: 1,
                col: 1,
                message: "not a GX Works2 instruction-list CSV: header row with `Step No.` and \
                          `Instruction` (ステップ番号 and 命令, or 步号 and 指令) not found"
                    .to_string(),
            }]
        );
        assert!(parse_csv("p.csv", b"").is_err());
    }

    #[test]
    fn garbage_does_not_panic() {
        let mut inputs: Vec<Vec<u8>> = vec![
            vec![0xFF, 0xFE, 0x41],             // odd UTF-16 length
            vec![0xFE, 0xFF, 0xD8, 0x00],       // lone surrogate
            vec![0x81, 0xFF, 0x00, 0xFE, 0x22], // invalid Shift-JIS
            vec![0xEF, 0xBB, 0xBF, 0xC3],
            (0..=255).collect(),
        ];
        inputs.push(
            format!("{HEADER}\n\"0\"\t\"\"\t\"LD\t\"X0\n\"\t\"\t\"\"\"\n\"\"\"\"\n\t\t\t\"")
                .into_bytes(),
        );
        inputs.push(format!("{HEADER}\n\t\t\t\"K5 \"\"unterminated").into_bytes());
        for bytes in inputs {
            let _ = parse_csv("g.csv", &bytes);
        }
        // An unterminated quote takes the rest of the line.
        let s = parse_csv(
            "p.csv",
            format!("{HEADER}\n\"0\"\t\"\"\t\"LD\tX0 K1").as_bytes(),
        )
        .unwrap();
        assert_eq!(instr(&s.items[0]).mnemonic.text, "LD\tX0 K1");
    }

    #[test]
    fn plc_information_row_names_the_model() {
        let text = export(&[&["0", "", "LD", "X0", "", "", ""]]);
        let s = parse_csv("p.csv", &utf16le(&text)).unwrap();
        let m = s.model.expect("a model");
        // `"PLC Information:"\t"QCPU (Q mode) Q06H"`: Q06H at column 35.
        assert_eq!((m.text.as_str(), m.line, m.col), ("Q06H", 2, 35));
        let uni = text.replace("QCPU (Q mode) Q06H", "QCPU (Q mode) Q04UDEH");
        let s = parse_csv("p.csv", uni.as_bytes()).unwrap();
        assert_eq!(s.model.map(|t| t.text).as_deref(), Some("Q04UDEH"));
        // Comma-separated, another edition's title, a bare model.
        let commas = format!(
            "MAIN\r\n\"PLC情報:\",\"Q03UDV\"\r\n{}\r\n\"0\",\"\",\"LD\",\"X0\"\r\n",
            HEADER.replace('\t', ",")
        );
        let s = parse_csv("p.csv", commas.as_bytes()).unwrap();
        assert_eq!(s.model.map(|t| t.text).as_deref(), Some("Q03UDV"));
        // No such row, an empty model cell, or the row after the header: none.
        let none = [
            text.replace("\"PLC Information:\"\t\"QCPU (Q mode) Q06H\"\r\n", ""),
            text.replace("QCPU (Q mode) Q06H", " "),
            text.replace("PLC Information:", "PLC Information"),
            format!("{HEADER}\r\n\"PLC Information:\"\t\"Q06H\"\r\n"),
        ];
        for t in none {
            assert_eq!(parse_csv("p.csv", t.as_bytes()).unwrap().model, None, "{t}");
        }
    }

    #[test]
    fn example_blink_csv() {
        let bytes = include_bytes!("../../../examples/csv/blink.csv");
        assert_eq!(&bytes[..2], &[0xFF, 0xFE]);
        let s = parse_csv("blink.csv", bytes).unwrap();
        let n =
            |m: &str, ops: &[&'static str], step: u32| (m.to_string(), ops.to_vec(), Some(step));
        assert_eq!(
            summary(&s),
            vec![
                n("LD", &["X0"], 0),
                n("ANI", &["T1"], 1),
                n("OUT", &["T0", "K5"], 2),
                n("LD", &["T0"], 6),
                n("OUT", &["T1", "K5"], 7),
                n("LD", &["T0"], 11),
                n("OUT", &["Y0"], 12),
                n("END", &[], 13),
            ]
        );
    }

    proptest! {
        #[test]
        fn never_panics_on_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..512)) {
            let _ = parse_csv("f.csv", &bytes);
        }

        #[test]
        fn never_panics_on_utf16le_text(text in any::<String>()) {
            let _ = parse_csv("f.csv", &utf16le(&text));
        }

        #[test]
        fn never_panics_after_header(body in "[\"\t, \r\nA-Z0-9Pa-z.]{0,200}") {
            let _ = parse_csv("f.csv", &utf16le(&format!("{HEADER}\r\n{body}")));
        }
    }
}
