//! Scenarios bound to the simulated modules of a project's rack: model
//! ports on module channels (`U<n>\CH<k>`, mA or V, scaled with `signal` and
//! `eng`) and on buffer-memory words (`U<n>\G<addr>`). The fixture project
//! is tests/rack: a Q64AD reading a tank level, a Q64DA driving the inflow
//! valve, a generic module.

use std::path::{Path, PathBuf};

use softplc_core::access::Value;
use softplc_sim::scenario::Scenario;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/rack")
        .join(name)
}

/// The loop closes through the modules: level → 4-20 mA → Q64AD → program
/// → Q64DA → 4-20 mA → inflow. With MV = 4·(2000 − PV) and the drain fully
/// open the level settles where 0.04·(MV/4000) = 0.02·√h, i.e.
/// 4·(1 − h) = √h: h = 0.779 m, PV ≈ 1559, MV ≈ 1766, 779 mm.
#[test]
fn tank_loop_through_the_rack() {
    let sc = Scenario::load(&fixture("tank_loop.toml")).unwrap_or_else(|e| panic!("{e}"));
    let outcome = sc
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
        .run(&mut |_| {});
    let report = outcome.report(false);
    assert_eq!((outcome.passed(), outcome.failed()), (9, 0), "{report}");
}

/// A scenario next to the fixture project: `extra` appended to the header.
fn scenario(extra: &str) -> Result<softplc_sim::scenario::Run, String> {
    let text = format!("project = \".\"\nscan_time = \"10ms\"\nduration = \"1s\"\n{extra}");
    Scenario::parse(&text, &fixture("inline.toml"))?.build()
}

fn error(extra: &str) -> String {
    match scenario(extra) {
        Ok(_) => panic!("expected an error for:\n{extra}"),
        Err(e) => e,
    }
}

/// Channel bindings are checked against the rack when the scenario is
/// built, and their syntax when it is parsed.
#[test]
fn channel_binding_errors() {
    let model =
        |port: &str, binding: &str| format!("[[model]]\ntype = \"fopdt\"\n{port} = {binding}\n");
    let e = error(&model("outputs.y", "'U9\\CH1'"));
    assert!(e.contains("no slot of the rack is unit U9"), "{e}");
    let e = error(&model("outputs.y", "'U0\\CH1'"));
    assert!(
        e.contains("slot 0 (input) holds no simulated module"),
        "{e}"
    );
    let e = error(&model("outputs.y", "'U2\\CH5'"));
    assert!(e.contains("has no channel CH5"), "{e}");
    // A D/A channel is an output of the module: a model reads it.
    let e = error(&model("outputs.y", "'U3\\CH1'"));
    assert!(
        e.contains("`U3\\CH1`: this module has no input channel 1"),
        "{e}"
    );
    let e = error(&model("outputs.y", "'U2\\CH0'"));
    assert!(
        e.contains("a module channel is written U<unit>\\CH<channel>"),
        "{e}"
    );
    let e = error(&model(
        "outputs.y",
        "{ device = 'U2\\CH1', raw = [0, 4000], eng = [0, 1] }",
    ));
    assert!(e.contains("carries mA or V, not digital values"), "{e}");
    let e = error(&model(
        "outputs.y",
        "{ device = 'U2\\CH1', signal = [4, 20] }",
    ));
    assert!(e.contains("give both `signal` and `eng` ranges"), "{e}");
    let e = error(&model(
        "outputs.y",
        "{ device = 'D0', signal = [4, 20], eng = [0, 1] }",
    ));
    assert!(e.contains("`signal` is for a module channel"), "{e}");
    let e = error("[[expect]]\ndevice = 'U2\\CH1'\nequals = 1\nat = \"0.5s\"\n");
    assert!(
        e.contains("is a module channel: it binds a model port"),
        "{e}"
    );
}

/// Unscaled, a channel carries the physical value: a model output of 12
/// (mA) is 2000 on 4-20 mA; the program's MV is then 4·(2000 − 2000) = 0,
/// which the Q64DA outputs as 4 mA, and a model reading CH1 sees 4.
#[test]
fn unscaled_channels() {
    let mut run = scenario(
        "[[model]]\nname = \"src\"\ntype = \"fopdt\"\nparams = { initial = 12.0 }\ninputs.u = 12\n\
         outputs.y = 'U2\\CH1'\n\
         [[model]]\nname = \"sink\"\ntype = \"fopdt\"\nparams = { tau = \"10ms\" }\n\
         inputs.u = 'U3\\CH1'\noutputs.y = 'D20:f32'\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..100 {
        run.step().unwrap_or_else(|e| panic!("{e}"));
    }
    let cpu = run.cpu();
    let names = softplc_core::names::Names::of(cpu);
    let get = |d: &str| names.parse(d).unwrap().read(cpu).unwrap();
    assert_eq!(get("U2\\G11"), Value::Int(2000));
    assert_eq!(get("D6"), Value::Int(0));
    match get("D20:f32") {
        Value::Float(v) => assert!((v - 4.0).abs() < 1e-6, "{v}"),
        v => panic!("{v:?}"),
    }
}
