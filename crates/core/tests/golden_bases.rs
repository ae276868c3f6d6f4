//! Golden tests of the base registers (004 §5.1; App. 1 SM250 L9587; App. 2
//! SD240-SD244, SD250 L10350-10358). softplc takes the rack's slots as
//! 8-slot Q bases in automatic mode: slots 0-7 the main base, 8-15
//! extension base 1, and so on.

mod common;
use common::Plc;

fn slots(n: usize) -> String {
    "[[slot]]\ntype = \"input\"\npoints = 16\n".repeat(n)
}

/// Ten 16-point input slots: X0-X9F on the main base (slots 0-7) and
/// extension base 1 (slots 8-9).
#[test]
fn the_base_registers_follow_the_rack() {
    let toml = format!("[[program]]\nfile = \"main.il\"\n{}", slots(10));
    let mut p = Plc::project(&toml, &[("main.il", "LD M0\nOUT SM250\nEND\n")]);
    // SD240 automatic mode; SD241 the last extension base; SD242 a bit per
    // base present, each a Q base; SD243 8 slots on the main base (bits
    // 0-3) and on extension base 1 (bits 4-7); SD244 extension bases 4-7.
    let sd: Vec<i64> = (240..=244).map(|n| p.int(&format!("SD{n}"))).collect();
    assert_eq!(sd, [0, 1, 0b11, 0x88, 0]);
    // SD250 only when SM250 turns ON: the last I/O number 9F → 09 + 1.
    p.scan();
    assert_eq!(p.int("SD250"), 0);
    p.set("M0", "1").scan();
    assert_eq!(p.int("SD250"), 0x0A);
    // Held while SM250 stays ON: a value written over it stays.
    p.set("SD250", "0").scan();
    assert_eq!(p.int("SD250"), 0);
    p.set("M0", "0").scan().set("M0", "1").scan();
    assert_eq!(p.int("SD250"), 0x0A);
}

/// Slot 40 is on extension base 5 (slots 40-47): six bases, SD244 holds
/// extension bases 4 and 5.
#[test]
fn extension_bases_past_the_third_are_in_sd244() {
    let toml = format!("[[program]]\nfile = \"main.il\"\n{}", slots(41));
    let p = Plc::project(&toml, &[("main.il", "END\n")]);
    let sd: Vec<i64> = (241..=244).map(|n| p.int(&format!("SD{n}:u16"))).collect();
    assert_eq!(sd, [5, 0b11_1111, 0x8888, 0x88]);
}

/// Without a rack: the main base alone, and no module for SD250.
#[test]
fn without_slots_the_main_base_alone() {
    let mut p = Plc::new("LD SM400\nOUT SM250\nEND\n");
    let sd: Vec<i64> = (240..=244).map(|n| p.int(&format!("SD{n}"))).collect();
    assert_eq!(sd, [0, 0, 1, 8, 0]);
    p.set("SD250", "7").scan();
    assert_eq!(p.int("SD250"), 0);
}
