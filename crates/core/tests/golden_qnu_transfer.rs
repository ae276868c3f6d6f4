//! DFMOV, the Universal models' 32-bit batch transfer of the same data
//! (SH-080809ENG §6.4): FMOV for 32-bit values.

mod common;
use common::*;

const QNU: &str = "Q04UDEHCPU";

#[test]
fn dfmov_fills_n_32_bit_points() {
    let mut p = Plc::on_model(
        "\
LD SM400
DFMOV K100000 D10 K3
DFMOV K-2 D20 K2
DFMOV D30 D30 K3
LD X0
DFMOVP D40 D50 D60
END
",
        QNU,
    );
    p.set("D30:i32", "7")
        .set("D40:i32", "-70000")
        .set("D60", "2");
    p.scan();
    // 100000 = H186A0: low word H86A0, high word 1, in D10/D11, D12/D13, D14/D15.
    for d in ["D10", "D12", "D14"] {
        assert_eq!(p.int(&format!("{d}:i32")), 100_000, "{d}");
    }
    assert_eq!((p.int("D10:u16"), p.int("D11")), (0x86A0, 1));
    assert_eq!(p.int("D16:i32"), 0);
    assert_eq!(
        (p.int("D20:i32"), p.int("D22:i32"), p.int("D24")),
        (-2, -2, 0)
    );
    // S inside the block is read once: its old value fills the block.
    assert_eq!(
        (p.int("D30:i32"), p.int("D32:i32"), p.int("D34:i32")),
        (7, 7, 7)
    );
    assert_eq!(p.int("D50:i32"), 0);
    // DFMOVP: on the rising edge of X0 only (n from D60 = 2).
    p.set("X0", "1").scan();
    assert_eq!(
        (p.int("D50:i32"), p.int("D52:i32"), p.int("D54")),
        (-70000, -70000, 0)
    );
    p.set("D50:i32", "0").scan();
    assert_eq!(p.int("D50:i32"), 0);
    assert_running(&p);
}

#[test]
fn dfmov_n_zero_does_nothing_and_errors_are_4101() {
    let mut p = Plc::on_model("LD SM400\nDFMOV K5 D0 D100\nEND\n", QNU);
    p.scan();
    assert_eq!(p.int("D0:i32"), 0);
    assert_running(&p);
    // A negative n is 4101.
    p.set("D100", "-1").scan();
    assert_stopped(&p, 4101);
    // D12286 + 2 points would need D12288-D12289: beyond D12287.
    let mut p = Plc::on_model(
        "LD SM400\nDFMOV K5 D12286 K1\nDFMOV K5 D12286 K2\nEND\n",
        QNU,
    );
    p.scan();
    assert_eq!(p.int("D12286:i32"), 5);
    assert_stopped(&p, 4101);
}

#[test]
fn dfmov_is_refused_on_a_qnh_and_takes_word_devices() {
    assert_eq!(
        diagnostics("LD SM400\nDFMOVP K1 D0 K1\nEND\n"),
        [
            "2:1: unsupported instruction `DFMOVP`: a Universal model instruction (QnU): it needs \
          a Universal model CPU ([cpu] model = \"Q04UDEHCPU\" or another QnU model, or --model)"
        ]
    );
    assert_eq!(
        model_diagnostics(QNU, "LD SM400\nDFMOV K1 K8Y0 K1\nEND\n"),
        ["2:10: `K8Y0`: a word device is needed here"]
    );
}
