//! The inter-CPU instructions and operands of a multi-CPU system (004
//! §16.2-16.4, L8949-9111; qcpu.md §7.4-7.6): `U3En\G` and FROM read
//! another CPU's shared memory, S(P).TO writes the own one, and the errors
//! 2110/2114/2115/2116, 4101 and 4107. One CPU is built as CPU `own` of a
//! system (`DeviceConfig::set_multi_cpu`); the other CPUs' windows are
//! written through the Cpu door, as the system's mirror does after each
//! CPU's END. Values worked out by hand. Step numbers: contacts and coils
//! 1 step, any other instruction 1 + its operand count.

mod common;
use common::{assert_running, assert_stopped, diagnostics, Plc};
use softplc_core::device::MultiCpu;

/// Unit 3 (100 words) is a module CPU 2 controls, unit 4 (100 words) one
/// this CPU controls.
fn cpu(own: u32, cpus: u32, refresh_words: u32, src: &str) -> Plc {
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices.set_units(&[(3, 100), (4, 100)]);
    cfg.devices.set_multi_cpu(MultiCpu {
        own,
        cpus,
        foreign: vec![3],
        refresh_words,
    });
    Plc::with_config(src, cfg)
}

/// Scans `src` once in `p`'s place and checks the stop error and its step.
fn stops_at(mut p: Plc, code: u16, step: u32, src: &str) {
    p.scan();
    assert_stopped(&p, code);
    let e = p.cpu.error().expect("an error");
    assert_eq!(e.step, Some(step), "{src}");
}

/// CPU 1 reads CPU 2's shared memory with `U3E1\G`, FROM/DFRO and a BMOV
/// block; it reads a module CPU 2 controls too (004 L9060-9069: other CPUs
/// read the user area; L9199-9205). CPU 2's user area starts at 800H =
/// G2048 (no auto refresh).
#[test]
fn another_cpus_shared_memory_and_module_are_read() {
    let mut p = cpu(
        1,
        2,
        0,
        "LD SM400\nMOV U3E1\\G2048 D0\nFROM H3E1 K2049 D1 K2\nDFRO H3E1 K2048 D10 K1\n\
         BMOV U3E1\\G2048 D20 K3\nMOV U3\\G5 D30\nFROM H3 K5 D31 K1\nMOV U3E1\\G0 D32\n\
         LD U3E1\\G2050.3\nOUT M0\nLD U3E1\\G2050.8\nOUT M1\nEND\n",
    );
    p.set("U3E1\\G2048", "1234")
        .set("U3E1\\G2049", "-5")
        .set("U3E1\\G2050", "255")
        .set("U3E1\\G0", "1")
        .set("U3\\G5", "77");
    p.scan();
    assert_running(&p);
    assert_eq!(p.int("D0"), 1234);
    assert_eq!((p.int("D1"), p.int("D2")), (-5, 255));
    // Low word 1234, high word -5 (FFFBH): -5·65536 + 1234 = -326446.
    assert_eq!(p.int("D10:i32"), -326_446);
    assert_eq!((p.int("D20"), p.int("D21"), p.int("D22")), (1234, -5, 255));
    assert_eq!((p.int("D30"), p.int("D31")), (77, 77));
    // The own-operation area's valid flag (0H) is readable by other CPUs.
    assert_eq!(p.int("D32"), 1);
    // 255 = 0000 0000 1111 1111: bit 3 ON, bit 8 OFF.
    assert!(p.bit("M0"));
    assert!(!p.bit("M1"));
}

/// A program's `U\G` or FROM/TO on its own CPU shared memory is SP.UNIT
/// ERROR 2114, read or write (004 L8994-8996), at the instruction's step.
#[test]
fn own_shared_memory_is_2114() {
    for (src, step) in [
        ("LD SM400\nMOV U3E0\\G2048 D0\nEND\n", 1),
        ("LD SM400\nMOV K1 U3E0\\G2048\nEND\n", 1),
        ("LD SM400\nMOV U3E0\\G0Z0 D0\nEND\n", 1),
        ("LD SM400\nFROM H3E0 K2048 D0 K1\nEND\n", 1),
        ("LD SM400\nTO H3E0 K2048 D0 K1\nEND\n", 1),
        ("LD U3E0\\G0.0\nOUT M0\nEND\n", 0),
        // LD 1 step, MOV K7 D0 3 steps: the second MOV is step 4.
        ("LD SM400\nMOV K7 D0\nMOV U3E0\\G2048 D1\nEND\n", 4),
    ] {
        stops_at(cpu(1, 2, 0, src), 2114, step, src);
    }
    // The error names CPU 1's shared memory: SD4 = 0401H, SD5 the CPU
    // number, SD6 its I/O number 3E00H (App. 2 SD5 *1, L10182-10200).
    let mut p = cpu(1, 2, 0, "LD SM400\nMOV U3E0\\G2048 D0\nEND\n");
    p.scan();
    assert_eq!(p.int("SD4"), 0x0401);
    assert_eq!((p.int("SD5"), p.int("SD6")), (1, 0x3E00));
    // The MOV before the error ran.
    let mut p = cpu(1, 2, 0, "LD SM400\nMOV K7 D0\nMOV U3E0\\G2048 D1\nEND\n");
    p.scan();
    assert_eq!(p.int("D0"), 7);
    // Names from outside monitor the own memory (contract §6).
    p.set("U3E0\\G2048", "5");
    assert_eq!(p.int("U3E0\\G2048"), 5);
}

/// Writing another CPU's shared memory — a `U\G` destination, TO, a block
/// destination, S.TO — is SP.UNIT ERROR 2115 (004 L8994).
#[test]
fn writing_another_cpus_shared_memory_is_2115() {
    for src in [
        "LD SM400\nMOV K1 U3E1\\G2048\nEND\n",
        "LD SM400\nTO H3E1 K2048 K1 K1\nEND\n",
        "LD SM400\nBMOV D0 U3E1\\G2048 K2\nEND\n",
        "LD SM400\nFMOV K0 U3E1\\G2048 K2\nEND\n",
        "LD SM400\nFROM H3 K0 U3E1\\G2048 K1\nEND\n",
        "LD SM400\nOUT U3E1\\G2048.0\nEND\n",
        "LD SM400\nSP.TO H3E1 K2048 D0 K1 M0\nEND\n",
    ] {
        stops_at(cpu(1, 2, 0, src), 2115, 1, src);
    }
}

/// Writing a module another CPU controls is SP.UNIT ERROR 2116 (004
/// L9199-9205); the own CPU's module is written as usual.
#[test]
fn writing_another_cpus_module_is_2116() {
    for src in [
        "LD SM400\nMOV K1 U3\\G0\nEND\n",
        "LD SM400\nTO H3 K0 K1 K1\nEND\n",
        "LD SM400\nDTO H3 K0 K1 K1\nEND\n",
        "LD SM400\nFROM H3E1 K2048 U3\\G0 K1\nEND\n",
        "LD SM400\nBMOV D0 U3\\G0 K4\nEND\n",
    ] {
        stops_at(cpu(1, 2, 0, src), 2116, 1, src);
    }
    let mut p = cpu(1, 2, 0, "LD SM400\nMOV K9 U4\\G0\nTO H4 K1 K8 K1\nEND\n");
    p.scan();
    assert_running(&p);
    assert_eq!((p.int("U4\\G0"), p.int("U4\\G1")), (9, 8));
}

/// A CPU that is not installed — CPU 3 of a 2-CPU system, any CPU of a
/// single CPU — is SP.UNIT ERROR 2110 (004 L8997).
#[test]
fn a_cpu_not_installed_is_2110() {
    for src in [
        "LD SM400\nMOV U3E2\\G2048 D0\nEND\n",
        "LD SM400\nFROM H3E2 K2048 D0 K1\nEND\n",
        "LD SM400\nSP.TO H3E2 K2048 D0 K1 M0\nEND\n",
    ] {
        stops_at(cpu(1, 2, 0, src), 2110, 1, src);
    }
    for src in [
        "LD SM400\nMOV U3E0\\G2048 D0\nEND\n",
        "LD SM400\nS.TO H3E0 K2048 D0 K1 M0\nEND\n",
    ] {
        stops_at(Plc::new(src), 2110, 1, src);
    }
}

/// SP.TO in CPU 2 (n1 = 3E1H) with 4 auto-refresh words: its user area
/// starts at 800H + 4 = 804H = G2052. D0-D2 go to G2052-G2054 at execution;
/// M0 turns ON at the END of that scan and OFF at the next END, M1 (error
/// completion) is OFF (004 §8.1.5 L5584-5586; PM S.TO).
#[test]
fn s_to_writes_the_user_area_and_completes_at_end() {
    let mut p = cpu(
        2,
        2,
        4,
        "LD X0\nSP.TO H3E1 H804 D0 K3 M0\nLD M0\nOUT M10\nEND\n",
    );
    p.set("D0", "11")
        .set("D1", "-22")
        .set("D2", "33")
        .set("M1", "1");
    p.set("X0", "1").scan();
    assert_running(&p);
    let words: Vec<i64> = (2051..=2055)
        .map(|g| p.int(&format!("U3E1\\G{g}")))
        .collect();
    assert_eq!(words, [0, 11, -22, 33, 0]);
    assert!(p.bit("M0"), "ON from the END of the completion scan");
    assert!(!p.bit("M1"), "normal completion: D+1 OFF");
    assert!(!p.bit("M10"), "M0 was still OFF while the scan ran");
    // Scan 2: the pulse form does not run again; M0 was ON during the scan
    // and goes OFF at its END.
    p.scan();
    assert!(p.bit("M10"));
    assert!(!p.bit("M0"));
    p.scan();
    assert!(!p.bit("M10"));
    // Executed every scan, S.TO completes at every END: M0 stays ON.
    let mut p = cpu(2, 2, 4, "LD X0\nS.TO H3E1 H804 D0 K1 M0\nEND\n");
    p.set("X0", "1").scans(3);
    assert!(p.bit("M0"));
    p.set("X0", "0").scan();
    assert!(!p.bit("M0"));
}

/// S.TO into the own-operation (0-1FFH), system (200-7FFH) or auto-refresh
/// area (800H-803H here), or past FFFH, is OPERATION ERROR 4101 (004
/// L9053-9069, L9106); FFDH-FFFH is the user area's end.
#[test]
fn s_to_outside_the_user_area_is_4101() {
    for src in [
        "LD SM400\nS.TO H3E1 K0 D0 K1 M0\nEND\n",
        "LD SM400\nS.TO H3E1 H200 D0 K1 M0\nEND\n",
        "LD SM400\nS.TO H3E1 H7FF D0 K2 M0\nEND\n",
        "LD SM400\nS.TO H3E1 H800 D0 K1 M0\nEND\n",
        "LD SM400\nS.TO H3E1 H803 D0 K1 M0\nEND\n",
        "LD SM400\nS.TO H3E1 HFFE D0 K3 M0\nEND\n",
        "LD SM400\nS.TO H3E1 H804 D0 K-1 M0\nEND\n",
    ] {
        stops_at(cpu(2, 2, 4, src), 4101, 1, src);
    }
    let mut p = cpu(2, 2, 4, "LD SM400\nS.TO H3E1 HFFD D0 K3 M0\nEND\n");
    p.set("D2", "3").scan();
    assert_running(&p);
    assert_eq!(p.int("U3E1\\G4095"), 3);
    // n1 of a module is not a shared memory: 4100.
    let src = "LD SM400\nS.TO H4 H804 D0 K1 M0\nEND\n";
    stops_at(cpu(2, 2, 4, src), 4100, 1, src);
}

/// 32 S.TO may wait for END; the 33rd is OPERATION ERROR 4107 (004
/// L9020-9024). LD SM400 is step 0 and each S.TO 6 steps: the 33rd is at
/// step 1 + 32·6 = 193. The count starts again after each END.
#[test]
fn the_33rd_s_to_before_end_is_4107() {
    let program = |n: usize| {
        let line = "S.TO H3E0 K2048 D0 K1 M0\n";
        format!("LD SM400\n{}END\n", line.repeat(n))
    };
    let mut p = cpu(1, 2, 0, &program(32));
    p.scans(3);
    assert_running(&p);
    assert!(p.bit("M0"));
    let src = program(33);
    stops_at(cpu(1, 2, 0, &src), 4107, 193, &src);
}

/// The motion-CPU instructions need a motion CPU; a QCPU has no S.FROM
/// (004 L9000-9028).
#[test]
fn motion_cpu_instructions_and_s_from_are_rejected() {
    for m in [
        "S.SFCS", "SP.SFCS", "S.SVST", "SP.SVST", "S.CHGV", "SP.CHGV", "S.CHGT", "SP.CHGT",
        "S.CHGA", "SP.CHGA", "S.DDWR", "SP.DDWR", "S.DDRD", "SP.DDRD", "S.GINT", "SP.GINT",
    ] {
        let d = diagnostics(&format!("LD X0\n{m} H3E1 K0 D0 M0\nEND\n"));
        assert!(
            d.iter().any(|d| d.contains("needs a motion CPU")),
            "{m}: {d:?}"
        );
    }
    for m in ["S.FROM", "SP.FROM"] {
        let d = diagnostics(&format!("LD X0\n{m} H3E1 K0 D0 K1 M0\nEND\n"));
        assert!(
            d.iter()
                .any(|d| d.contains("not a MELSEC-Q instruction") && d.contains("FROM")),
            "{m}: {d:?}"
        );
    }
}

/// Blocks other instructions write count as writes too: `$MOV` of a string
/// into another CPU's memory is 2115, DATERD into it 2115, SORT in place on
/// it 2115 (004 L8994).
#[test]
fn written_blocks_of_other_instructions_are_refused() {
    for src in [
        "LD SM400\n$MOV \"AB\" U3E1\\G2048\nEND\n",
        "LD SM400\nDATERD U3E1\\G2048\nEND\n",
        "LD SM400\nSORT U3E1\\G2048 K4 K1 M0 D0\nEND\n",
    ] {
        let mut p = cpu(1, 2, 0, src);
        p.scan();
        assert_stopped(&p, 2115);
    }
}
