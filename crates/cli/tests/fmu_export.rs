//! `softplc fmu` (contract §8): the exported FMU's library driven through
//! its FMI 3.0 C functions as a master drives it, compared with `softplc
//! run` at every communication point; its timing; a broken call sequence.

use std::collections::HashMap;
use std::ffi::{c_char, c_void, CStr, CString};
use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::Mutex;

use libloading::Library;

fn softplc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
        .args(args)
        .current_dir(workspace())
        .output()
        .expect("softplc runs")
}

fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

const OK: i32 = 0;
const ERROR: i32 = 3;

type Inst = *mut c_void;
type LogFn = unsafe extern "C" fn(*mut c_void, i32, *const c_char, *const c_char);
type Instantiate = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_char,
    bool,
    bool,
    bool,
    bool,
    *const u32,
    usize,
    *mut c_void,
    Option<LogFn>,
    *const c_void,
) -> Inst;
type EnterInit = unsafe extern "C" fn(Inst, bool, f64, f64, bool, f64) -> i32;
type Call = unsafe extern "C" fn(Inst) -> i32;
type Free = unsafe extern "C" fn(Inst);
type DoStep =
    unsafe extern "C" fn(Inst, f64, f64, bool, *mut bool, *mut bool, *mut bool, *mut f64) -> i32;
type Get<T> = unsafe extern "C" fn(Inst, *const u32, usize, *mut T, usize) -> i32;
type Set<T> = unsafe extern "C" fn(Inst, *const u32, usize, *const T, usize) -> i32;

/// What the FMU logged, one message per entry.
#[derive(Default)]
struct Log(Mutex<Vec<String>>);

unsafe extern "C" fn log_message(
    env: *mut c_void,
    _status: i32,
    _cat: *const c_char,
    msg: *const c_char,
) {
    // SAFETY: `env` is the boxed `Log` of the instance, alive until it is
    // freed; the FMU passes a NUL-terminated message.
    let (log, msg) = unsafe { (&*(env as *const Log), CStr::from_ptr(msg)) };
    log.0
        .lock()
        .unwrap()
        .push(msg.to_string_lossy().into_owned());
}

/// An exported FMU, unpacked, with one instance.
struct Fmu {
    lib: Library,
    inst: Inst,
    log: Box<Log>,
    /// name → (value reference, element type).
    vars: HashMap<String, (u32, String)>,
    _dir: tempfile::TempDir,
}

/// `softplc fmu ARGS -o DIR/NAME.fmu`, unpacked and instantiated.
fn export(name: &str, args: &[&str]) -> (Fmu, String) {
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join(format!("{name}.fmu"));
    let mut all = vec!["fmu"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", file.to_str().unwrap()]);
    let o = softplc(&all);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let dir = tempfile::tempdir().unwrap();
    zip::ZipArchive::new(std::fs::File::open(&file).unwrap())
        .unwrap()
        .extract(dir.path())
        .unwrap();
    let xml = std::fs::read_to_string(dir.path().join("modelDescription.xml")).unwrap();
    let so = dir.path().join(format!("binaries/x86_64-linux/{name}.so"));
    // SAFETY: the library is softplc's own FMU binary.
    let lib = unsafe { Library::new(&so) }.unwrap();
    let fmu = Fmu::instantiate(lib, &xml, dir);
    (fmu, xml)
}

/// An attribute's value on a line of our modelDescription.xml.
fn attr<'a>(line: &'a str, name: &str) -> Option<&'a str> {
    let start = line.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(&line[start..start + line[start..].find('"')?])
}

impl Fmu {
    fn instantiate(lib: Library, xml: &str, dir: tempfile::TempDir) -> Fmu {
        let token = attr(xml, "instantiationToken").unwrap().to_string();
        let mut vars = HashMap::new();
        for line in xml
            .lines()
            .filter(|l| l.contains("valueReference=") && l.contains("causality"))
        {
            let ty = line
                .trim_start()
                .trim_start_matches('<')
                .split(' ')
                .next()
                .unwrap();
            let vr: u32 = attr(line, "valueReference").unwrap().parse().unwrap();
            vars.insert(
                attr(line, "name").unwrap().to_string(),
                (vr, ty.to_string()),
            );
        }
        let log = Box::<Log>::default();
        let resources = format!("{}/resources/", dir.path().display());
        let (name, token, res) = (
            CString::new("plc").unwrap(),
            CString::new(token).unwrap(),
            CString::new(resources).unwrap(),
        );
        // SAFETY: the FMI 3.0 function type of fmi3InstantiateCoSimulation;
        // the strings and the log outlive the call and the instance.
        let inst = unsafe {
            let f = lib
                .get::<Instantiate>(b"fmi3InstantiateCoSimulation\0")
                .unwrap();
            f(
                name.as_ptr(),
                token.as_ptr(),
                res.as_ptr(),
                false,
                false,
                false,
                false,
                std::ptr::null(),
                0,
                &*log as *const Log as *mut c_void,
                Some(log_message),
                std::ptr::null(),
            )
        };
        assert!(!inst.is_null(), "{:?}", log.0.lock().unwrap());
        Fmu {
            lib,
            inst,
            log,
            vars,
            _dir: dir,
        }
    }

    fn vr(&self, name: &str) -> u32 {
        self.vars[name].0
    }

    fn call(&self, f: &str) -> i32 {
        // SAFETY: an FMI 3.0 function taking only the instance.
        unsafe { self.lib.get::<Call>(f.as_bytes()).unwrap()(self.inst) }
    }

    fn init(&self) -> i32 {
        // SAFETY: fmi3EnterInitializationMode's type.
        let s = unsafe {
            self.lib
                .get::<EnterInit>(b"fmi3EnterInitializationMode")
                .unwrap()(self.inst, false, 0.0, 0.0, false, 0.0)
        };
        assert_eq!(s, OK);
        self.call("fmi3ExitInitializationMode")
    }

    fn step(&self, t: f64, h: f64) -> i32 {
        let (mut a, mut b, mut c, mut last) = (true, true, true, 0.0);
        // SAFETY: fmi3DoStep's type; the out pointers are locals.
        unsafe {
            self.lib.get::<DoStep>(b"fmi3DoStep").unwrap()(
                self.inst, t, h, false, &mut a, &mut b, &mut c, &mut last,
            )
        }
    }

    fn get<T: Copy + Default>(&self, f: &str, vr: u32) -> (i32, T) {
        let mut v = T::default();
        // SAFETY: fmi3Get<Type>'s type with one value.
        let s =
            unsafe { self.lib.get::<Get<T>>(f.as_bytes()).unwrap()(self.inst, &vr, 1, &mut v, 1) };
        (s, v)
    }

    fn set<T: Copy>(&self, f: &str, vr: u32, v: T) -> i32 {
        // SAFETY: fmi3Set<Type>'s type with one value.
        unsafe { self.lib.get::<Set<T>>(f.as_bytes()).unwrap()(self.inst, &vr, 1, &v, 1) }
    }

    /// A variable's value as `run`'s trace writes it (bits 0/1).
    fn value(&self, name: &str) -> i64 {
        let (vr, ty) = &self.vars[name];
        let (s, v) = match ty.as_str() {
            "Boolean" => {
                let (s, b) = self.get::<bool>("fmi3GetBoolean", *vr);
                (s, b as i64)
            }
            "Int16" => {
                let (s, x) = self.get::<i16>("fmi3GetInt16", *vr);
                (s, x as i64)
            }
            "Int32" => {
                let (s, x) = self.get::<i32>("fmi3GetInt32", *vr);
                (s, x as i64)
            }
            t => panic!("type {t}"),
        };
        assert_eq!(s, OK, "{name}: {:?}", self.log.0.lock().unwrap());
        v
    }

    fn write(&self, name: &str, v: i64) {
        let (vr, ty) = &self.vars[name];
        let s = match ty.as_str() {
            "Boolean" => self.set::<u8>("fmi3SetBoolean", *vr, (v != 0) as u8),
            "Int16" => self.set::<i16>("fmi3SetInt16", *vr, v as i16),
            t => panic!("type {t}"),
        };
        assert_eq!(s, OK, "{name}: {:?}", self.log.0.lock().unwrap());
    }

    fn logged(&self) -> Vec<String> {
        self.log.0.lock().unwrap().clone()
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: fmi3FreeInstance's type; the instance is not used again.
        unsafe { self.lib.get::<Free>(b"fmi3FreeInstance").unwrap()(self.inst) }
    }
}

/// `softplc run PROGRAM --scans N --at … --trace OUTPUTS`: the outputs after
/// each scan, row `k - 1` after scan `k`.
fn run_trace(
    program: &str,
    scans: u64,
    at: &[(u64, &str, i64)],
    outputs: &[&str],
) -> Vec<Vec<i64>> {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("trace.csv");
    let scans = scans.to_string();
    let traced = outputs.join(",");
    let mut args = vec![
        "run",
        program,
        "--scans",
        &scans,
        "--trace",
        &traced,
        "--trace-file",
    ];
    let csv_arg = csv.to_str().unwrap().to_string();
    args.push(&csv_arg);
    let writes: Vec<String> = at.iter().map(|(n, d, v)| format!("{n}:{d}={v}")).collect();
    for w in &writes {
        args.push("--at");
        args.push(w);
    }
    let o = softplc(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_to_string(csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').skip(2).map(|v| v.parse().unwrap()).collect())
        .collect()
}

/// Steps the FMU `steps` times by `h` = the scan time, writing the inputs
/// `at` the communication point of `run`'s scan before which `--at` writes
/// them, and compares the outputs with `run`'s after every step.
fn compare_with_run(
    fmu: &Fmu,
    program: &str,
    steps: u64,
    at: &[(u64, &str, i64)],
    outputs: &[&str],
) -> Vec<Vec<i64>> {
    let trace = run_trace(program, steps, at, outputs);
    assert_eq!(trace.len() as u64, steps);
    let h = 0.01;
    assert_eq!(fmu.init(), OK);
    for k in 0..steps {
        // `--at N:` writes before scan N, the scan of the step from (N-1)·h.
        for (_, dev, v) in at.iter().filter(|(n, _, _)| *n == k + 1) {
            fmu.write(dev, *v);
        }
        assert_eq!(fmu.step(k as f64 * h, h), OK, "{:?}", fmu.logged());
        let got: Vec<i64> = outputs.iter().map(|o| fmu.value(o)).collect();
        assert_eq!(got, trace[k as usize], "after scan {}: {outputs:?}", k + 1);
    }
    assert_eq!(fmu.call("fmi3Terminate"), OK);
    trace
}

#[test]
fn blink_as_an_fmu_gives_what_run_gives_at_every_communication_point() {
    let outputs = ["Y0", "CN0", "TN0", "T0"];
    let (fmu, xml) = export(
        "blink",
        &[
            "examples/blink.il",
            "--input",
            "X0",
            "--input",
            "X1",
            "--output",
            "Y0",
            "--output",
            "CN0",
            "--output",
            "TN0",
            "--output",
            "T0",
        ],
    );
    assert!(xml.contains(r#"<Boolean name="X0" valueReference="2" causality="input" variability="discrete" start="false"/>"#), "{xml}");
    assert!(
        xml.contains(r#"<Int16 name="CN0" valueReference="5" causality="output""#),
        "{xml}"
    );
    // Blinking from the start; X0 off at 2 s, X1 clears the count at 2.5 s,
    // X0 on again at 2.7 s.
    let at = [
        (1, "X0", 1),
        (201, "X0", 0),
        (251, "X1", 1),
        (261, "X1", 0),
        (271, "X0", 1),
    ];
    compare_with_run(&fmu, "examples/blink.il", 400, &at, &outputs);
    // Y0 rose at about 0.5 s and 1.5 s; X1 cleared the count at 2.5 s; after
    // X0 at 2.7 s it rose again 0.5 s later, and not again before 4 s.
    assert_eq!(fmu.value("CN0"), 1);
}

#[test]
fn heated_tank_as_an_fmu_gives_what_run_gives_at_every_communication_point() {
    let outputs = ["Y0", "Y1", "D611", "D820"];
    let (fmu, xml) = export(
        "tank",
        &[
            "examples/sim/heated_tank.il",
            "--input",
            "X0",
            "--input",
            "D800",
            "--output",
            "Y0",
            "--output",
            "Y1",
            "--output",
            "D611",
            "--output",
            "D820",
        ],
    );
    assert!(xml.contains(r#"<Int16 name="D800" valueReference="3" causality="input" variability="discrete" start="0"/>"#), "{xml}");
    // The "A/D" word rises by 50 counts (5 °C) every half second from 20 °C;
    // PID control starts at 1 s.
    let mut at: Vec<(u64, &str, i64)> = (0..12)
        .map(|m| (50 * m + 1, "D800", 200 + 50 * m as i64))
        .collect();
    at.push((101, "X0", 1));
    at.sort_by_key(|w| w.0);
    compare_with_run(&fmu, "examples/sim/heated_tank.il", 600, &at, &outputs);
    // PV follows the "A/D" word: 20 °C + 11 × 5 °C, under the 80 °C alarm.
    assert_eq!(fmu.value("D611"), 750);
    assert_eq!(fmu.value("Y1"), 0);
}

/// A program that counts its scans in D0.
fn counter() -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("count.il");
    std::fs::write(&p, "LD SM400\nINC D0\nEND\n").unwrap();
    let s = p.to_str().unwrap().to_string();
    (dir, s)
}

#[test]
fn a_step_runs_the_scans_that_end_by_its_end_within_a_microsecond() {
    let (_d, program) = counter();
    let (fmu, _) = export(
        "count",
        &[&program, "--output", "D0", "--scan-time", "10ms"],
    );
    assert_eq!(fmu.init(), OK);
    let d0 = || fmu.value("D0");
    assert_eq!(d0(), 0);
    // Steps of 25 ms: scans end at 10, 20 | 30, 40, 50 | 60, 70 | …
    let mut t = 0.0;
    for want in [2, 5, 7, 10] {
        assert_eq!(fmu.step(t, 0.025), OK);
        t += 0.025;
        assert_eq!(d0(), want);
    }
    // 0.1 s + 0.0299999999 s: the scan ending at 0.13 s is within 1 µs.
    assert_eq!(fmu.step(0.1, 0.0299999999), OK);
    assert_eq!(d0(), 13);
    // 0.13 s + 9.998 ms ends 2 µs before the next scan: none runs.
    assert_eq!(fmu.step(0.13, 0.009998), OK);
    assert_eq!(d0(), 13);
    // A zero step runs nothing.
    assert_eq!(fmu.step(0.139998, 0.0), OK);
    assert_eq!(d0(), 13);
    assert_eq!(fmu.step(0.139998, 0.000002), OK);
    assert_eq!(d0(), 14);
}

#[test]
fn the_scan_time_parameter_is_set_before_initialization_only() {
    let (_d, program) = counter();
    let (fmu, xml) = export(
        "count",
        &[&program, "--output", "D0:u16", "--scan-time", "10ms"],
    );
    assert!(xml.contains(r#"<Float64 name="scan_time" valueReference="1" causality="parameter" variability="fixed" start="0.01""#), "{xml}");
    assert!(
        xml.contains(r#"<UInt16 name="D0:u16" valueReference="2" causality="output""#),
        "{xml}"
    );
    assert_eq!(fmu.get::<f64>("fmi3GetFloat64", 1), (OK, 0.01));
    assert_eq!(fmu.set::<f64>("fmi3SetFloat64", 1, 0.001), OK);
    assert_eq!(fmu.set::<f64>("fmi3SetFloat64", 1, 0.0), ERROR);
    assert_eq!(fmu.init(), OK);
    assert_eq!(fmu.set::<f64>("fmi3SetFloat64", 1, 0.002), ERROR);
    assert!(
        fmu.logged()
            .last()
            .unwrap()
            .contains("not allowed in Step mode"),
        "{:?}",
        fmu.logged()
    );
    assert_eq!(fmu.step(0.0, 0.1), OK);
    // 1 ms scans: 100 in 0.1 s.
    assert_eq!(fmu.get::<u16>("fmi3GetUInt16", 2), (OK, 100));
    assert_eq!(fmu.get::<f64>("fmi3GetFloat64", 0), (OK, 0.1));
    assert_eq!(fmu.set::<f64>("fmi3SetFloat64", 0, 0.5), ERROR);
    // Reset: powered on again with the exported scan time.
    assert_eq!(fmu.call("fmi3Reset"), OK);
    assert_eq!(fmu.get::<u16>("fmi3GetUInt16", 2), (OK, 0));
    assert_eq!(fmu.init(), OK);
    assert_eq!(fmu.step(0.0, 0.1), OK);
    assert_eq!(fmu.get::<u16>("fmi3GetUInt16", 2), (OK, 10));
}

#[test]
fn a_wrong_call_sequence_is_refused_with_a_logged_reason() {
    let (_d, program) = counter();
    let (fmu, _) = export("count", &[&program, "--input", "D10", "--output", "D0"]);
    let last = || fmu.logged().last().cloned().unwrap_or_default();
    // DoStep before initialization.
    assert_eq!(fmu.step(0.0, 0.01), ERROR);
    assert!(
        last().contains("fmi3DoStep is not allowed in Instantiated mode"),
        "{}",
        last()
    );
    // Unknown value reference, wrong type, an output set.
    assert_eq!(fmu.get::<i16>("fmi3GetInt16", 99).0, ERROR);
    assert!(
        last().contains("no variable has value reference 99"),
        "{}",
        last()
    );
    assert_eq!(fmu.get::<i32>("fmi3GetInt32", fmu.vr("D0")).0, ERROR);
    assert!(
        last().contains("`D0` (value reference 3) is Int16, not Int32"),
        "{}",
        last()
    );
    assert_eq!(fmu.set::<i16>("fmi3SetInt16", fmu.vr("D0"), 5), ERROR);
    assert!(
        last().contains("`D0` (value reference 3) is an output and cannot be set"),
        "{}",
        last()
    );
    assert_eq!(fmu.get::<i8>("fmi3GetInt8", 2).0, ERROR);
    assert!(last().contains("no Int8 variable"), "{}", last());
    // No event mode.
    assert_eq!(fmu.call("fmi3EnterEventMode"), ERROR);
    assert!(last().contains("no event mode"), "{}", last());
    // Exit before enter.
    assert_eq!(fmu.call("fmi3ExitInitializationMode"), ERROR);
    // After all that, it still runs normally.
    assert_eq!(fmu.set::<i16>("fmi3SetInt16", fmu.vr("D10"), -7), OK);
    assert_eq!(fmu.get::<i16>("fmi3GetInt16", fmu.vr("D10")), (OK, -7));
    assert_eq!(fmu.init(), OK);
    assert_eq!(fmu.step(0.0, 0.03), OK);
    assert_eq!(fmu.get::<i16>("fmi3GetInt16", fmu.vr("D0")), (OK, 3));
    assert_eq!(fmu.call("fmi3Terminate"), OK);
    assert_eq!(fmu.step(0.03, 0.01), ERROR);
    assert!(
        last().contains("not allowed in Terminated mode"),
        "{}",
        last()
    );
}

#[test]
fn a_changed_resource_or_a_null_resource_path_is_refused_at_instantiation() {
    let (_d, program) = counter();
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("c.fmu");
    let o = softplc(&[
        "fmu",
        &program,
        "--output",
        "D0",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let dir = tempfile::tempdir().unwrap();
    zip::ZipArchive::new(std::fs::File::open(&file).unwrap())
        .unwrap()
        .extract(dir.path())
        .unwrap();
    std::fs::write(
        dir.path().join("resources/count.il"),
        "LD SM400\nINC D1\nEND\n",
    )
    .unwrap();
    let xml = std::fs::read_to_string(dir.path().join("modelDescription.xml")).unwrap();
    let token = CString::new(attr(&xml, "instantiationToken").unwrap()).unwrap();
    // SAFETY: softplc's own FMU binary.
    let lib = unsafe { Library::new(dir.path().join("binaries/x86_64-linux/c.so")) }.unwrap();
    let log = Box::<Log>::default();
    let res = CString::new(format!("{}/resources/", dir.path().display())).unwrap();
    let instantiate = |res: *const c_char| {
        // SAFETY: fmi3InstantiateCoSimulation's type; the strings and log outlive the call.
        unsafe {
            lib.get::<Instantiate>(b"fmi3InstantiateCoSimulation")
                .unwrap()(
                c"x".as_ptr(),
                token.as_ptr(),
                res,
                false,
                false,
                false,
                false,
                std::ptr::null(),
                0,
                &*log as *const Log as *mut c_void,
                Some(log_message),
                std::ptr::null(),
            )
        }
    };
    assert!(instantiate(res.as_ptr()).is_null());
    assert!(
        log.0.lock().unwrap()[0].contains("come from different exports"),
        "{:?}",
        log.0.lock().unwrap()
    );
    assert!(instantiate(std::ptr::null()).is_null());
    assert!(
        log.0.lock().unwrap()[1].contains("no resource path given"),
        "{:?}",
        log.0.lock().unwrap()
    );
}

#[test]
fn export_errors_name_the_device_or_say_how_to_get_the_library() {
    let (_d, program) = counter();
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("c.fmu");
    let f = file.to_str().unwrap();
    let err = |args: &[&str]| {
        let o = softplc(args);
        assert!(!o.status.success());
        assert!(!file.exists());
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let e = err(&["fmu", &program, "--output", "Q0", "-o", f]);
    assert!(e.contains("Q0"), "{e}");
    let e = err(&["fmu", &program, "--output", "D0:str", "-o", f]);
    assert!(
        e.contains("`D0:str`: a string has no FMU variable type"),
        "{e}"
    );
    let e = err(&["fmu", &program, "--input", "D0", "--output", "D0", "-o", f]);
    assert!(e.contains("`D0`: named twice"), "{e}");
    let e = err(&[
        "fmu",
        &program,
        "--output",
        "D0",
        "-o",
        f,
        "--fmu-library",
        "/nonexistent/lib.so",
    ]);
    assert!(
        e.contains("--fmu-library /nonexistent/lib.so: no such file"),
        "{e}"
    );
    let o = Command::new(env!("CARGO_BIN_EXE_softplc"))
        .args(["fmu", &program, "--output", "D0", "-o", f])
        .env("SOFTPLC_FMU_LIBRARY", "/nonexistent/x.so")
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&o.stderr)
        .contains("SOFTPLC_FMU_LIBRARY /nonexistent/x.so: no such file"));
}

/// A copy of an example directory: `run` keeps a project's state directory
/// in it, the FMU keeps none.
fn copy_dir(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.file_name() == "state" {
            continue;
        }
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

#[test]
fn a_project_as_an_fmu_gives_what_run_gives_at_every_communication_point() {
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("project");
    copy_dir(&workspace().join("examples/project"), &project);
    let p = project.to_str().unwrap();
    let outputs = ["Y0", "Y1", "Y2", "D0", "D11"];
    let (fmu, _) = export(
        "filler",
        &[
            p, "--input", "X0", "--input", "X2", "--input", "X3", "--output", "Y0", "--output",
            "Y1", "--output", "Y2", "--output", "D0", "--output", "D11",
        ],
    );
    // Start, a bottle at the filler at 0.5 s, then flow-meter pulses every
    // 20 ms (the fixed-scan program counts them every 50 ms).
    let mut at: Vec<(u64, &str, i64)> = vec![(1, "X0", 1), (3, "X0", 0), (50, "X2", 1)];
    for k in 0..100 {
        at.push((60 + 2 * k, "X3", (k % 2 == 0) as i64));
    }
    let trace = compare_with_run(&fmu, p, 400, &at, &outputs);
    // The conveyor ran (Y0) and the valve opened (Y1) at some point.
    assert!(
        trace.iter().any(|r| r[0] == 1) && trace.iter().any(|r| r[1] == 1),
        "{trace:?}"
    );
}

/// `softplc run SYSTEM --scans N --at … --show …`: the devices after N scans
/// of CPU 1.
fn run_show(program: &str, scans: u64, at: &[(u64, &str, i64)], shows: &[&str]) -> Vec<i64> {
    let scans = scans.to_string();
    let mut args = vec!["run", program, "--scans", &scans, "--json"];
    let writes: Vec<String> = at.iter().map(|(n, d, v)| format!("{n}:{d}={v}")).collect();
    for w in &writes {
        args.push("--at");
        args.push(w);
    }
    for s in shows {
        args.push("--show");
        args.push(s);
    }
    let o = softplc(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    shows
        .iter()
        .map(|s| match &v["devices"][*s] {
            serde_json::Value::Bool(b) => *b as i64,
            n => n.as_i64().unwrap(),
        })
        .collect()
}

#[test]
fn a_multi_cpu_system_as_an_fmu_gives_what_run_gives() {
    let dir = tempfile::tempdir().unwrap();
    let system = dir.path().join("line");
    copy_dir(&workspace().join("examples/multi_cpu"), &system);
    let s = system.to_str().unwrap();
    let outputs = ["CPU1/Y0", "CPU1/D1002", "CPU2/D820", "CPU2/Y1"];
    let (fmu, xml) = export(
        "line",
        &[
            s,
            "--input",
            "CPU1/X0",
            "--input",
            "CPU2/D800",
            "--output",
            "CPU1/Y0",
            "--output",
            "CPU1/D1002",
            "--output",
            "CPU2/D820",
            "--output",
            "CPU2/Y1",
        ],
    );
    assert!(
        xml.contains(r#"<Boolean name="CPU1/X0" valueReference="2" causality="input""#),
        "{xml}"
    );
    // Start at 0.1 s; the tank's temperature word at 30 °C, then 85 °C.
    let at = [
        (11, "CPU1/X0", 1),
        (21, "CPU1/X0", 0),
        (1, "CPU2/D800", 300),
        (151, "CPU2/D800", 850),
    ];
    assert_eq!(fmu.init(), OK);
    let mut checked = 0;
    for k in 0..300u64 {
        for (_, dev, v) in at.iter().filter(|(n, _, _)| *n == k + 1) {
            fmu.write(dev, *v);
        }
        assert_eq!(fmu.step(k as f64 * 0.01, 0.01), OK, "{:?}", fmu.logged());
        if [1, 15, 100, 160, 300].contains(&(k + 1)) {
            let got: Vec<i64> = outputs.iter().map(|o| fmu.value(o)).collect();
            let written: Vec<_> = at.iter().copied().filter(|w| w.0 <= k + 1).collect();
            assert_eq!(
                got,
                run_show(s, k + 1, &written, &outputs),
                "after {} scans of CPU 1",
                k + 1
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 5);
    // Filling (step 1, valve Y0 open) and the over-temperature alarm at 85 °C.
    assert_eq!(fmu.value("CPU1/D1002"), 1);
    assert_eq!(fmu.value("CPU1/Y0"), 1);
    assert_eq!(fmu.value("CPU2/Y1"), 1);
}

type GetState = unsafe extern "C" fn(Inst, *mut *mut c_void) -> i32;
type SetState = unsafe extern "C" fn(Inst, *mut c_void) -> i32;
type StateSize = unsafe extern "C" fn(Inst, *mut c_void, *mut usize) -> i32;
type Serialize = unsafe extern "C" fn(Inst, *mut c_void, *mut u8, usize) -> i32;
type Deserialize = unsafe extern "C" fn(Inst, *const u8, usize, *mut *mut c_void) -> i32;

impl Fmu {
    fn get_state(&self, state: &mut *mut c_void) -> i32 {
        // SAFETY: fmi3GetFMUState's type; `state` is a local handle.
        unsafe { self.lib.get::<GetState>(b"fmi3GetFMUState").unwrap()(self.inst, state) }
    }

    fn set_state(&self, state: *mut c_void) -> i32 {
        // SAFETY: fmi3SetFMUState's type with a handle of this FMU.
        unsafe { self.lib.get::<SetState>(b"fmi3SetFMUState").unwrap()(self.inst, state) }
    }

    fn free_state(&self, state: &mut *mut c_void) -> i32 {
        // SAFETY: fmi3FreeFMUState's type; the handle is not used again.
        unsafe { self.lib.get::<GetState>(b"fmi3FreeFMUState").unwrap()(self.inst, state) }
    }

    fn serialize(&self, state: *mut c_void) -> Vec<u8> {
        let mut n = 0usize;
        // SAFETY: the serialization functions' types; the buffer has `n` bytes.
        unsafe {
            let size = self
                .lib
                .get::<StateSize>(b"fmi3SerializedFMUStateSize")
                .unwrap();
            assert_eq!(size(self.inst, state, &mut n), OK);
            let mut b = vec![0u8; n];
            let f = self.lib.get::<Serialize>(b"fmi3SerializeFMUState").unwrap();
            assert_eq!(f(self.inst, state, b.as_mut_ptr(), n), OK);
            b
        }
    }

    fn deserialize(&self, bytes: &[u8], state: &mut *mut c_void) -> i32 {
        // SAFETY: fmi3DeserializeFMUState's type; the buffer has its length.
        unsafe {
            self.lib
                .get::<Deserialize>(b"fmi3DeserializeFMUState")
                .unwrap()(self.inst, bytes.as_ptr(), bytes.len(), state)
        }
    }
}

#[test]
fn an_fmu_state_goes_back_in_time_also_serialized_and_a_damaged_one_changes_nothing() {
    let (_d, program) = counter();
    let (fmu, xml) = export("count", &[&program, "--input", "D10", "--output", "D0"]);
    assert!(
        xml.contains(r#"canGetAndSetFMUState="true" canSerializeFMUState="true""#),
        "{xml}"
    );
    let d0 = || fmu.value("D0");
    let mut s1: *mut c_void = std::ptr::null_mut();
    // Not before initialization.
    assert_eq!(fmu.get_state(&mut s1), ERROR);
    assert_eq!(fmu.init(), OK);
    assert_eq!(fmu.step(0.0, 0.1), OK);
    // An input set but not yet written is part of the state.
    fmu.write("D10", 42);
    assert_eq!(fmu.get_state(&mut s1), OK);
    assert!(!s1.is_null());
    fmu.write("D10", 7);
    assert_eq!(fmu.step(0.1, 0.1), OK);
    assert_eq!(d0(), 20);
    assert_eq!(fmu.set_state(s1), OK);
    assert_eq!((d0(), fmu.value("D10")), (10, 42));
    assert_eq!(fmu.get::<f64>("fmi3GetFloat64", 0), (OK, 0.1));
    // The same steps again give the same values.
    assert_eq!(fmu.step(0.1, 0.05), OK);
    assert_eq!(d0(), 15);
    // Serialized and back, into a new state.
    let bytes = fmu.serialize(s1);
    let mut s2: *mut c_void = std::ptr::null_mut();
    assert_eq!(fmu.deserialize(&bytes, &mut s2), OK);
    assert_eq!(fmu.set_state(s2), OK);
    assert_eq!(d0(), 10);
    assert_eq!(fmu.step(0.1, 0.1), OK);
    assert_eq!(d0(), 20);
    // A damaged state is refused and nothing changes.
    let mut bad = bytes.clone();
    let last = bad.len() - 1;
    bad[last] ^= 0x55;
    let mut s3: *mut c_void = std::ptr::null_mut();
    assert_eq!(fmu.deserialize(&bad, &mut s3), OK);
    assert_eq!(fmu.set_state(s3), ERROR);
    assert!(
        fmu.logged().last().unwrap().contains("damaged"),
        "{:?}",
        fmu.logged()
    );
    assert_eq!(d0(), 20);
    assert_eq!(fmu.get::<f64>("fmi3GetFloat64", 0), (OK, 0.2));
    assert_eq!(fmu.step(0.2, 0.01), OK);
    assert_eq!(d0(), 21);
    // Freed: the handles become NULL.
    for s in [&mut s1, &mut s2, &mut s3] {
        assert_eq!(fmu.free_state(s), OK);
        assert!(s.is_null());
    }
}
