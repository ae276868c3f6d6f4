//! Golden tests of the character string instructions ($MOV, $+ and programming
//! manual §7.11). Every expected value is worked out by hand next to it.
//!
//! String layout (PM §3.2.5): two characters a word, the first in the low byte;
//! "ABC" in D0 is D0 = 'B'·256 + 'A' = 4241H, D1 = 0043H (NUL in the high byte);
//! "ABCD" ends with a whole 0000H word. ASCII: '0' = 30H … '9' = 39H, 'A' = 41H,
//! space = 20H, '-' = 2DH, '.' = 2EH.

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};
use softplc_core::access::Value;

/// The string at `dev` (read up to its NUL).
fn text(p: &Plc, dev: &str) -> String {
    match p.get(&format!("{dev}:str")) {
        Value::Str(s) => s,
        v => panic!("{dev}: {v:?}"),
    }
}

/// A word as unsigned 16 bits.
fn w(p: &Plc, dev: &str) -> i64 {
    p.int(&format!("{dev}:u16"))
}

/// Runs `src` (wrapped in `LD SM400 … END`) once after `setup`.
fn run(src: &str, setup: &[(&str, &str)]) -> Plc {
    let mut p = Plc::new(&format!("LD SM400\n{src}\nEND\n"));
    for (d, v) in setup {
        p.set(d, v);
    }
    p.scan();
    p
}

// ------------------------------------------------------------------ $MOV

#[test]
fn smov_constant_layout() {
    let p = run(
        "$MOV \"ABC\" D0\n$MOV \"ABCD\" D10\n$MOV \"\" D20",
        &[("D2", "H1234"), ("D20", "H5555"), ("D21", "H6666")],
    );
    assert_running(&p);
    // "ABC": D0 = 42H·256 + 41H = 4241H, D1 = 00H·256 + 43H = 0043H; D2 untouched.
    assert_eq!(w(&p, "D0"), 0x4241);
    assert_eq!(w(&p, "D1"), 0x0043);
    assert_eq!(w(&p, "D2"), 0x1234);
    // "ABCD": 4241H, 4443H and a whole NUL word.
    assert_eq!(w(&p, "D10"), 0x4241);
    assert_eq!(w(&p, "D11"), 0x4443);
    assert_eq!(w(&p, "D12"), 0);
    // "": one NUL word; D21 untouched.
    assert_eq!(w(&p, "D20"), 0);
    assert_eq!(w(&p, "D21"), 0x6666);
}

#[test]
fn smov_device_to_device_and_overlap() {
    let p = run("$MOV D10 D20", &[("D10:str", "HELLO")]);
    // "HELLO": D20 = 'E''H' = 4548H, D21 = 4C4CH, D22 = 004FH.
    assert_eq!(text(&p, "D20"), "HELLO");
    assert_eq!(w(&p, "D20"), 0x4548);
    assert_eq!(w(&p, "D22"), 0x004F);
    // Overlap forwards: "ABCDEF" at D10 (D10-D13) moved to D11: copying from
    // the front would overwrite D11-D12 before reading them.
    let p = run("$MOV D10 D11", &[("D10:str", "ABCDEF")]);
    assert_eq!(text(&p, "D11"), "ABCDEF");
    assert_eq!(w(&p, "D14"), 0);
    // D10 keeps its first two characters.
    assert_eq!(w(&p, "D10"), 0x4241);
    // Overlap backwards: D11 → D10.
    let p = run("$MOV D11 D10", &[("D11:str", "XYZ")]);
    assert_eq!(text(&p, "D10"), "XYZ");
}

#[test]
fn smov_range_errors() {
    // D12280-D12287 all 4141H ("AA…"): no NUL before the last D (D12287) → 4101.
    let mut setup = vec![];
    let names: Vec<String> = (12280..12288).map(|n| format!("D{n}")).collect();
    for n in &names {
        setup.push((n.as_str(), "H4141"));
    }
    let p = run("$MOV D12280 D0", &setup);
    assert_stopped(&p, 4101);
    assert_eq!(w(&p, "D0"), 0);
    // "ABCDEF" needs 4 words (3 + the NUL word): from D12285 that is D12288 → 4101
    // and nothing is written.
    let p = run("$MOV \"ABCDEF\" D12285", &[("D12285", "7")]);
    assert_stopped(&p, 4101);
    assert_eq!(w(&p, "D12285"), 7);
    // "ABCDE" needs 3 words (NUL in the high byte of the third): D12285-D12287 fits.
    let p = run("$MOV \"ABCDE\" D12285", &[]);
    assert_running(&p);
    assert_eq!(w(&p, "D12287"), 0x0045);
}

#[test]
fn smov_index_and_pulse() {
    // Z1 = 5: "XY" to D5 = 'Y''X' = 5958H, D6 = 0000H.
    let p = run("$MOV \"XY\" D0Z1", &[("Z1", "5"), ("D6", "9")]);
    assert_eq!(w(&p, "D5"), 0x5958);
    assert_eq!(w(&p, "D6"), 0);
    assert_eq!(w(&p, "D0"), 0);
    // $MOVP copies once per rising edge.
    let mut p = Plc::new("LD X0\n$MOVP D10 D20\nEND\n");
    p.set("D10:str", "ONE").set("X0", "1").scan();
    assert_eq!(text(&p, "D20"), "ONE");
    p.set("D10:str", "TWO").scan();
    assert_eq!(text(&p, "D20"), "ONE");
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(text(&p, "D20"), "TWO");
}

#[test]
fn string_constant_limits_at_load() {
    // 32 characters are accepted (004 L7540-7555), 33 are not.
    let s32 = "ABCDEFGHIJKLMNOPQRSTUVWXYZ012345";
    assert_eq!(s32.len(), 32);
    let p = run(&format!("$MOV \"{s32}\" D0"), &[]);
    assert_eq!(text(&p, "D0"), s32);
    // 32 characters: 16 words and a NUL word at D16.
    assert_eq!(w(&p, "D16"), 0);
    let d = diagnostics(&format!("LD SM400\n$MOV \"{s32}6\" D0\nEND\n"));
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(d[0].starts_with("2:6:") && d[0].contains("32"), "{d:?}");
    // A number is not a string; a destination needs a word device.
    let d = diagnostics("LD SM400\n$MOV K1 D0\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
    let d = diagnostics("LD SM400\n$MOV \"A\" K4M0\nEND\n");
    assert_eq!(d.len(), 1, "{d:?}");
}

// ------------------------------------------------------------------ $+

#[test]
fn sadd_three_and_two_operands() {
    let p = run(
        "$+ \"AB\" \"CDE\" D0\n$+ \"DE\" D10\n$+ D20 D30 D40",
        &[("D10:str", "ABC"), ("D20:str", "12"), ("D30:str", "345")],
    );
    assert_running(&p);
    // "AB" + "CDE" = "ABCDE": 4241H, 4443H, 0045H.
    assert_eq!(text(&p, "D0"), "ABCDE");
    assert_eq!(w(&p, "D2"), 0x0045);
    // D10 "ABC" + "DE" = "ABCDE".
    assert_eq!(text(&p, "D10"), "ABCDE");
    assert_eq!(text(&p, "D40"), "12345");
    // "12345" has odd length: NUL in the high byte of D42 = 0035H.
    assert_eq!(w(&p, "D42"), 0x0035);
}

#[test]
fn sadd_overlapping_operands() {
    // D = S2: "12" + "345" into D20 itself → "12345" (S2 is moved out first).
    let p = run("$+ D10 D20 D20", &[("D10:str", "12"), ("D20:str", "345")]);
    assert_eq!(text(&p, "D20"), "12345");
    // Crosswise: D20 = "ABCDEF", S1 = D21 = "CDEF", S2 = D20 = "ABCDEF", D = D20:
    // "CDEF" + "ABCDEF" = "CDEFABCDEF".
    let p = run("$+ D21 D20 D20", &[("D20:str", "ABCDEF")]);
    assert_eq!(text(&p, "D20"), "CDEFABCDEF");
    // Two-operand form appending a string to itself: "AB" + "AB" = "ABAB".
    let p = run("$+ D0 D0", &[("D0:str", "AB")]);
    assert_eq!(text(&p, "D0"), "ABAB");
}

#[test]
fn sadd_errors_and_pulse() {
    // D12286 "AB" + "CDE" = 5 characters = 3 words: D12286-D12288 → 4101, D12286
    // keeps "AB".
    let p = run("$+ \"CDE\" D12286", &[("D12286:str", "AB")]);
    assert_stopped(&p, 4101);
    assert_eq!(text(&p, "D12286"), "AB");
    // $+P appends once per rising edge: "" → "X" → (still ON) "X" → "XX".
    let mut p = Plc::new("LD X0\n$+P \"X\" D0\nEND\n");
    p.set("X0", "1").scan();
    assert_eq!(text(&p, "D0"), "X");
    p.scan();
    assert_eq!(text(&p, "D0"), "X");
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(text(&p, "D0"), "XX");
}

// ------------------------------------------------------------------ BIN → ASCII

#[test]
fn binda_and_dbinda() {
    let p = run(
        "BINDA K-12345 D0\nBINDA K123 D10\nBINDA K0 D20\nBINDA K-32768 D30\n\
         DBINDA K-2147483648 D40\nDBINDA K1234567 D50",
        &[("D3", "H1234")],
    );
    assert_running(&p);
    // −12345 → "-12345": D0 = '1''-' = 312DH, D1 = 3332H, D2 = 3534H, D3 = 0000H.
    assert_eq!(w(&p, "D0"), 0x312D);
    assert_eq!(w(&p, "D1"), 0x3332);
    assert_eq!(w(&p, "D2"), 0x3534);
    assert_eq!(w(&p, "D3"), 0);
    // 123 → sign space, 00123 with the leading zeros as spaces: "   123".
    assert_eq!(text(&p, "D10"), "   123");
    assert_eq!(w(&p, "D10"), 0x2020);
    // 0 keeps its units digit: "     0".
    assert_eq!(text(&p, "D20"), "     0");
    assert_eq!(text(&p, "D30"), "-32768");
    // 32-bit: sign + 10 digits = 11 characters, NUL in the high byte of D45.
    assert_eq!(text(&p, "D40"), "-2147483648");
    assert_eq!(w(&p, "D45"), 0x0038);
    // 1234567 → sign space and 0001234567 → "    1234567".
    assert_eq!(text(&p, "D50"), "    1234567");
}

#[test]
fn sm701_on_suppresses_the_terminator() {
    let p = run(
        "BINDA K5 D0\nDBINDA K5 D10\nBINHA H1 D20\nASC D30 D40 K2",
        &[
            ("SM701", "1"),
            ("D3", "H1234"),
            ("D15", "HFFFF"),
            ("D22", "H5678"),
            ("D30", "HAB00"),
            ("D41", "H9999"),
        ],
    );
    assert_running(&p);
    // "     5": D0 = D1 = 2020H, D2 = '5''␣' = 3520H.
    assert_eq!(w(&p, "D0"), 0x2020);
    assert_eq!(w(&p, "D2"), 0x3520);
    // SM701 ON: D3 is not cleared (so the characters run on into D3); D15's high byte is not written (only '5' in the
    // low byte: FF35H).
    assert_eq!(w(&p, "D3"), 0x1234);
    assert_eq!(w(&p, "D15"), 0xFF35);
    // BINHA 0001H → "0001", D22 untouched.
    assert_eq!(w(&p, "D20"), 0x3030);
    assert_eq!(w(&p, "D21"), 0x3130);
    assert_eq!(w(&p, "D22"), 0x5678);
    // ASC of ABxxH, 2 characters → "AB", D41 untouched.
    assert_eq!(w(&p, "D40"), 0x4241);
    assert_eq!(w(&p, "D41"), 0x9999);
}

#[test]
fn binha_and_bcdda() {
    let p = run(
        "BINHA H02A6 D0\nBINHA HFFFF D10\nDBINHA H89ABCDEF D20\n\
         BCDDA H1234 D30\nBCDDA H0012 D40\nDBCDDA H12345678 D50",
        &[],
    );
    assert_running(&p);
    // 02A6H → "02A6" without zero suppression: D0 = '2''0' = 3230H, D1 = '6''A' =
    // 3641H, D2 = 0000H.
    assert_eq!(w(&p, "D0"), 0x3230);
    assert_eq!(w(&p, "D1"), 0x3641);
    assert_eq!(w(&p, "D2"), 0);
    assert_eq!(text(&p, "D10"), "FFFF");
    assert_eq!(text(&p, "D20"), "89ABCDEF");
    assert_eq!(w(&p, "D24"), 0);
    assert_eq!(text(&p, "D30"), "1234");
    assert_eq!(text(&p, "D40"), "0012");
    assert_eq!(text(&p, "D50"), "12345678");
    // A nibble above 9 is not BCD: 12A4H → 4100.
    let p = run("BCDDA H12A4 D0", &[]);
    assert_stopped(&p, 4100);
    let p = run("DBCDDA H9999999F D0", &[]);
    assert_stopped(&p, 4100);
}

// ------------------------------------------------------------------ ASCII → BIN

#[test]
fn dabin_and_ddabin() {
    let cases: [(&str, i64); 5] = [
        ("-12345", -12345),
        (" 32767", 32767),
        ("-32768", -32768),
        ("-  123", -123), // spaces in digit places count as 0
        (" 00000", 0),
    ];
    for (s, v) in cases {
        let p = run("DABIN D0 D10", &[("D0:str", s)]);
        assert_running(&p);
        assert_eq!(p.int("D10"), v, "{s}");
    }
    for s in [" 32768", "+12345", " 12a45", "-99999"] {
        let p = run("DABIN D0 D10", &[("D0:str", s), ("D10", "7")]);
        assert_stopped(&p, 4100);
        assert_eq!(p.int("D10"), 7, "{s}");
    }
    let p = run("DDABIN D0 D10", &[("D0:str", "-2147483648")]);
    assert_eq!(p.int("D10:i32"), -2_147_483_648);
    let p = run("DDABIN D0 D10", &[("D0:str", "     123456")]);
    assert_eq!(p.int("D10:i32"), 123_456);
    let p = run("DDABIN D0 D10", &[("D0:str", " 2147483648")]);
    assert_stopped(&p, 4100);
}

#[test]
fn habin_and_dabcd() {
    let p = run(
        "HABIN D0 D10\nDHABIN D20 D30\nDABCD D40 D50\nDABCD D60 D70\nDDABCD D80 D90",
        &[
            ("D0:str", "1A2F"),
            ("D20:str", "89ABCDEF"),
            ("D40:str", "1234"),
            ("D60:str", "  12"),
            ("D80:str", "12345678"),
        ],
    );
    assert_running(&p);
    assert_eq!(w(&p, "D10"), 0x1A2F);
    assert_eq!(p.int("D30:u32"), 0x89AB_CDEF);
    assert_eq!(w(&p, "D50"), 0x1234);
    // Spaces count as 0: "  12" → 0012H.
    assert_eq!(w(&p, "D70"), 0x0012);
    assert_eq!(p.int("D90:u32"), 0x1234_5678);
    // Lower-case hexadecimal and non-digits are 4100.
    let p = run("HABIN D0 D10", &[("D0:str", "1a2f")]);
    assert_stopped(&p, 4100);
    let p = run("DABCD D0 D10", &[("D0:str", "12X4")]);
    assert_stopped(&p, 4100);
    let p = run("DABCD D0 D10", &[("D0:str", "12A4")]);
    assert_stopped(&p, 4100);
}

#[test]
fn dabin_source_past_device_end() {
    // DABIN reads 3 words: from D12286 that is D12288 → 4101.
    let p = run("DABIN D12286 D0", &[]);
    assert_stopped(&p, 4101);
}

// ------------------------------------------------------------------ LEN

#[test]
fn len_of_strings() {
    let p = run(
        "LEN D0 D100\nLEN D10 D101\nLEN \"ABC\" D102\nLEN D20Z1 D103",
        &[
            ("D0:str", "HELLO"),
            ("D10:str", ""),
            ("Z1", "2"),
            ("D22:str", "0123456789"),
        ],
    );
    assert_running(&p);
    assert_eq!(p.int("D100"), 5);
    assert_eq!(p.int("D101"), 0);
    assert_eq!(p.int("D102"), 3);
    // D20Z1 = D22.
    assert_eq!(p.int("D103"), 10);
    // No NUL up to D12287 → 4101.
    let p = run("LEN D12287 D0", &[("D12287", "H4142")]);
    assert_stopped(&p, 4101);
}

// ------------------------------------------------------------------ STR, DSTR

/// Runs `STR D0 D2 D10` (or DSTR) with S1 = (total, dec) and value `v`.
fn str_run(instr: &str, total: i64, dec: i64, v: &str) -> Plc {
    let ty = if instr == "DSTR" { "D2:i32" } else { "D2" };
    run(
        &format!("{instr} D0 D2 D10"),
        &[
            ("D0", &total.to_string()),
            ("D1", &dec.to_string()),
            (ty, v),
            ("D14", "H7777"),
        ],
    )
}

#[test]
fn str_formats() {
    // 6 characters, 2 decimals, −1234 → sign, "12.34": "-12.34", then a NUL word
    // (even length) in D13.
    let p = str_run("STR", 6, 2, "-1234");
    assert_running(&p);
    assert_eq!(text(&p, "D10"), "-12.34");
    assert_eq!(w(&p, "D13"), 0);
    // 8 characters, 3 decimals, 12 → "0.012" right-aligned after the sign and two
    // spaces: "   0.012".
    assert_eq!(text(&str_run("STR", 8, 3, "12"), "D10"), "   0.012");
    // 5 characters, no decimals, 123 → "  123" (no point).
    let p = str_run("STR", 5, 0, "123");
    assert_eq!(text(&p, "D10"), "  123");
    // Odd length: NUL in the high byte of D12 = 00H·256 + '3'.
    assert_eq!(w(&p, "D12"), 0x0033);
    // Minimum: 2 characters, 0 decimals, −5 → "-5".
    assert_eq!(text(&str_run("STR", 2, 0, "-5"), "D10"), "-5");
    // 3 decimals of 4 characters: dec ≤ total − 3 = 1 fails.
    assert_stopped(&str_run("STR", 4, 2, "1"), 4100);
    // 12345 needs 5 digit places; 4 characters leave 3 → 4100, D14 unchanged.
    let p = str_run("STR", 4, 0, "12345");
    assert_stopped(&p, 4100);
    assert_eq!(w(&p, "D14"), 0x7777);
    // Limits: total 9 or dec 6 are out of range for STR.
    assert_stopped(&str_run("STR", 9, 0, "1"), 4100);
    assert_stopped(&str_run("STR", 8, 6, "1"), 4100);
}

#[test]
fn dstr_formats() {
    // 13 characters, 10 decimals, −2147483648 → sign + "0.2147483648".
    assert_eq!(
        text(&str_run("DSTR", 13, 10, "-2147483648"), "D10"),
        "-0.2147483648"
    );
    // 10 characters, 2 decimals, 1234567 → " 12345.67" needs 9: one space more.
    assert_eq!(
        text(&str_run("DSTR", 10, 2, "1234567"), "D10"),
        "  12345.67"
    );
    assert_stopped(&str_run("DSTR", 14, 0, "1"), 4100);
    assert_stopped(&str_run("DSTR", 13, 11, "1"), 4100);
}

// ------------------------------------------------------------------ VAL, DVAL

fn val_run(instr: &str, s: &str) -> Plc {
    run(
        &format!("{instr} D0 D20 D30"),
        &[("D0:str", s), ("D30", "7")],
    )
}

#[test]
fn val_parses_sign_digits_and_point() {
    // "-123.45": 7 characters, 2 decimals, −12345 (the manual's example).
    let p = val_run("VAL", "-123.45");
    assert_running(&p);
    assert_eq!((p.int("D20"), p.int("D21"), p.int("D30")), (7, 2, -12345));
    // Leading zeros and spaces after the sign are ignored: " 00012" → 6, 0, 12.
    let p = val_run("VAL", " 00012");
    assert_eq!((p.int("D20"), p.int("D21"), p.int("D30")), (6, 0, 12));
    // "-  5.5" → 6 characters, 1 decimal, −55.
    let p = val_run("VAL", "-  5.5");
    assert_eq!((p.int("D20"), p.int("D21"), p.int("D30")), (6, 1, -55));
    // Constant source: " 3.2767" → 7, 4, 32767.
    let p = run("VAL \" 3.2767\" D20 D30", &[]);
    assert_eq!((p.int("D20"), p.int("D21"), p.int("D30")), (7, 4, 32767));
}

#[test]
fn val_errors() {
    for s in [
        "123",       // no sign character
        "-",         // one character
        " 1.2.3",    // two points
        " 12 3",     // space after a digit
        " 32768",    // beyond 16 bits
        " 3.2768",   // 32768 without the point
        " .12",      // 2 decimals need 5 characters
        " 12345678", // 9 characters
        " 12A",      // not a digit
    ] {
        let p = val_run("VAL", s);
        assert_stopped(&p, 4100);
        assert_eq!(p.int("D30"), 7, "{s}");
    }
}

#[test]
fn dval_32_bit() {
    // "-2147483.648": 12 characters, 3 decimals, −2147483648.
    let p = val_run("DVAL", "-2147483.648");
    assert_running(&p);
    assert_eq!(p.int("D20"), 12);
    assert_eq!(p.int("D21"), 3);
    assert_eq!(p.int("D30:i32"), -2_147_483_648);
    assert_stopped(&val_run("DVAL", " 2147483648"), 4100);
    // 14 characters.
    assert_stopped(&val_run("DVAL", " 1234567890123"), 4100);
}

// ------------------------------------------------------------------ ESTR

/// Runs `ESTR D0 D10 D20` with the real `x` and format (form, total, dec).
fn estr_run(x: &str, form: i64, total: i64, dec: i64) -> Plc {
    run(
        "ESTR D0 D10 D20",
        &[
            ("D0:f32", x),
            ("D10", &form.to_string()),
            ("D11", &total.to_string()),
            ("D12", &dec.to_string()),
        ],
    )
}

#[test]
fn estr_decimal_point_format() {
    // −12.34567 (f32 −12.3456697…) with 8 characters, 2 decimals: 1234.567 rounds
    // to 1235 → "12.35", 2 spaces after the sign: "-  12.35".
    let p = estr_run("-12.34567", 0, 8, 2);
    assert_running(&p);
    assert_eq!(text(&p, "D20"), "-  12.35");
    // 0.125 (exact) to 2 decimals: 12.5 is a tie, rounded away from zero → 0.13.
    assert_eq!(text(&estr_run("0.125", 0, 5, 2), "D20"), " 0.13");
    // 2.5 with no decimals → 3, 5 characters: "    3".
    assert_eq!(text(&estr_run("2.5", 0, 5, 0), "D20"), "    3");
    // 0 → " 0.0".
    assert_eq!(text(&estr_run("0", 0, 4, 1), "D20"), " 0.0");
    // 123456 needs 6 integer places; 6 characters leave 5 → 4100.
    assert_stopped(&estr_run("123456", 0, 6, 0), 4100);
    // 2 decimals need 5 characters.
    assert_stopped(&estr_run("1", 0, 4, 2), 4100);
}

#[test]
fn estr_exponent_format() {
    // 1234.5 = 1.2345·10³ to 2 decimals: 123.45 rounds to 123 → "1.23E+03", 9
    // characters with the sign; 10 asked → one space: "  1.23E+03".
    assert_eq!(text(&estr_run("1234.5", 1, 10, 2), "D20"), "  1.23E+03");
    // 125 = 1.25·10² to 1 decimal: 12.5 is a tie → 13 → "-1.3E+02" for −125.
    assert_eq!(text(&estr_run("-125", 1, 8, 1), "D20"), "-1.3E+02");
    // 9.9999 to 2 decimals: 999.99 → 1000, one digit too many → 1.00·10¹.
    assert_eq!(text(&estr_run("9.9999", 1, 9, 2), "D20"), " 1.00E+01");
    // 0.000123 (f32 1.22999996·10⁻⁴) to 3 decimals: 1229.99996 → 1230 →
    // "1.230E-04".
    assert_eq!(text(&estr_run("0.000123", 1, 10, 3), "D20"), " 1.230E-04");
    // 0 → " 0.00E+00"; no decimals → no point: " 5E+00".
    assert_eq!(text(&estr_run("0", 1, 9, 2), "D20"), " 0.00E+00");
    assert_eq!(text(&estr_run("5", 1, 6, 0), "D20"), " 5E+00");
}

#[test]
fn estr_errors() {
    // Format 2, too few characters for the exponent format (1 decimal needs 8),
    // 8 decimals, 25 characters.
    assert_stopped(&estr_run("1", 2, 10, 2), 4100);
    assert_stopped(&estr_run("1", 1, 7, 1), 4100);
    assert_stopped(&estr_run("1", 0, 12, 8), 4100);
    assert_stopped(&estr_run("1", 0, 25, 2), 4100);
    // +∞ is not a real number.
    let p = run("ESTR D0 D10 D20", &[("D0:u32", "0x7F800000"), ("D11", "8")]);
    assert_stopped(&p, 4100);
}

// ------------------------------------------------------------------ EVAL

fn eval_run(s: &str) -> Plc {
    run("EVAL D0 D20", &[("D0:str", s), ("D20:f32", "7")])
}

#[test]
fn eval_formats() {
    // Decimal point format.
    let p = eval_run("-12.345");
    assert_running(&p);
    assert_eq!(p.real("D20"), -12.345f32 as f64);
    // Only 6 significant digits count, the rest is cut (manual example):
    // "-1.30156812" → −1.30156.
    assert_eq!(eval_run("-1.30156812").real("D20"), -1.30156f32 as f64);
    // Spaces and the leading zero are ignored: "- 01.231" → −1.231.
    assert_eq!(eval_run("- 01.231").real("D20"), -1.231f32 as f64);
    // Exponent format: " 1.2345E+02" = 123.45; "-1.0453E+03" = −1045.3;
    // "1.5E-3" = 0.0015; "+5" = 5.
    assert_eq!(eval_run(" 1.2345E+02").real("D20"), 123.45f32 as f64);
    assert_eq!(eval_run("-1.0453E+03").real("D20"), -1045.3f32 as f64);
    assert_eq!(eval_run("1.5E-3").real("D20"), 0.0015f32 as f64);
    assert_eq!(eval_run("+5").real("D20"), 5.0);
    // Integer digits beyond the sixth are cut but keep their place:
    // "123456789" → 123456·10³.
    assert_eq!(eval_run("123456789").real("D20"), 123_456_000.0);
    // Zero.
    assert_eq!(eval_run("0.000").int("D20:u32"), 0);
    // A constant operand.
    let p = run("EVAL \"3.5\" D20", &[]);
    assert_eq!(p.real("D20"), 3.5);
}

#[test]
fn eval_errors() {
    for s in [
        "1.2.3",
        "12A",
        "",
        "1.5e+02",
        "1E+39",
        "1E-39",
        "1.0E+02E+01",
        "-",
        "1234567890123456789012345", // 25 characters
    ] {
        let p = eval_run(s);
        assert_stopped(&p, 4100);
        assert_eq!(p.real("D20"), 7.0, "{s}");
    }
}

// ------------------------------------------------------------------ ASC, HEX

#[test]
fn asc_fifteen_characters() {
    // The manual's example: 1234H 5678H 9ABCH DEF0H, n = 15 →
    // "123456789ABCDEF" and 00H in the high byte of D7 = 0046H ('F').
    let p = run(
        "ASC D10 D0 K15",
        &[
            ("D10", "H1234"),
            ("D11", "H5678"),
            ("D12", "H9ABC"),
            ("D13", "HDEF0"),
        ],
    );
    assert_running(&p);
    assert_eq!(text(&p, "D0"), "123456789ABCDEF");
    assert_eq!(w(&p, "D0"), 0x3231);
    assert_eq!(w(&p, "D7"), 0x0046);
    // Overlapping: ASC D10 D10 K8 with 1234H 5678H → "12345678" in D10-D13 and
    // a NUL word in D14.
    let p = run("ASC D10 D10 K8", &[("D10", "H1234"), ("D11", "H5678")]);
    assert_eq!(text(&p, "D10"), "12345678");
    assert_eq!(w(&p, "D14"), 0);
    // n = 0 does nothing; n < 0 is 4100.
    let p = run("ASC D10 D0 K0", &[("D10", "H1234"), ("D0", "5")]);
    assert_running(&p);
    assert_eq!(p.int("D0"), 5);
    assert_stopped(&run("ASC D10 D0 K-1", &[]), 4100);
}

#[test]
fn hex_characters_to_words() {
    // n = 9: "1234ABCD9" → 1234H, ABCDH and 9 as the top digit of D2 = 9000H.
    let p = run("HEX D10 D0 K9", &[("D10:str", "1234ABCD9"), ("D3", "5")]);
    assert_running(&p);
    assert_eq!(w(&p, "D0"), 0x1234);
    assert_eq!(w(&p, "D1"), 0xABCD);
    assert_eq!(w(&p, "D2"), 0x9000);
    assert_eq!(p.int("D3"), 5);
    // Overlapping: HEX D10 D10 K8 with "12345678" → D10 = 1234H, D11 = 5678H.
    let p = run("HEX D10 D10 K8", &[("D10:str", "12345678")]);
    assert_eq!(w(&p, "D10"), 0x1234);
    assert_eq!(w(&p, "D11"), 0x5678);
    // A lower-case or non-hexadecimal character → 4100, D unchanged.
    let p = run("HEX D10 D0 K4", &[("D10:str", "12a4"), ("D0", "5")]);
    assert_stopped(&p, 4100);
    assert_eq!(p.int("D0"), 5);
}

// ------------------------------------------------------------------ RIGHT, LEFT

#[test]
fn right_and_left() {
    let p = run(
        "RIGHT D0 D10 K3\nLEFT D0 D20 K3\nRIGHT D0 D30 K0\nLEFT D0 D40 K7\nRIGHT \"HELLO\" D50 K2",
        &[("D0:str", "ABCDEFG"), ("D30", "H4141")],
    );
    assert_running(&p);
    assert_eq!(text(&p, "D10"), "EFG");
    assert_eq!(text(&p, "D20"), "ABC");
    // n = 0: an empty string (a NUL word).
    assert_eq!(w(&p, "D30"), 0);
    assert_eq!(text(&p, "D40"), "ABCDEFG");
    assert_eq!(text(&p, "D50"), "LO");
    // More characters than the string has, or a negative count → 4101.
    assert_stopped(&run("RIGHT D0 D10 K8", &[("D0:str", "ABCDEFG")]), 4101);
    assert_stopped(&run("LEFT D0 D10 K-1", &[("D0:str", "ABCDEFG")]), 4101);
}

// ------------------------------------------------------------------ MIDR, MIDW

fn mid_run(instr: &str, s1: &str, d: &str, pos: i64, cnt: i64) -> Plc {
    run(
        &format!("{instr} D0 D20 D40"),
        &[
            ("D0:str", s1),
            ("D20:str", d),
            ("D40", &pos.to_string()),
            ("D41", &cnt.to_string()),
        ],
    )
}

#[test]
fn midr_extracts() {
    // "ABCDEFGHIJK" from the 5th character: 3 → "EFG"; −1 or 100 → "EFGHIJK".
    assert_eq!(
        text(&mid_run("MIDR", "ABCDEFGHIJK", "", 5, 3), "D20"),
        "EFG"
    );
    assert_eq!(
        text(&mid_run("MIDR", "ABCDEFGHIJK", "", 5, -1), "D20"),
        "EFGHIJK"
    );
    assert_eq!(
        text(&mid_run("MIDR", "ABCDEFGHIJK", "", 5, 100), "D20"),
        "EFGHIJK"
    );
    // 0 characters: an empty string.
    assert_eq!(text(&mid_run("MIDR", "ABCDEFGHIJK", "XX", 5, 0), "D20"), "");
    // The last character: position 11.
    assert_eq!(text(&mid_run("MIDR", "ABCDEFGHIJK", "", 11, 1), "D20"), "K");
    // Position 12 (beyond 11 characters), position 0, count −2 → 4101.
    assert_stopped(&mid_run("MIDR", "ABCDEFGHIJK", "", 12, 1), 4101);
    assert_stopped(&mid_run("MIDR", "ABCDEFGHIJK", "", 0, 1), 4101);
    assert_stopped(&mid_run("MIDR", "ABCDEFGHIJK", "", 1, -2), 4101);
}

#[test]
fn midw_replaces_in_place() {
    // The manual's examples: "ABCDEFGHI", S1 "012345678", position 5, 8 characters
    // → "ABCD01234" (the rest does not fit and is not written).
    let p = mid_run("MIDW", "012345678", "ABCDEFGHI", 5, 8);
    assert_running(&p);
    assert_eq!(text(&p, "D20"), "ABCD01234");
    // "ABCDEFGHI", position 3, 6 characters → "AB012345I".
    assert_eq!(
        text(&mid_run("MIDW", "012345678", "ABCDEFGHI", 3, 6), "D20"),
        "AB012345I"
    );
    // "ABCDEFGHIJK", S1 "012345", position 2, −1 (all of S1) → "A012345HIJK".
    assert_eq!(
        text(&mid_run("MIDW", "012345", "ABCDEFGHIJK", 2, -1), "D20"),
        "A012345HIJK"
    );
    // A count larger than S1: only S1's 2 characters → "XYCDEFGHI".
    assert_eq!(
        text(&mid_run("MIDW", "XY", "ABCDEFGHI", 1, 5), "D20"),
        "XYCDEFGHI"
    );
    // 0 characters: 00H at the start of D (as the manual states).
    assert_eq!(text(&mid_run("MIDW", "XY", "ABCDEFGHI", 1, 0), "D20"), "");
    // Position 10 in a 9-character D → 4101, D unchanged.
    let p = mid_run("MIDW", "XY", "ABCDEFGHI", 10, 1);
    assert_stopped(&p, 4101);
    assert_eq!(text(&p, "D20"), "ABCDEFGHI");
}

// ------------------------------------------------------------------ INSTR

#[test]
fn instr_search() {
    let p = run(
        "INSTR D0 D10 D100 K1\nINSTR D0 D10 D101 K4\nINSTR D0 D10 D102 K8\n\
         INSTR \"XY\" D10 D103 K1\nINSTR \"AB\" \"CCAB\" D104 K2",
        &[("D0:str", "CD"), ("D10:str", "ABCDEFCD"), ("D102", "9")],
    );
    assert_running(&p);
    // "CD" in "ABCDEFCD": first at 3; from the 4th character at 7; from the 8th
    // ("D") nowhere → 0.
    assert_eq!(p.int("D100"), 3);
    assert_eq!(p.int("D101"), 7);
    assert_eq!(p.int("D102"), 0);
    assert_eq!(p.int("D103"), 0);
    // "AB" in "CCAB" from the 2nd character: at 3.
    assert_eq!(p.int("D104"), 3);
    // n = 0 or beyond the 8 characters → 4101.
    let setup = [("D0:str", "CD"), ("D10:str", "ABCDEFCD")];
    assert_stopped(&run("INSTR D0 D10 D100 K0", &setup), 4101);
    assert_stopped(&run("INSTR D0 D10 D100 K9", &setup), 4101);
}

// ------------------------------------------------------------------ conditions

#[test]
fn condition_off_does_nothing() {
    let mut p = Plc::new("LD X0\n$MOV \"A\" D0\nLD X0\nBINDA K1 D10\nEND\n");
    p.set("D0", "5").set("D10", "6").scan();
    assert_eq!(p.int("D0"), 5);
    assert_eq!(p.int("D10"), 6);
}

#[test]
fn string_comparison_contacts() {
    // Character by character by ASCII code; a string that is the start of the
    // other is the smaller one (PM §6.1.3).
    let src = "LD$= D0 \"ABC\"\nOUT M0\nLD$< D0 \"ABD\"\nOUT M1\nLD$> D0 \"AB\"\nOUT M2\n\
               LD X0\nAND$<> \"ABC\" D0\nOUT M3\nLD X0\nOR$>= D10 D0\nOUT M4\nEND\n";
    let mut p = Plc::new(src);
    p.set("D0:str", "ABC").set("D10:str", "B").scan();
    assert!(p.bit("M0"), "ABC = ABC");
    assert!(p.bit("M1"), "ABC < ABD: C (43H) < D (44H)");
    assert!(p.bit("M2"), "ABC > AB: longer");
    assert!(!p.bit("M3"), "X0 OFF");
    assert!(p.bit("M4"), "B (42H) > A (41H) at the first character");
    p.set("X0", "1").scan();
    assert!(!p.bit("M3"), "equal strings");
    // A device string with no NUL before the end of D is 4101.
    let mut p = Plc::new("LD$= D12287 \"A\"\nOUT M0\nEND\n");
    p.set("D12287", "H4141").scan();
    assert_eq!(p.int("SD0"), 4101);
}
