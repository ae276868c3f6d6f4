//! The rack (004 ch. 5 I/O numbering, ch. 8 intelligent function modules):
//! I/O assignment and its SP.UNIT LAY ERR. rules, buffer memory as
//! `U<n>\G<addr>` and with FROM/TO/DFRO/DTO, SP.UNIT ERROR 2110, direct
//! I/O DX/DY. Values worked out by hand from the manual's rules.

mod common;
use common::{assert_running, assert_stopped, Plc};

/// A rack: 32 inputs X0-X1F (slot 0), 16 outputs Y20-Y2F (slot 1), a
/// generic module of 100 words at X/Y30 (slot 2, unit 3), an empty slot
/// (16 points, 40-4F), a generic module at X/Y50 (slot 4, unit 5).
const RACK: &str = "[[program]]\nfile = \"main.il\"\n\
    [[slot]]\ntype = \"input\"\npoints = 32\n\
    [[slot]]\ntype = \"output\"\npoints = 16\n\
    [[slot]]\ntype = \"intelligent\"\nbuffer_words = 100\n\
    [[slot]]\ntype = \"empty\"\n\
    [[slot]]\ntype = \"intelligent\"\nmodule = \"generic\"\n";

fn rack(program: &str) -> Plc {
    Plc::project(RACK, &[("main.il", program)])
}

/// `U3\G10` is word 10 of the module at X/Y30: a word operand like D.
#[test]
fn buffer_memory_is_a_word_device() {
    let mut p = rack("LD SM400\nMOV K1234 U3\\G10\nMOV U3\\G10 D0\nMOV U5\\G4095 D1\nEND\n");
    p.set("U5\\G4095", "-7");
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("U3\\G10"), 1234);
    assert_eq!(p.int("D0"), 1234);
    assert_eq!(p.int("D1"), -7);
    // Units are separate memories: U5\G10 is untouched.
    assert_eq!(p.int("U5\\G10"), 0);
}

/// FROM/TO move words between buffer memory and devices; DFRO/DTO 32-bit
/// pairs (n3 counts pairs); a constant S of TO fills every word.
#[test]
fn from_and_to() {
    let mut p = rack(
        "LD SM400\nTO H3 K0 D10 K3\nFROM H3 K1 D20 K2\nTO H5 K0 K-1 K4\nDTO H5 K10 K100000 K2\nDFRO H5 K10 D30 K1\nEND\n",
    );
    p.set("D10", "1").set("D11", "2").set("D12", "3");
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("U3\\G0"), 1);
    assert_eq!(p.int("U3\\G2"), 3);
    assert_eq!((p.int("D20"), p.int("D21")), (2, 3));
    for g in 0..4 {
        assert_eq!(p.int(&format!("U5\\G{g}")), -1, "U5\\G{g}");
    }
    assert_eq!(p.int("U5\\G4"), 0);
    // 100000 = H186A0: low word 86A0, high word 1, twice.
    assert_eq!(p.int("U5\\G10:u32"), 100_000);
    assert_eq!(p.int("U5\\G12:u32"), 100_000);
    assert_eq!(p.int("D30:i32"), 100_000);
}

/// Index modification within a module: U3\G0Z0 with Z0 = 99 is the last
/// word; Z0 = 100 runs past the module's 100 words: OPERATION ERROR 4101.
#[test]
fn indexed_buffer_memory_past_the_module_is_4101() {
    let mut p = rack("LD SM400\nMOV K5 U3\\G0Z0\nEND\n");
    p.set("Z0", "99").scan();
    assert_running(&p);
    assert_eq!(p.int("U3\\G99"), 5);
    p.set("Z0", "100").scan();
    assert_stopped(&p, 4101);
}

/// FROM past the module's buffer memory: 4101.
#[test]
fn from_past_the_buffer_is_4101() {
    let mut p = rack("LD SM400\nFROM H3 K99 D0 K2\nEND\n");
    p.scan();
    assert_stopped(&p, 4101);
}

/// Buffer memory of a slot with no intelligent module — the input slot
/// (unit 0), the empty slot (unit 4) or no slot (unit 9) — is SP.UNIT
/// ERROR 2110 when the instruction runs (004 L4952, L8997).
#[test]
fn no_module_is_2110() {
    for program in [
        "LD SM400\nFROM H0 K0 D0 K1\nEND\n",
        "LD SM400\nTO H4 K0 K1 K1\nEND\n",
        "LD SM400\nMOV U9\\G0 D0\nEND\n",
        "LD SM400\nMOV K1 U2\\G0Z0\nEND\n",
    ] {
        let mut p = rack(program);
        p.scan();
        assert_stopped(&p, 2110);
    }
    // Not executed: no error.
    let mut p = rack("LD X0\nFROM H9 K0 D0 K1\nEND\n");
    p.scan();
    assert_running(&p);
}

/// `LD DX10` reads the input module now: after `OUT X10` wrote device
/// memory, DX10 gives the module's value, and X10 then holds it too
/// (004 L6071-6083).
#[test]
fn direct_input_reads_the_module_and_updates_x() {
    let mut p = rack("LD SM400\nOUT X10\nLD X10\nOUT M0\nLD DX10\nOUT M1\nLD X10\nOUT M2\nEND\n");
    p.scan();
    assert!(p.bit("M0"), "OUT X10 set device memory");
    assert!(!p.bit("M1"), "the module's X10 is OFF");
    assert!(!p.bit("M2"), "a later X10 sees what DX10 read");
    p.set("X10", "1").scan();
    assert!(p.bit("M1") && p.bit("M2"));
}

/// `OUT DY20` writes Y20 at once (004 L6134-6150).
#[test]
fn direct_output() {
    let mut p = rack("LD X0\nOUT DY20\nLD Y20\nOUT M0\nEND\n");
    p.set("X0", "1").scan();
    assert!(p.bit("Y20") && p.bit("M0"));
}

/// Names from outside (`--set`/`--show`, scenarios, HTTP): a unit with no
/// module and an address past the module's words are errors naming them.
#[test]
fn buffer_memory_names_from_outside() {
    use softplc_core::access::DeviceSpec;
    let p = rack("END\n");
    let read = |s: &str| p.cpu.read_device(&DeviceSpec::parse(s).unwrap());
    assert_eq!(
        read("U9\\G0").unwrap_err(),
        "`U9\\G0`: no intelligent function module has unit number 9 (start I/O number 90)"
    );
    assert_eq!(
        read("U3\\G100").unwrap_err(),
        "`U3\\G100`: past the module's buffer memory (G0-G99)"
    );
    assert_eq!(
        read("U3\\G99:i32").unwrap_err(),
        "`U3\\G99:i32`: past the module's buffer memory (G0-G99)"
    );
    assert!(read("U3\\G98:i32").is_ok());
}

/// Device initial values reach buffer memory at power-on and STOP→RUN, and
/// the auto refresh copies at END: CPU → module before the module runs,
/// module → CPU after (004 ch. 8, L5440-5462).
#[test]
fn initial_values_and_auto_refresh() {
    let toml = "[[program]]\nfile = \"main.il\"\n\
        [[slot]]\ntype = \"intelligent\"\nbuffer_words = 20\n\
        refresh = [{ buffer = 10, to = \"D100\", words = 2 }, { buffer = 0, from = \"W10\", words = 3 }]\n\
        [initial]\n\"U0\\\\G5\" = 77\n";
    let mut p = Plc::project(
        toml,
        &[("main.il", "LD SM400\nMOVP K9 W11\nMOV U0\\G5 D0\nEND\n")],
    );
    p.set("U0\\G10", "4").set("U0\\G11", "-2");
    p.scan();
    assert_eq!(p.int("D0"), 77, "the initial value was written at power-on");
    // END of scan 1: W10-W12 → G0-G2, then G10-G11 → D100-D101.
    assert_eq!(p.int("U0\\G1"), 9);
    assert_eq!((p.int("D100"), p.int("D101")), (4, -2));
    // A program write to G10 reaches D100 at the same END.
    p.set("U0\\G10", "5").scan();
    assert_eq!(p.int("D100"), 5);
}
