//! The process and redundant CPU models: Q12PRHCPU and Q25PRHCPU are process
//! CPUs that also have the PID control instructions; the QnPHCPUs reject
//! those (PID Control Instructions manual §1: "the process CPU does not
//! support the PID control instructions"), which the QnHCPUs keep.

mod common;
use common::project::load_files;

fn project(model: &str) -> String {
    format!("[cpu]\nmodel = \"{model}\"\n[[program]]\nfile = \"main.il\"\n")
}

const PID: &str = "LD SM402\nPIDINIT D500\nLD SM400\nPIDCONT D600\nEND\n";
const SPID: &str = "LD SM400\nS.PID R40 R140 R240 R1000 SD1506\nEND\n";

#[test]
fn the_redundant_models_load_with_their_memory_and_model_code() {
    for (model, steps, code) in [("Q12PRHCPU", 124, 0x004B), ("Q25PRHCPU", 252, 0x004C)] {
        let p = softplc_core::profile::find(model).unwrap();
        assert_eq!(p.family, "MELSEC-QnPH");
        assert_eq!(p.capacity.program_steps, steps * 1024);
        assert_eq!(p.capacity.programs, 124);
        assert_eq!(p.doors.mc, Some(code));
        assert!(softplc_core::instructions::is_process_model(model));
        let p = load_files(&project(model), &[("main.il", SPID)]).unwrap();
        assert_eq!(p.config.profile.model, model);
    }
    // Any case, as every model.
    assert_eq!(
        softplc_core::profile::find("q12prhcpu").unwrap().model,
        "Q12PRHCPU"
    );
}

#[test]
fn the_pid_control_instructions_are_refused_on_the_qnphcpus() {
    let why = "a PID control instruction, which the process CPUs (Q02PHCPU, Q06PHCPU, \
               Q12PHCPU, Q25PHCPU) do not have: on these models a PID loop is written with the \
               process-control instructions (S.PID or S.2PID, between S.IN and S.OUT1); the PID \
               control instructions run on the other MELSEC-Q models, the Universal models and \
               the redundant Q12PRHCPU/Q25PRHCPU";
    for model in ["Q02PHCPU", "Q06PHCPU", "Q12PHCPU", "Q25PHCPU"] {
        assert_eq!(
            load_files(&project(model), &[("main.il", PID)]).unwrap_err(),
            [
                format!("main.il:2:1: unsupported instruction `PIDINIT`: {why}"),
                format!("main.il:4:1: unsupported instruction `PIDCONT`: {why}"),
            ],
            "{model}"
        );
        // Every form of both families.
        for m in [
            "S.PIDINIT D0",
            "SP.PIDINIT D0",
            "S.PIDCONT D0",
            "S.PIDSTOP K1",
            "SP.PIDRUN K1",
            "S.PIDPRMW K1 D0",
            "PIDINITP D0",
            "PIDSTOP K1",
            "PIDRUNP K1",
            "PIDPRMW K1 D0",
            "PID57 K1 D0 K0",
        ] {
            let e = load_files(
                &project(model),
                &[("main.il", &format!("LD X0\n{m}\nEND\n"))],
            )
            .unwrap_err();
            assert_eq!(e.len(), 1, "{model} {m}: {e:?}");
            assert!(e[0].ends_with(why), "{model} {m}: {e:?}");
        }
        // The process-control instructions are the way.
        load_files(&project(model), &[("main.il", SPID)]).unwrap();
    }
}

#[test]
fn the_redundant_and_qnh_models_run_the_pid_control_instructions() {
    for model in ["Q12PRHCPU", "Q25PRHCPU", "Q06HCPU", "Q06UDEHCPU"] {
        let p = load_files(&project(model), &[("main.il", PID)])
            .unwrap_or_else(|e| panic!("{model}: {e:?}"));
        assert_eq!(p.config.profile.model, model);
    }
    // Both families together on a redundant CPU.
    load_files(
        &project("Q25PRHCPU"),
        &[("main.il", "LD SM402\nPIDINIT D500\nLD SM400\nPIDCONT D600\nS.PID R40 R140 R240 R1000 SD1506\nEND\n")],
    )
    .unwrap();
}
