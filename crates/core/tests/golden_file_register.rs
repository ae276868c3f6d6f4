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
