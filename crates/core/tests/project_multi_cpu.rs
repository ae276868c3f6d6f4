//! `[multi_cpu]` in plc.toml (docs/multi-cpu.md): the parameters read, and
//! one failing file per limit of the auto-refresh settings (004 L8780-8879)
//! with the exact `line:col: message`.

mod common;
use common::project::{errors, ok};
use softplc_core::device::DeviceKind;

const MAIN: &str = "[[program]]\nfile = \"main.il\"\n";

fn with(t: &str) -> String {
    format!("{MAIN}[multi_cpu]\n{t}")
}

#[test]
fn parameters_are_read() {
    let p = ok(&with(
        "cpus = 3\nstop_all = { 3 = false }\nout_of_group_input = true\n\
         [[multi_cpu.refresh]]\ndevice = \"B0\"\nwords = [2, 0, 4]\n\
         [[multi_cpu.refresh]]\ndevice = \"D100\"\nwords = [16, 16, 16]\n",
    ));
    let m = p.multi_cpu.unwrap();
    assert_eq!(m.cpus, 3);
    assert_eq!(m.stop_all, [true, true, false, true]);
    assert!(m.out_of_group_input && !m.out_of_group_output);
    assert_eq!(m.refresh[0].device, DeviceKind::B);
    // Setting 1 of CPU 3 follows CPU 1's and CPU 2's points: B20-B5F.
    assert_eq!(m.refresh[0].range_of(2), (0x20, 64));
    // CPU 3's words: setting 1 at 800H-803H, setting 2 at 804H-813H.
    assert_eq!(m.shared_address(2, 1), 0x804);
    assert_eq!(m.refresh_words(2), 20);
}

#[test]
fn limits_are_load_errors() {
    let refresh = |dev: &str, words: &str| {
        with(&format!(
            "cpus = 2\n[[multi_cpu.refresh]]\ndevice = \"{dev}\"\nwords = {words}\n"
        ))
    };
    let cases = [
        (
            refresh("D0", "[3, 2]"),
            "7:9: refresh setting 1: words is a list of 2 even counts (2-word units), one per CPU",
        ),
        (
            refresh("D0", "[2, 2, 2]"),
            "7:9: refresh setting 1: words is a list of 2 even counts (2-word units), one per CPU",
        ),
        (
            refresh("B8", "[2, 2]"),
            "6:10: refresh setting 1: a bit device starts at 0 or a multiple of 16, not B8",
        ),
        (
            refresh("X0", "[2, 2]"),
            "6:10: refresh setting 1: device \"X0\" must be B, M, Y, D, W, R or ZR",
        ),
        (
            refresh("D12000", "[200, 200]"),
            "6:10: refresh setting 1: 400 points from D12000 run past the last D point",
        ),
        (
            with(
                "cpus = 2\n[[multi_cpu.refresh]]\ndevice = \"D0\"\nwords = [2048, 0]\n\
                  [[multi_cpu.refresh]]\ndevice = \"W0\"\nwords = [2, 0]\n",
            ),
            "5:1: auto refresh: CPU 1 sends 2050 words; at most 2048 (2K) a CPU",
        ),
        (
            with(
                "cpus = 2\n[[multi_cpu.refresh]]\ndevice = \"D0\"\nwords = [4, 4]\n\
                  [[multi_cpu.refresh]]\ndevice = \"D6\"\nwords = [2, 2]\n",
            ),
            "5:1: auto refresh: settings 1 and 2 overlap",
        ),
        (
            with("cpus = 5\n"),
            "4:8: cpus must be the number of CPUs, 2-4",
        ),
        (
            with("cpus = 2\nstop_all = { 3 = true }\n"),
            "5:14: stop_all: `3` is not CPU 2 (CPU 1's stop error always stops every CPU)",
        ),
        (
            with("stop_all = { 2 = true }\n"),
            "3:2: [multi_cpu] needs cpus (the number of CPUs, 2-4)",
        ),
    ];
    for (toml, want) in cases {
        assert_eq!(errors(&toml), vec![want.to_string()], "{toml}");
    }
}

/// More than four settings.
#[test]
fn five_settings_are_refused() {
    let mut t = "cpus = 2\n".to_string();
    for k in 0..5 {
        t += &format!(
            "[[multi_cpu.refresh]]\ndevice = \"D{}\"\nwords = [2, 2]\n",
            k * 10
        );
    }
    let e = errors(&with(&t));
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(
        e[0].ends_with("5 auto-refresh settings: a multi-CPU system has settings 1-4"),
        "{e:?}"
    );
}

/// An APLC-TCP is never part of a multi-CPU system.
#[test]
fn aplc_refuses_multi_cpu() {
    let e = errors(
        "[cpu]\nmodel = \"APLC-TCP\"\n[[program]]\nfile = \"main.apl\"\n[multi_cpu]\ncpus = 2\n",
    );
    let want =
        "5:2: an APLC-TCP is never part of a multi-CPU system: [multi_cpu] is for MELSEC-Q CPUs";
    assert!(e.iter().any(|m| m == want), "{e:?}");
}
