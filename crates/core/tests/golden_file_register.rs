//! Golden tests of the file-register byte instructions ZRRDB/ZRWRB
//! (`file_register.rs`): byte 2k is the low byte of ZRk, 2k+1 its high byte.
//! Q06HCPU defaults: ZR0-ZR517119, so bytes 0-1034239.

mod common;
use common::{assert_running, assert_stopped, Plc};

#[test]
fn zrrdb_reads_bytes_low_first_and_clears_the_high_byte() {
    let mut p = Plc::new(
        "LD SM400\nMOV H1234 ZR0\nMOV HABCD ZR1\nMOV HFFFF D0\n\
         ZRRDB K0 D0\nZRRDB K1 D1\nZRRDB K3 D2\nZRRDB K2 D3\nEND\n",
    );
    p.scan();
    assert_running(&p);
    // ZR0 = 12 34h, ZR1 = AB CDh: bytes 0-3 are 34h, 12h, CDh, ABh.
    let d: Vec<i64> = ["D0", "D1", "D2", "D3"].iter().map(|d| p.int(d)).collect();
    assert_eq!(d, [0x34, 0x12, 0xAB, 0xCD]);
}

#[test]
fn zrwrb_writes_one_byte_and_keeps_the_other() {
    let mut p =
        Plc::new("LD SM400\nMOV H1234 ZR0\nMOV HABCD ZR1\nZRWRB K1 HFF\nZRWRB K2 H177\nEND\n");
    p.scan();
    assert_running(&p);
    // Byte 1 (high of ZR0) ← FFh: FF34h; byte 2 (low of ZR1) ← 77h (low byte of 177h): AB77h.
    assert_eq!((p.int("ZR0:u16"), p.int("ZR1:u16")), (0xFF34, 0xAB77));
}

#[test]
fn zrrdb_byte_number_is_32_bit() {
    // Byte 131073 = 2·65536 + 1: the high byte of ZR65536.
    let mut p = Plc::new("LD SM400\nDMOV K131073 D10\nMOV H5A00 ZR65536\nZRRDB D10 D4\nEND\n");
    p.scan();
    assert_eq!(p.int("D4"), 0x5A);
}

#[test]
fn zrwrbp_writes_on_the_rising_edge_only() {
    let mut p = Plc::new("LD SM400\nINC D20\nLD X1\nZRWRBP K4 D20\nEND\n");
    p.set("X1", "1").scans(3);
    // D20 = 1 at the first scan, when X1 rose: ZR2 low byte = 1; later scans write nothing.
    assert_eq!((p.int("D20"), p.int("ZR2")), (3, 1));
}

#[test]
fn zr_byte_numbers_outside_the_file_registers_are_4101() {
    let mut p = Plc::new("LD X0\nZRRDB K1034240 D0\nEND\n");
    p.scan();
    assert_running(&p);
    p.set("X0", "1").scan();
    assert_stopped(&p, 4101);
    let mut p = Plc::new("LD SM400\nDMOV K-1 D10\nZRWRB D10 K1\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

/// A project with `[devices]` settings `devices` and one program.
fn project(devices: &str, program: &str) -> Plc {
    let toml = format!("[[program]]\nfile = \"main.il\"\n[devices]\n{devices}");
    Plc::project(&toml, &[("main.il", program)])
}

/// SD640 is the drive of the file-register file (004 App. 2, L10532-10533):
/// 3 for the standard RAM, which holds 32K points on a QnHCPU (§10.7.1
/// (1)), 1 for memory card A when the file is larger; SM640 is ON while
/// file registers are in use (App. 1 L9673); SD647 the capacity in K points.
#[test]
fn sd640_is_the_drive_the_file_register_size_needs() {
    let p = project("file_register = 32768\n", "END\n");
    assert_eq!(
        (p.int("SD640"), p.bit("SM640"), p.int("SD647")),
        (3, true, 32)
    );
    let p = project("file_register = 33792\n", "END\n");
    assert_eq!(
        (p.int("SD640"), p.bit("SM640"), p.int("SD647")),
        (1, true, 33)
    );
    // The default, 517120 points, is a 1 MB card.
    let p = Plc::new("END\n");
    assert_eq!(
        (p.int("SD640"), p.bit("SM640"), p.int("SD647")),
        (1, true, 505)
    );
    // No file registers: no drive, not in use, no name.
    let p = project("file_register = 0\n", "END\n");
    assert_eq!(
        (p.int("SD640"), p.bit("SM640"), p.int("SD641")),
        (0, false, 0)
    );
}

/// A Universal model's standard RAM holds its default file registers (the
/// Q04UDEHCPU's 256 KB = 131072 points): they are drive 3.
#[test]
fn a_universal_models_file_registers_are_in_its_standard_ram() {
    let p = Plc::on_model("END\n", "Q04UDEHCPU");
    assert_eq!((p.int("SD640"), p.int("SD647")), (3, 128));
    let toml = "[cpu]\nmodel = \"Q04UDEHCPU\"\n[devices]\nfile_register = 132096\n\
                [[program]]\nfile = \"main.il\"\n";
    let p = Plc::project(toml, &[("main.il", "END\n")]);
    assert_eq!(p.int("SD640"), 1);
}

/// SD641-SD646 hold the file name as ASCII, two characters a word, the
/// first in the low byte, then `.` and the extension QDR (004 App. 2,
/// L10534-10539): "MAIN    .QDR" by default.
#[test]
fn sd641_to_sd646_hold_the_file_register_file_name() {
    let words =
        |p: &Plc| -> Vec<i64> { (641..=646).map(|n| p.int(&format!("SD{n}:u16"))).collect() };
    let p = Plc::new("END\n");
    // "MA" "IN" "  " "  " ".Q" "DR", low byte first.
    assert_eq!(words(&p), [0x414D, 0x4E49, 0x2020, 0x2020, 0x512E, 0x5244]);
    let p = project("file_register_name = \"recipe1\"\n", "END\n");
    // "RECIPE1 ": "RE" "CI" "PE" "1 ".
    assert_eq!(words(&p), [0x4552, 0x4943, 0x4550, 0x2031, 0x512E, 0x5244]);
    let toml = "[[program]]\nfile = \"main.il\"\n[devices]\nfile_register_name = \"TOOLONGNAME\"\n";
    let e = Plc::try_project(toml, &[("main.il", "END\n")])
        .err()
        .unwrap();
    assert!(e.contains("must be 1-8 letters, digits or _"), "{e}");
}

/// Reading or writing file registers outside the registered range is no
/// error (004 §10.7.5 (1), L7180-7194): the memory card reads 0 and the
/// write changes nothing; SM672 turns ON at END (App. 1 L9676) and stays ON
/// until the program resets it.
#[test]
fn file_registers_outside_the_registered_range_are_no_error() {
    // Default: ZR0-ZR517119 on the memory card. Z0 = 20: ZR517110Z0 is ZR517130.
    let mut p = Plc::new(
        "LD SM400\nMOV K20 Z0\nMOV K99 D0\nMOV ZR517110Z0 D0\nMOV ZR517090Z0 D3\n\
         LD X0\nMOV K7 ZR517110Z0\nLD X1\nMOV ZR517110Z0 D1\nLD X2\nRST SM672\nEND\n",
    );
    p.scan();
    assert_running(&p);
    assert_eq!((p.int("D0"), p.int("SD0")), (0, 0));
    assert!(p.bit("SM672"));
    // The write of one scan is gone at the next.
    p.set("X0", "1").scan();
    p.set("X0", "0").set("X1", "1").scan();
    assert_eq!(p.int("D1"), 0);
    assert_running(&p);
    // The program resets SM672, but ZR517130 is read every scan, so END
    // sets it again.
    p.set("X2", "1").scan();
    assert!(p.bit("SM672"));
}

/// In-range accesses leave SM672 OFF.
#[test]
fn sm672_stays_off_for_accesses_in_range() {
    let mut p = Plc::new("LD SM400\nMOV K5 Z0\nMOV K1 ZR517110Z0\nMOV R5Z0 D0\nEND\n");
    p.scan();
    assert!(!p.bit("SM672"));
    assert_eq!(p.int("ZR517115"), 1);
}

/// RSET to a block beyond the registered file registers is no error; R
/// there reads 0 and writes nothing (004 §10.7.5 (1), (2) (a)).
#[test]
fn r_in_a_block_beyond_the_file_registers_reads_0() {
    let mut p = Plc::new(
        "LD SM400\nRSET K0\nMOV K11 R5\nRSET K16\nMOV R5 D0\nMOV K22 R5\nRSET K0\nMOV R5 D1\nEND\n",
    );
    p.set("D0", "-1").scan();
    assert_running(&p);
    assert_eq!((p.int("D0"), p.int("D1"), p.int("ZR5")), (0, 11, 11));
    assert!(p.bit("SM672"));
    // The ignored write of K22 is not read back at the next scan.
    p.scan();
    assert_eq!(p.int("D0"), 0);
}

/// An operand that starts inside the file registers and runs past their
/// end is one access softplc cannot split: 4101.
#[test]
fn an_operand_straddling_the_end_of_the_file_registers_is_4101() {
    let mut p = Plc::new("LD SM400\nMOV K1 Z0\nDMOV K1 ZR517118Z0\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

/// SM672 is memory card A's flag: file registers in the standard RAM set
/// nothing, and still read 0 outside their range with no error.
#[test]
fn standard_ram_file_registers_outside_the_range_set_no_flag() {
    let p = &mut project(
        "file_register = 32768\n",
        "LD SM400\nMOV K1 Z0\nMOV K99 D0\nMOV ZR32767Z0 D0\nMOV K5 ZR32767Z0\nEND\n",
    );
    p.scan();
    assert_running(p);
    assert_eq!(p.int("D0"), 0);
    assert!(!p.bit("SM672"));
}

/// The APLC-TCP has no file-register file to name: the key is refused.
#[test]
fn file_register_name_is_refused_on_an_aplc() {
    let toml = "[cpu]\nmodel = \"APLC-TCP\"\n[devices]\nfile_register_name = \"MAIN\"\n\
                [[program]]\nfile = \"a.apl\"\n";
    let err = Plc::try_project(toml, &[("a.apl", "")])
        .err()
        .unwrap_or_default();
    assert!(
        err.contains("file_register_name is a MELSEC-Q parameter"),
        "{err}"
    );
}
