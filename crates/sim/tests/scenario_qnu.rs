//! A scenario whose `cpu` is a Universal model (QnU) runs its program file
//! on that model: its instruction set and its device points.

use softplc_sim::scenario::Scenario;

#[test]
fn a_scenario_on_a_q04udehcpu_runs_a_pulse_not_contact() {
    let dir = std::env::temp_dir().join(format!("softplc-sim-qnu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Y0 = X0 · ¬fall(X1); ZR131071 is the Q04UDEHCPU's last file register.
    std::fs::write(
        dir.join("main.il"),
        "LD X0\nANDFI X1\nOUT Y0\nLD SM400\nMOV K5 ZR131071\nEND\n",
    )
    .unwrap();
    let toml =
        "program = \"main.il\"\ncpu = \"Q04UDEHCPU\"\nscan_time = \"10ms\"\nduration = \"1s\"\n\
                [[timeline]]\nat = \"0s\"\nset = { X0 = true }\n\
                [[expect]]\ndevice = \"Y0\"\nequals = true\nat = \"0.5s\"\n\
                [[expect]]\ndevice = \"ZR131071\"\nequals = 5\nat = \"0.5s\"\n";
    let path = dir.join("s.toml");
    std::fs::write(&path, toml).unwrap();
    let sc = Scenario::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let outcome = sc
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
        .run(&mut |_| {});
    let report = outcome.report(false);
    assert_eq!((outcome.passed(), outcome.failed()), (2, 0), "{report}");
    let _ = std::fs::remove_dir_all(&dir);
}
