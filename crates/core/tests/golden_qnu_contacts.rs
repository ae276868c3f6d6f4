//! The pulse NOT contacts of the Universal models (SH-080809ENG §5.1.3):
//! LDPI/ANDPI/ORPI are OFF only on the scan their device rises, LDFI/ANDFI/
//! ORFI only on the scan it falls; ON on every other scan. Refused, with the
//! reason, on the CPUs that lack them.

mod common;
use common::*;

/// The QnU CPU of these tests (the production machine's model).
const QNU: &str = "Q04UDEHCPU";

#[test]
fn pulse_not_contacts_off_only_on_their_edge() {
    let mut p = Plc::on_model(
        "\
LDPI X0
OUT Y0
LDFI X0
OUT Y1
LD SM400
ANDPI X0
OUT Y2
LD SM400
ANDFI X0
OUT Y3
LD SM401
ORPI X0
OUT Y4
LD SM401
ORFI X0
OUT Y5
END
",
        QNU,
    );
    // SM400 is always ON, SM401 always OFF, so each rung is its contact.
    // …PI (Y0, Y2, Y4) are OFF only where X0 goes OFF→ON, …FI (Y1, Y3, Y5)
    // only where it goes ON→OFF: the negation of LDP/LDF.
    for (x0, want) in [
        ("0", "111111"), // stays OFF
        ("1", "010101"), // OFF→ON
        ("1", "111111"), // stays ON
        ("0", "101010"), // ON→OFF
        ("0", "111111"),
        ("1", "010101"), // a second rising edge
    ] {
        inputs(&mut p, x0);
        p.scan();
        assert_eq!(outputs(&p, 6), want, "X0 = {x0}");
    }
    assert_running(&p);
}

#[test]
fn pulse_not_contacts_on_a_word_bit_and_an_indexed_bit() {
    // D0.5 is bit 5 of D0 (32); X0Z1 with Z1 = 3 is X3.
    let mut p = Plc::on_model(
        "\
LDPI D0.5
OUT Y0
LDFI D0.5
OUT Y1
LD SM400
ANDPI X0Z1
OUT Y2
END
",
        QNU,
    );
    p.set("Z1", "3");
    for (d0, x3, want) in [
        ("0", "0", "111"),
        ("32", "0", "011"), // bit 5 rises
        ("33", "1", "110"), // bit 5 stays ON; X3 rises
        ("1", "1", "101"),  // bit 5 falls
        ("96", "0", "011"), // bit 5 rises again (D0 = 0x60)
    ] {
        p.set("D0", d0).set("X3", x3);
        p.scan();
        assert_eq!(outputs(&p, 3), want, "D0 = {d0}, X3 = {x3}");
    }
}

#[test]
fn pulse_not_contacts_in_a_rung_with_mps_and_anb() {
    // Y0 = X0 · ¬rise(X1), Y1 = X0 · ¬fall(X1),
    // Y2 = X0 · (¬rise(X2) + ¬fall(X3)).
    let mut p = Plc::on_model(
        "\
LD X0
MPS
ANDPI X1
OUT Y0
MRD
ANDFI X1
OUT Y1
MPP
LDPI X2
ORFI X3
ANB
OUT Y2
END
",
        QNU,
    );
    for (x, want) in [
        ("1000", "111"),
        ("1110", "011"), // X1 and X2 rise: Y0 OFF; ¬fall(X3) keeps Y2 ON
        ("1011", "101"), // X1 falls: Y1 OFF; X2 stays ON
        ("1001", "111"), // X2 falls, X3 stays ON: no …PI/…FI edge
        ("1010", "110"), // X2 rises and X3 falls in the same scan: Y2 OFF
        ("0100", "000"), // X0 OFF; X1 rises while the rung is OFF …
        ("1100", "111"), // … so its edge memory is ON: no rise seen now
        ("1000", "101"), // X1 falls
    ] {
        inputs(&mut p, x);
        p.scan();
        assert_eq!(outputs(&p, 3), want, "X0-X3 = {x}");
    }
}

/// The reason a CPU without the Universal models' instructions gives.
const NEEDS_QNU: &str = "a Universal model instruction (QnU): it needs a Universal model CPU \
     ([cpu] model = \"Q04UDEHCPU\" or another QnU model, or --model)";

#[test]
fn refused_with_the_reason_on_other_cpus() {
    for m in ["LDPI", "LDFI"] {
        assert_eq!(
            diagnostics(&format!("{m} X0\nOUT Y0\nEND\n")),
            [format!("1:1: unsupported instruction `{m}`: {NEEDS_QNU}")]
        );
    }
    // A refused contact is still a contact: the rung goes on (ANB, OUT) with
    // no further diagnostic.
    for m in ["ANDPI", "ANDFI", "ORPI", "ORFI"] {
        let src = format!("LD X0\nLD X1\n{m} X2\nANB\nOUT Y0\nEND\n");
        let want = [format!("3:1: unsupported instruction `{m}`: {NEEDS_QNU}")];
        assert_eq!(model_diagnostics("Q06HCPU", &src), want);
        assert_eq!(model_diagnostics("Q25PHCPU", &src), want);
        // Every Universal model has them.
        for qnu in ["Q00UJCPU", "Q03UDVCPU", QNU, "Q26UDEHCPU"] {
            Plc::on_model(&src, qnu);
        }
    }
    // The process-control instructions are refused on a Universal model.
    let e = model_diagnostics(QNU, "LD X0\nS.IN D0 D100 D200 M0\nEND\n");
    assert_eq!(e.len(), 1);
    assert!(
        e[0].starts_with("2:1: unsupported instruction `S.IN`: a process-control instruction"),
        "{e:?}"
    );
    // No pulse form.
    assert_eq!(
        model_diagnostics(QNU, "LDPIP X0\nOUT Y0\nEND\n"),
        ["1:1: `LDPIP`: LDPI has no pulse form"]
    );
}
