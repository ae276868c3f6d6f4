//! The C interface of an FMI 3.0 co-simulation FMU (FMI 3.0 §2.2, the
//! function types of `fmi3FunctionTypes.h`): loading its shared library and
//! calling one instance. This is the only file of softplc-sim with `unsafe`.

use std::ffi::{c_char, c_void, CStr, CString};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

use libloading::os::unix::{Library, RTLD_GLOBAL, RTLD_LOCAL, RTLD_NOW};

use super::description::Description;

type Fmi3Instance = *mut c_void;
/// `fmi3Status` (FMI 3.0 §2.2.3): OK 0, Warning 1, Discard 2, Error 3, Fatal 4.
type Status = i32;
const OK: Status = 0;
const WARNING: Status = 1;
const FATAL: Status = 4;

type LogMessage = unsafe extern "C" fn(*mut c_void, Status, *const c_char, *const c_char);
type IntermediateUpdate =
    unsafe extern "C" fn(*mut c_void, f64, bool, bool, bool, bool, *mut bool, *mut f64);
type InstantiateCoSimulation = unsafe extern "C" fn(
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
    Option<LogMessage>,
    Option<IntermediateUpdate>,
) -> Fmi3Instance;
type FreeInstance = unsafe extern "C" fn(Fmi3Instance);
type EnterInitializationMode =
    unsafe extern "C" fn(Fmi3Instance, bool, f64, f64, bool, f64) -> Status;
type InstanceCall = unsafe extern "C" fn(Fmi3Instance) -> Status;
type Get<T> = unsafe extern "C" fn(Fmi3Instance, *const u32, usize, *mut T, usize) -> Status;
type Set<T> = unsafe extern "C" fn(Fmi3Instance, *const u32, usize, *const T, usize) -> Status;
type DoStep = unsafe extern "C" fn(
    Fmi3Instance,
    f64,
    f64,
    bool,
    *mut bool,
    *mut bool,
    *mut bool,
    *mut f64,
) -> Status;

/// The functions of the FMU's library that softplc calls.
#[derive(Clone, Copy)]
pub struct Api {
    instantiate: InstantiateCoSimulation,
    free_instance: FreeInstance,
    enter_initialization_mode: EnterInitializationMode,
    exit_initialization_mode: InstanceCall,
    terminate: InstanceCall,
    do_step: DoStep,
    get_f64: Get<f64>,
    set_f64: Set<f64>,
    get_f32: Get<f32>,
    set_f32: Set<f32>,
    get_i32: Get<i32>,
    set_i32: Set<i32>,
    get_bool: Get<bool>,
    set_bool: Set<bool>,
}

/// Messages the FMU logged with status Warning or worse (the last ones, up
/// to [`MAX_LOG_BYTES`]): the reason given with an error.
#[derive(Default)]
struct Log {
    text: Mutex<String>,
}

const MAX_LOG_BYTES: usize = 2000;

/// `fmi3LogMessageCallback`. Never unwinds (a panic must not cross into C).
unsafe extern "C" fn log_message(
    env: *mut c_void,
    status: Status,
    category: *const c_char,
    message: *const c_char,
) {
    if env.is_null() || message.is_null() || status < WARNING {
        return;
    }
    // SAFETY: `env` is the `Log` this instance was created with (boxed, so
    // its address is stable, and freed only after fmi3FreeInstance), and the
    // FMU passes NUL-terminated strings valid for the call (FMI 3.0 §2.3.1).
    let (log, message) = unsafe { (&*(env as *const Log), CStr::from_ptr(message)) };
    let category = if category.is_null() {
        String::new()
    } else {
        // SAFETY: as `message`.
        unsafe { CStr::from_ptr(category) }
            .to_string_lossy()
            .into_owned()
    };
    let mut text = log.text.lock().unwrap_or_else(|e| e.into_inner());
    if !text.is_empty() {
        text.push_str("; ");
    }
    if !category.is_empty() {
        text.push_str(&category);
        text.push_str(": ");
    }
    // One line per message, so that reports stay one line per result.
    for (i, part) in message.to_string_lossy().lines().enumerate() {
        if i > 0 {
            text.push(' ');
        }
        text.push_str(part.trim());
    }
    if text.len() > MAX_LOG_BYTES {
        let cut = text.len() - MAX_LOG_BYTES;
        let cut = (cut..text.len())
            .find(|&i| text.is_char_boundary(i))
            .unwrap_or(0);
        text.replace_range(..cut, "…");
    }
}

/// A loader error with the loader's own reason (libloading keeps it as the
/// error's source).
fn dl_error(e: &libloading::Error) -> String {
    match std::error::Error::source(e) {
        Some(why) => why.to_string(),
        None => e.to_string(),
    }
}

/// The platform folder of the FMU's binaries (FMI 3.0 §2.5.1.4).
fn platform_folder() -> Result<&'static str, String> {
    match (std::env::consts::ARCH, std::env::consts::OS) {
        ("x86_64", "linux") => Ok("x86_64-linux"),
        ("aarch64", "linux") => Ok("aarch64-linux"),
        ("x86", "linux") => Ok("x86-linux"),
        (a, o) => Err(format!("no FMU binaries folder is defined for {a}-{o}")),
    }
}

/// The libpython of the `python3` on PATH, loaded with its symbols global so
/// that an FMU built with pythonfmu/pythonfmu3 (whose library expects its
/// host to provide Python, with no dependency on libpython of its own) finds
/// them. Loaded once per process and never unloaded.
fn preload_python() -> Result<(), String> {
    static PYTHON: OnceLock<Result<Library, String>> = OnceLock::new();
    let r = PYTHON.get_or_init(|| {
        let script = "import os,sysconfig;print(os.path.join(sysconfig.get_config_var('LIBDIR') or '', sysconfig.get_config_var('LDLIBRARY') or ''))";
        let out = std::process::Command::new("python3")
            .args(["-c", script])
            .output()
            .map_err(|e| format!("cannot run python3 to find libpython: {e}"))?;
        let path = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
        if !out.status.success() || !path.is_file() || path.extension().is_some_and(|e| e == "a")
        {
            return Err(format!(
                "python3 on PATH has no shared libpython (found `{}`)",
                path.display()
            ));
        }
        // SAFETY: loading libpython runs no Python code; its initialisers
        // only set up static data.
        unsafe { Library::open(Some(&path), RTLD_NOW | RTLD_GLOBAL) }
            .map_err(|e| format!("cannot load {}: {}", path.display(), dl_error(&e)))
    });
    r.as_ref().map(|_| ()).map_err(|e| e.clone())
}

/// Opens the FMU's library. Libraries are never unloaded (kept for the life
/// of the process): an FMU embedding a runtime (Python, a JVM) may not
/// survive being unloaded and loaded again.
fn open_library(path: &Path) -> Result<&'static Library, String> {
    let open = || {
        // SAFETY: an FMU's library may run initialisers on load; loading it
        // is what importing an FMU means (FMI 3.0 §2.5.1.4), and the user
        // chose the FMU in the scenario.
        unsafe { Library::open(Some(path), RTLD_NOW | RTLD_LOCAL) }
    };
    let fail = |e: String| format!("cannot load {}: {e}", path.display());
    let lib = match open().map_err(|e| dl_error(&e)) {
        Ok(l) => l,
        Err(e) if e.contains("undefined symbol: Py") || e.contains("undefined symbol: _Py") => {
            preload_python().map_err(|p| fail(format!("{e} (a pythonfmu FMU: {p})")))?;
            open().map_err(|e| fail(dl_error(&e)))?
        }
        Err(e) => return Err(fail(e)),
    };
    Ok(Box::leak(Box::new(lib)))
}

/// Looks up the FMI 3.0 functions in `lib`.
fn api(lib: &'static Library, path: &Path) -> Result<Api, String> {
    macro_rules! sym {
        ($name:literal) => {{
            // SAFETY: the symbol has the type of the FMI 3.0 function of
            // that name (fmi3FunctionTypes.h), and the library is never
            // unloaded, so the pointer stays valid.
            let s = unsafe { lib.get(concat!($name, "\0").as_bytes()) }
                .map_err(|e| format!("{}: no function {} ({e})", path.display(), $name))?;
            *s
        }};
    }
    Ok(Api {
        instantiate: sym!("fmi3InstantiateCoSimulation"),
        free_instance: sym!("fmi3FreeInstance"),
        enter_initialization_mode: sym!("fmi3EnterInitializationMode"),
        exit_initialization_mode: sym!("fmi3ExitInitializationMode"),
        terminate: sym!("fmi3Terminate"),
        do_step: sym!("fmi3DoStep"),
        get_f64: sym!("fmi3GetFloat64"),
        set_f64: sym!("fmi3SetFloat64"),
        get_f32: sym!("fmi3GetFloat32"),
        set_f32: sym!("fmi3SetFloat32"),
        get_i32: sym!("fmi3GetInt32"),
        set_i32: sym!("fmi3SetInt32"),
        get_bool: sym!("fmi3GetBoolean"),
        set_bool: sym!("fmi3SetBoolean"),
    })
}

/// One instance of a co-simulation FMU.
pub struct Instance {
    ptr: Fmi3Instance,
    api: Api,
    log: Box<Log>,
    /// After fmi3Fatal no function may be called, not even fmi3FreeInstance.
    fatal: bool,
    initialized: bool,
}

// SAFETY: FMI 3.0 §2.2.1 lets the importer call an instance's functions from
// any thread as long as the calls are not concurrent; `Instance` is only used
// through `&mut self` (or moved whole), which guarantees that.
unsafe impl Send for Instance {}

/// A value type exchanged through fmi3Get/Set<Type>.
pub trait Value: Copy {
    fn getter(api: &Api) -> Get<Self>;
    fn setter(api: &Api) -> Set<Self>;
}

macro_rules! value {
    ($t:ty, $get:ident, $set:ident) => {
        impl Value for $t {
            fn getter(api: &Api) -> Get<Self> {
                api.$get
            }
            fn setter(api: &Api) -> Set<Self> {
                api.$set
            }
        }
    };
}
value!(f64, get_f64, set_f64);
value!(f32, get_f32, set_f32);
value!(i32, get_i32, set_i32);
value!(bool, get_bool, set_bool);

fn status_name(s: Status) -> String {
    match s {
        0 => "fmi3OK".into(),
        1 => "fmi3Warning".into(),
        2 => "fmi3Discard".into(),
        3 => "fmi3Error".into(),
        4 => "fmi3Fatal".into(),
        n => format!("status {n}"),
    }
}

impl Instance {
    /// Loads the library of the FMU unpacked in `dir` and instantiates it for
    /// co-simulation (FMI 3.0 §4.2.1: no event mode, no early return).
    pub fn new(dir: &Path, desc: &Description, name: &str) -> Result<Instance, String> {
        let lib_path = dir.join("binaries").join(platform_folder()?).join(format!(
            "{}{}",
            desc.model_identifier,
            std::env::consts::DLL_SUFFIX
        ));
        if !lib_path.is_file() {
            return Err(format!(
                "the FMU has no binary for this platform ({} is missing)",
                lib_path.strip_prefix(dir).unwrap_or(&lib_path).display()
            ));
        }
        // Loading and instantiation happen one at a time in the process:
        // each copy of a pythonfmu library starts Python on its first
        // instantiation unless it is running, and two starting it at once
        // (parallel scenarios) abort the process.
        static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());
        let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
        let lib = open_library(&lib_path)?;
        let api = api(lib, &lib_path)?;
        let cstr = |s: &str, what: &str| {
            CString::new(s).map_err(|_| format!("the {what} contains a NUL character"))
        };
        let resources = std::path::absolute(dir.join("resources"))
            .map_err(|e| format!("resources folder: {e}"))?;
        // The resource path ends with a separator (FMI 3.0 §2.3.1).
        let resources = cstr(&format!("{}/", resources.display()), "resources path")?;
        let name_c = cstr(name, "instance name")?;
        let token = cstr(&desc.instantiation_token, "instantiation token")?;
        let log = Box::new(Log::default());
        let env = &*log as *const Log as *mut c_void;
        // SAFETY: the strings are NUL-terminated and outlive the call; no
        // intermediate variables (null array of length 0); `env` points to
        // the boxed `Log`, kept alive in the instance until after
        // fmi3FreeInstance; `log_message` has the callback's signature.
        let ptr = unsafe {
            (api.instantiate)(
                name_c.as_ptr(),
                token.as_ptr(),
                resources.as_ptr(),
                false,
                true,
                false,
                false,
                std::ptr::null(),
                0,
                env,
                Some(log_message),
                None,
            )
        };
        if ptr.is_null() {
            let why = log.text.lock().unwrap_or_else(|e| e.into_inner()).clone();
            return Err(format!(
                "fmi3InstantiateCoSimulation failed{}",
                if why.is_empty() {
                    String::new()
                } else {
                    format!(": {why}")
                }
            ));
        }
        Ok(Instance {
            ptr,
            api,
            log,
            fatal: false,
            initialized: false,
        })
    }

    /// Checks a status: OK and Warning pass; anything else is an error with
    /// the messages the FMU logged.
    fn check(&mut self, status: Status, call: &str) -> Result<(), String> {
        if status == OK || status == WARNING {
            return Ok(());
        }
        if status == FATAL {
            self.fatal = true;
        }
        let mut log = self.log.text.lock().unwrap_or_else(|e| e.into_inner());
        let why = std::mem::take(&mut *log);
        Err(format!(
            "{call} returned {}{}",
            status_name(status),
            if why.is_empty() {
                String::new()
            } else {
                format!(": {why}")
            }
        ))
    }

    fn usable(&self, call: &str) -> Result<(), String> {
        if self.fatal {
            Err(format!("{call}: the FMU returned fmi3Fatal before"))
        } else {
            Ok(())
        }
    }

    /// fmi3Get<Type> of `vrs` into `values` (same length).
    pub fn get<T: Value>(&mut self, vrs: &[u32], values: &mut [T]) -> Result<(), String> {
        self.usable("fmi3Get")?;
        debug_assert_eq!(vrs.len(), values.len());
        let n = vrs.len().min(values.len());
        // SAFETY: both arrays hold `n` elements of the variable type the FMU
        // declares for these value references (checked when the ports were
        // built from the model description).
        let s =
            unsafe { (T::getter(&self.api))(self.ptr, vrs.as_ptr(), n, values.as_mut_ptr(), n) };
        self.check(s, "fmi3Get")
    }

    /// fmi3Set<Type> of `vrs` to `values` (same length).
    pub fn set<T: Value>(&mut self, vrs: &[u32], values: &[T]) -> Result<(), String> {
        self.usable("fmi3Set")?;
        debug_assert_eq!(vrs.len(), values.len());
        let n = vrs.len().min(values.len());
        // SAFETY: as in `get`; the FMU only reads `values`.
        let s = unsafe { (T::setter(&self.api))(self.ptr, vrs.as_ptr(), n, values.as_ptr(), n) };
        self.check(s, "fmi3Set")
    }

    /// fmi3EnterInitializationMode at start time 0, no tolerance, no stop time.
    pub fn enter_initialization_mode(&mut self) -> Result<(), String> {
        self.usable("fmi3EnterInitializationMode")?;
        // SAFETY: a live instance, plain values.
        let s =
            unsafe { (self.api.enter_initialization_mode)(self.ptr, false, 0.0, 0.0, false, 0.0) };
        self.initialized = true;
        self.check(s, "fmi3EnterInitializationMode")
    }

    /// fmi3ExitInitializationMode: the instance is then in Step Mode (no
    /// event mode used, FMI 3.0 §4.2.1).
    pub fn exit_initialization_mode(&mut self) -> Result<(), String> {
        self.usable("fmi3ExitInitializationMode")?;
        // SAFETY: a live instance.
        let s = unsafe { (self.api.exit_initialization_mode)(self.ptr) };
        self.check(s, "fmi3ExitInitializationMode")
    }

    /// fmi3DoStep from `t` over `h` seconds. A step the FMU discards, cuts
    /// short or ends the simulation in is an error.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), String> {
        self.usable("fmi3DoStep")?;
        let (mut event, mut terminate, mut early) = (false, false, false);
        let mut last = t;
        // SAFETY: a live instance; the out-pointers are to locals that live
        // over the call.
        let s = unsafe {
            (self.api.do_step)(
                self.ptr,
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        // The message is formatted on failure only (no allocation per step).
        let at = |e: String| format!("at t = {t} s (step {h} s): {e}");
        self.check(s, "fmi3DoStep").map_err(at)?;
        if terminate {
            return Err(at(
                "fmi3DoStep ended the simulation (terminateSimulation)".into()
            ));
        }
        Ok(())
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        if self.fatal {
            return;
        }
        // SAFETY: a live instance, freed exactly once; the `Log` it may call
        // back into is dropped after this.
        unsafe {
            if self.initialized {
                (self.api.terminate)(self.ptr);
            }
            (self.api.free_instance)(self.ptr);
        }
    }
}
