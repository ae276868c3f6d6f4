//! The FMI 3.0 C functions (the function types of `fmi3FunctionTypes.h`,
//! FMI 3.0 §2.3 and §4) exported by the shared library. This is the crate's
//! only `unsafe`: turning the master's pointers into slices and the
//! instance handle into a [`Slave`]. Every call runs inside `catch_unwind`,
//! so a panic never crosses into C: it answers fmi3Fatal, logged.
//!
//! Functions softplc does not support answer fmi3Error with a logged reason
//! (FMI 3.0 §2.3.1 lets an FMU refuse what its modelDescription.xml does
//! not promise).

#![deny(unsafe_op_in_unsafe_fn)]

use std::ffi::{c_char, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

use crate::slave::Slave;

type Fmi3Instance = *mut c_void;
type Status = i32;
const OK: Status = 0;
const ERROR: Status = 3;
const FATAL: Status = 4;

/// `fmi3LogMessageCallback`.
type LogMessage = unsafe extern "C" fn(*mut c_void, Status, *const c_char, *const c_char);

/// What the FMU keeps per instance besides the PLC.
struct Instance {
    /// The master's `instanceEnvironment`, given back to `log`.
    env: *mut c_void,
    log: Option<LogMessage>,
    slave: Slave,
    /// After a panic no call is served (FMI 3.0: after fmi3Fatal only
    /// fmi3FreeInstance... and not even that is required).
    fatal: bool,
}

/// Sends `message` to the master's logger with `status`.
fn log_to(env: *mut c_void, log: Option<LogMessage>, status: Status, message: &str) {
    let Some(log) = log else { return };
    let category = if status >= ERROR {
        c"logStatusError"
    } else {
        c"logEvents"
    };
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    // SAFETY: `log` is the master's fmi3LogMessageCallback, called with the
    // environment it gave and NUL-terminated strings valid during the call.
    unsafe { log(env, status, category.as_ptr(), text.as_ptr()) }
}

/// Runs `f` on the instance behind `instance`: errors are logged and
/// answer fmi3Error, a panic answers fmi3Fatal.
///
/// # Safety
/// `instance` is null or a pointer returned by
/// [`fmi3InstantiateCoSimulation`] and not yet freed, used by one thread at
/// a time (FMI 3.0 §2.3.1).
unsafe fn with(instance: Fmi3Instance, f: impl FnOnce(&mut Slave) -> Result<(), String>) -> Status {
    if instance.is_null() {
        return ERROR;
    }
    // SAFETY: see the function's contract: the pointer came from
    // `Box::into_raw` and no other reference to it is alive during the call.
    let inst = unsafe { &mut *(instance as *mut Instance) };
    if inst.fatal {
        return FATAL;
    }
    match catch_unwind(AssertUnwindSafe(|| f(&mut inst.slave))) {
        Ok(Ok(())) => OK,
        Ok(Err(why)) => {
            log_to(inst.env, inst.log, ERROR, &why);
            ERROR
        }
        Err(panic) => {
            inst.fatal = true;
            let why = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            log_to(
                inst.env,
                inst.log,
                FATAL,
                &format!("internal error (the instance is unusable): {why}"),
            );
            FATAL
        }
    }
}

/// The `n` elements at `p` (none when `n` is 0).
///
/// # Safety
/// When `n > 0`, `p` points to `n` initialised elements valid for the call.
unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(format!("{what} is NULL with {n} elements"));
    }
    // SAFETY: see the function's contract.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// The `n` writable elements at `p`.
///
/// # Safety
/// When `n > 0`, `p` points to `n` elements writable during the call.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, what: &str) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(format!("{what} is NULL with {n} elements"));
    }
    // SAFETY: see the function's contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// A C string argument, `None` for NULL.
///
/// # Safety
/// `p` is null or a NUL-terminated string valid for the call.
unsafe fn text(p: *const c_char) -> Option<String> {
    // SAFETY: see the function's contract.
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

/// # Safety
/// FMI 3.0 fmi3SetDebugLogging.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: Fmi3Instance,
    _logging_on: bool,
    _n_categories: usize,
    _categories: *const *const c_char,
) -> Status {
    // Errors are always logged; softplc logs nothing else.
    // SAFETY: the master's instance handle (FMI 3.0 §2.3.1).
    unsafe { with(instance, |_| Ok(())) }
}

/// # Safety
/// FMI 3.0 fmi3InstantiateCoSimulation: strings NUL-terminated or NULL.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instance_name: *const c_char,
    instantiation_token: *const c_char,
    resource_path: *const c_char,
    _visible: bool,
    _logging_on: bool,
    event_mode_used: bool,
    _early_return_allowed: bool,
    _required_intermediate_variables: *const u32,
    _n_required_intermediate_variables: usize,
    instance_environment: *mut c_void,
    log_message: Option<LogMessage>,
    _intermediate_update: *const c_void,
) -> Fmi3Instance {
    let env = instance_environment;
    let made = catch_unwind(|| {
        // SAFETY: the master passes NUL-terminated strings or NULL.
        let (name, token, resources) = unsafe {
            (
                text(instance_name),
                text(instantiation_token),
                text(resource_path),
            )
        };
        let name = name.unwrap_or_default();
        if event_mode_used {
            return Err(format!(
                "{name}: softplc's FMU has no event mode (hasEventMode is false)"
            ));
        }
        let resources = resources.filter(|r| !r.is_empty()).ok_or_else(|| {
            format!("{name}: no resource path given: the FMU's resources/ folder holds the program")
        })?;
        let resources = PathBuf::from(resources.strip_prefix("file://").unwrap_or(&resources));
        Slave::instantiate(&resources, token.as_deref()).map_err(|e| format!("{name}: {e}"))
    });
    match made {
        Ok(Ok(slave)) => Box::into_raw(Box::new(Instance {
            env,
            log: log_message,
            slave,
            fatal: false,
        })) as Fmi3Instance,
        Ok(Err(why)) => {
            log_to(env, log_message, ERROR, &why);
            std::ptr::null_mut()
        }
        Err(_) => {
            log_to(
                env,
                log_message,
                FATAL,
                "internal error while instantiating",
            );
            std::ptr::null_mut()
        }
    }
}

/// # Safety
/// FMI 3.0 fmi3InstantiateModelExchange.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _instance_name: *const c_char,
    _instantiation_token: *const c_char,
    _resource_path: *const c_char,
    _visible: bool,
    _logging_on: bool,
    instance_environment: *mut c_void,
    log_message: Option<LogMessage>,
) -> Fmi3Instance {
    log_to(
        instance_environment,
        log_message,
        ERROR,
        "softplc's FMU is for co-simulation only (no model exchange)",
    );
    std::ptr::null_mut()
}

/// # Safety
/// FMI 3.0 fmi3InstantiateScheduledExecution.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instance_name: *const c_char,
    _instantiation_token: *const c_char,
    _resource_path: *const c_char,
    _visible: bool,
    _logging_on: bool,
    instance_environment: *mut c_void,
    log_message: Option<LogMessage>,
    _clock_update: *const c_void,
    _lock_preemption: *const c_void,
    _unlock_preemption: *const c_void,
) -> Fmi3Instance {
    log_to(
        instance_environment,
        log_message,
        ERROR,
        "softplc's FMU is for co-simulation only (no scheduled execution)",
    );
    std::ptr::null_mut()
}

/// # Safety
/// FMI 3.0 fmi3FreeInstance: `instance` is not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(instance: Fmi3Instance) {
    if instance.is_null() {
        return;
    }
    // A panic in a destructor must not unwind into C either.
    let _ = catch_unwind(|| {
        // SAFETY: the pointer came from `Box::into_raw` in
        // fmi3InstantiateCoSimulation and the master frees it once.
        drop(unsafe { Box::from_raw(instance as *mut Instance) });
    });
}

/// # Safety
/// FMI 3.0 fmi3EnterInitializationMode.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: Fmi3Instance,
    _tolerance_defined: bool,
    _tolerance: f64,
    start_time: f64,
    _stop_time_defined: bool,
    _stop_time: f64,
) -> Status {
    // SAFETY: the master's instance handle.
    unsafe { with(instance, |s| s.enter_initialization(start_time)) }
}

/// # Safety
/// FMI 3.0 fmi3ExitInitializationMode.
#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: Fmi3Instance) -> Status {
    // SAFETY: the master's instance handle.
    unsafe { with(instance, Slave::exit_initialization) }
}

/// # Safety
/// FMI 3.0 fmi3Terminate.
#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(instance: Fmi3Instance) -> Status {
    // SAFETY: the master's instance handle.
    unsafe { with(instance, Slave::terminate) }
}

/// # Safety
/// FMI 3.0 fmi3Reset.
#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(instance: Fmi3Instance) -> Status {
    // SAFETY: the master's instance handle.
    unsafe { with(instance, Slave::reset) }
}

/// # Safety
/// FMI 3.0 fmi3DoStep: the out pointers are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    instance: Fmi3Instance,
    current_communication_point: f64,
    communication_step_size: f64,
    _no_set_fmu_state_prior_to_current_point: bool,
    event_handling_needed: *mut bool,
    terminate_simulation: *mut bool,
    early_return: *mut bool,
    last_successful_time: *mut f64,
) -> Status {
    let (t, h) = (current_communication_point, communication_step_size);
    // SAFETY: the master's instance handle.
    unsafe {
        with(instance, |s| {
            s.do_step(t, h)?;
            for flag in [event_handling_needed, terminate_simulation, early_return] {
                if !flag.is_null() {
                    // SAFETY: non-null out pointers are writable (FMI 3.0 §4.2.1).
                    *flag = false;
                }
            }
            if !last_successful_time.is_null() {
                // SAFETY: as above.
                *last_successful_time = t + h;
            }
            Ok(())
        })
    }
}

/// fmi3Get<Type> and fmi3Set<Type> of a type softplc has variables of.
macro_rules! get_set {
    ($get:ident, $set:ident, $t:ty) => {
        /// # Safety
        /// FMI 3.0 fmi3Get<Type>: `nvr` value references, `n` writable values.
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            instance: Fmi3Instance,
            vrs: *const u32,
            nvr: usize,
            values: *mut $t,
            n: usize,
        ) -> Status {
            // SAFETY: the master's instance handle and arrays of the given lengths.
            unsafe {
                with(instance, |s| {
                    let vrs = slice(vrs, nvr, "valueReferences")?;
                    s.get(vrs, slice_mut(values, n, "values")?)
                })
            }
        }

        /// # Safety
        /// FMI 3.0 fmi3Set<Type>: `nvr` value references, `n` values.
        #[no_mangle]
        pub unsafe extern "C" fn $set(
            instance: Fmi3Instance,
            vrs: *const u32,
            nvr: usize,
            values: *const $t,
            n: usize,
        ) -> Status {
            // SAFETY: the master's instance handle and arrays of the given lengths.
            unsafe {
                with(instance, |s| {
                    let vrs = slice(vrs, nvr, "valueReferences")?;
                    s.set(vrs, slice(values, n, "values")?)
                })
            }
        }
    };
}

get_set!(fmi3GetInt16, fmi3SetInt16, i16);
get_set!(fmi3GetUInt16, fmi3SetUInt16, u16);
get_set!(fmi3GetInt32, fmi3SetInt32, i32);
get_set!(fmi3GetUInt32, fmi3SetUInt32, u32);
get_set!(fmi3GetFloat32, fmi3SetFloat32, f32);

/// # Safety
/// FMI 3.0 fmi3GetBoolean.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetBoolean(
    instance: Fmi3Instance,
    vrs: *const u32,
    nvr: usize,
    values: *mut bool,
    n: usize,
) -> Status {
    // SAFETY: the master's instance handle and arrays of the given lengths.
    unsafe {
        with(instance, |s| {
            let vrs = slice(vrs, nvr, "valueReferences")?;
            s.get(vrs, slice_mut(values, n, "values")?)
        })
    }
}

/// # Safety
/// FMI 3.0 fmi3SetBoolean. Read as bytes: any non-zero byte is true.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetBoolean(
    instance: Fmi3Instance,
    vrs: *const u32,
    nvr: usize,
    values: *const u8,
    n: usize,
) -> Status {
    // SAFETY: the master's instance handle and arrays of the given lengths.
    unsafe {
        with(instance, |s| {
            let vrs = slice(vrs, nvr, "valueReferences")?;
            let values: Vec<bool> = slice(values, n, "values")?
                .iter()
                .map(|b| *b != 0)
                .collect();
            s.set(vrs, &values)
        })
    }
}

/// # Safety
/// FMI 3.0 fmi3GetFloat64 (the scan_time parameter).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    instance: Fmi3Instance,
    vrs: *const u32,
    nvr: usize,
    values: *mut f64,
    n: usize,
) -> Status {
    // SAFETY: the master's instance handle and arrays of the given lengths.
    unsafe {
        with(instance, |s| {
            let vrs = slice(vrs, nvr, "valueReferences")?;
            s.get_f64(vrs, slice_mut(values, n, "values")?)
        })
    }
}

/// # Safety
/// FMI 3.0 fmi3SetFloat64 (the scan_time parameter).
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    instance: Fmi3Instance,
    vrs: *const u32,
    nvr: usize,
    values: *const f64,
    n: usize,
) -> Status {
    // SAFETY: the master's instance handle and arrays of the given lengths.
    unsafe {
        with(instance, |s| {
            let vrs = slice(vrs, nvr, "valueReferences")?;
            s.set_f64(vrs, slice(values, n, "values")?)
        })
    }
}

/// A Get/Set of a type no softplc variable has: fine for no value
/// references, else the first is unknown.
///
/// # Safety
/// `vrs` points to `nvr` value references.
unsafe fn no_variable_of(instance: Fmi3Instance, vrs: *const u32, nvr: usize, ty: &str) -> Status {
    // SAFETY: the master's instance handle and array.
    unsafe {
        with(instance, |_| {
            match slice(vrs, nvr, "valueReferences")?.first() {
                None => Ok(()),
                Some(vr) => Err(format!(
                    "value reference {vr}: softplc's FMU has no {ty} variable"
                )),
            }
        })
    }
}

/// Get/Set of the types softplc never uses.
macro_rules! no_variables {
    ($($name:ident, $ty:literal, ($($arg:ident : $argty:ty),*);)*) => {$(
        /// # Safety
        /// The FMI 3.0 function of this name.
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            instance: Fmi3Instance,
            vrs: *const u32,
            nvr: usize,
            $($arg: $argty),*
        ) -> Status {
            $(let _ = $arg;)*
            // SAFETY: the master's instance handle and array.
            unsafe { no_variable_of(instance, vrs, nvr, $ty) }
        }
    )*};
}

no_variables! {
    fmi3GetInt8, "Int8", (_v: *mut i8, _n: usize);
    fmi3SetInt8, "Int8", (_v: *const i8, _n: usize);
    fmi3GetUInt8, "UInt8", (_v: *mut u8, _n: usize);
    fmi3SetUInt8, "UInt8", (_v: *const u8, _n: usize);
    fmi3GetInt64, "Int64", (_v: *mut i64, _n: usize);
    fmi3SetInt64, "Int64", (_v: *const i64, _n: usize);
    fmi3GetUInt64, "UInt64", (_v: *mut u64, _n: usize);
    fmi3SetUInt64, "UInt64", (_v: *const u64, _n: usize);
    fmi3GetString, "String", (_v: *mut *const c_char, _n: usize);
    fmi3SetString, "String", (_v: *const *const c_char, _n: usize);
    fmi3GetBinary, "Binary", (_sizes: *mut usize, _v: *mut *const u8, _n: usize);
    fmi3SetBinary, "Binary", (_sizes: *const usize, _v: *const *const u8, _n: usize);
    fmi3GetClock, "Clock", (_v: *mut bool);
    fmi3SetClock, "Clock", (_v: *const bool);
    fmi3GetIntervalDecimal, "Clock", (_intervals: *mut f64, _qualifiers: *mut i32);
    fmi3GetIntervalFraction, "Clock", (_counters: *mut u64, _resolutions: *mut u64, _qualifiers: *mut i32);
    fmi3GetShiftDecimal, "Clock", (_shifts: *mut f64);
    fmi3GetShiftFraction, "Clock", (_counters: *mut u64, _resolutions: *mut u64);
    fmi3SetIntervalDecimal, "Clock", (_intervals: *const f64);
    fmi3SetIntervalFraction, "Clock", (_counters: *const u64, _resolutions: *const u64);
    fmi3SetShiftDecimal, "Clock", (_shifts: *const f64);
    fmi3SetShiftFraction, "Clock", (_counters: *const u64, _resolutions: *const u64);
}

/// # Safety
/// FMI 3.0 fmi3GetNumberOfVariableDependencies. No output depends directly
/// on an input (inputs act at the next scan): always 0.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
    instance: Fmi3Instance,
    _vr: u32,
    n: *mut usize,
) -> Status {
    // SAFETY: the master's instance handle; `n` NULL or writable.
    unsafe {
        with(instance, |_| {
            if !n.is_null() {
                // SAFETY: as above.
                *n = 0;
            }
            Ok(())
        })
    }
}

/// # Safety
/// FMI 3.0 fmi3GetVariableDependencies (there are none to give).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetVariableDependencies(
    instance: Fmi3Instance,
    _dependent: u32,
    _element_indices_of_dependent: *mut usize,
    _independents: *mut u32,
    _element_indices_of_independents: *mut usize,
    _dependency_kinds: *mut i32,
    n: usize,
) -> Status {
    // SAFETY: the master's instance handle.
    unsafe {
        with(instance, |_| {
            if n == 0 {
                Ok(())
            } else {
                Err(format!("asked for {n} dependencies; there are none"))
            }
        })
    }
}

/// Refuses a call softplc's FMU does not support, with the reason logged.
///
/// # Safety
/// The master's instance handle.
unsafe fn refuse(instance: Fmi3Instance, call: &str, why: &str) -> Status {
    // SAFETY: as the function's contract.
    unsafe { with(instance, |_| Err(format!("{call}: {why}"))) }
}

/// FMI functions softplc answers with fmi3Error.
macro_rules! unsupported {
    ($($name:ident ($($arg:ident : $argty:ty),*) $why:expr;)*) => {$(
        /// # Safety
        /// The FMI 3.0 function of this name.
        #[no_mangle]
        pub unsafe extern "C" fn $name(instance: Fmi3Instance, $($arg: $argty),*) -> Status {
            $(let _ = $arg;)*
            // SAFETY: the master's instance handle.
            unsafe { refuse(instance, stringify!($name), $why) }
        }
    )*};
}

/// Model exchange functions (importers such as fmpy look every function up).
const NO_ME: &str = "softplc's FMU is for co-simulation only (no model exchange)";

unsupported! {
    fmi3EnterEventMode() "softplc's FMU has no event mode";
    fmi3EnterStepMode() "softplc's FMU has no event mode";
    fmi3EnterConfigurationMode() "softplc's FMU has no structural parameters";
    fmi3ExitConfigurationMode() "softplc's FMU has no structural parameters";
    fmi3EvaluateDiscreteStates() "softplc's FMU has no event mode";
    fmi3UpdateDiscreteStates(_a: *mut bool, _b: *mut bool, _c: *mut bool, _d: *mut bool, _e: *mut bool, _f: *mut f64) "softplc's FMU has no event mode";
    fmi3GetOutputDerivatives(_vrs: *const u32, _nvr: usize, _orders: *const i32, _values: *mut f64, _n: usize) "a PLC's outputs have no derivatives (maxOutputDerivativeOrder is 0)";
    fmi3GetDirectionalDerivative(_u: *const u32, _nu: usize, _k: *const u32, _nk: usize, _seed: *const f64, _ns: usize, _sens: *mut f64, _nsens: usize) "not supported (providesDirectionalDerivatives is false)";
    fmi3GetAdjointDerivative(_u: *const u32, _nu: usize, _k: *const u32, _nk: usize, _seed: *const f64, _ns: usize, _sens: *mut f64, _nsens: usize) "not supported (providesAdjointDerivatives is false)";
    fmi3ActivateModelPartition(_clock: u32, _time: f64) "softplc's FMU is for co-simulation only";
    fmi3EnterContinuousTimeMode() NO_ME;
    fmi3CompletedIntegratorStep(_no_set: bool, _enter_event_mode: *mut bool, _terminate: *mut bool) NO_ME;
    fmi3SetTime(_time: f64) NO_ME;
    fmi3SetContinuousStates(_x: *const f64, _n: usize) NO_ME;
    fmi3GetContinuousStateDerivatives(_dx: *mut f64, _n: usize) NO_ME;
    fmi3GetEventIndicators(_z: *mut f64, _n: usize) NO_ME;
    fmi3GetContinuousStates(_x: *mut f64, _n: usize) NO_ME;
    fmi3GetNominalsOfContinuousStates(_nominals: *mut f64, _n: usize) NO_ME;
    fmi3GetNumberOfEventIndicators(_n: *mut usize) NO_ME;
    fmi3GetNumberOfContinuousStates(_n: *mut usize) NO_ME;
}

/// An FMU state as the master holds it (`fmi3FMUState`): the bytes of
/// [`Slave::save_state`], boxed.
type FmuState = *mut c_void;

/// The bytes behind a state handle.
///
/// # Safety
/// `state` is null or a handle of fmi3GetFMUState/fmi3DeserializeFMUState
/// not yet freed.
unsafe fn state_bytes<'a>(state: FmuState) -> Result<&'a Vec<u8>, String> {
    if state.is_null() {
        return Err("the FMU state is NULL".into());
    }
    // SAFETY: see the function's contract: a `Box<Vec<u8>>` made by this library.
    Ok(unsafe { &*(state as *const Vec<u8>) })
}

/// Puts `bytes` in `*state`: into the state there (FMI 3.0: an existing
/// state is overwritten) or a new one.
///
/// # Safety
/// `state` is writable; `*state` null or a live handle of this library.
unsafe fn store_state(state: *mut FmuState, bytes: Vec<u8>) -> Result<(), String> {
    if state.is_null() {
        return Err("no place for the FMU state (NULL)".into());
    }
    // SAFETY: see the function's contract.
    unsafe {
        if (*state).is_null() {
            *state = Box::into_raw(Box::new(bytes)) as FmuState;
        } else {
            *(*state as *mut Vec<u8>) = bytes;
        }
    }
    Ok(())
}

/// # Safety
/// FMI 3.0 fmi3GetFMUState.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(instance: Fmi3Instance, state: *mut FmuState) -> Status {
    // SAFETY: the master's instance handle and state pointer.
    unsafe { with(instance, |s| store_state(state, s.save_state()?)) }
}

/// # Safety
/// FMI 3.0 fmi3SetFMUState.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(instance: Fmi3Instance, state: FmuState) -> Status {
    // SAFETY: the master's instance handle and a state handle of this library.
    unsafe { with(instance, |s| s.load_state(state_bytes(state)?)) }
}

/// # Safety
/// FMI 3.0 fmi3FreeFMUState: `*state` is not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(instance: Fmi3Instance, state: *mut FmuState) -> Status {
    // SAFETY: the master's instance handle and state pointer.
    unsafe {
        with(instance, |_| {
            if !state.is_null() && !(*state).is_null() {
                // SAFETY: a `Box<Vec<u8>>` of this library, freed once.
                drop(Box::from_raw(*state as *mut Vec<u8>));
                *state = std::ptr::null_mut();
            }
            Ok(())
        })
    }
}

/// # Safety
/// FMI 3.0 fmi3SerializedFMUStateSize.
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: Fmi3Instance,
    state: FmuState,
    size: *mut usize,
) -> Status {
    // SAFETY: the master's instance handle, a state handle, `size` writable.
    unsafe {
        with(instance, |_| {
            let n = state_bytes(state)?.len();
            if size.is_null() {
                return Err("size is NULL".into());
            }
            *size = n;
            Ok(())
        })
    }
}

/// # Safety
/// FMI 3.0 fmi3SerializeFMUState: `bytes` holds `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: Fmi3Instance,
    state: FmuState,
    bytes: *mut u8,
    size: usize,
) -> Status {
    // SAFETY: the master's instance handle, a state handle, a buffer of `size`.
    unsafe {
        with(instance, |_| {
            let b = state_bytes(state)?;
            if size != b.len() {
                return Err(format!(
                    "the serialized FMU state is {} bytes, not {size} (fmi3SerializedFMUStateSize)",
                    b.len()
                ));
            }
            slice_mut(bytes, size, "serializedState")?.copy_from_slice(b);
            Ok(())
        })
    }
}

/// # Safety
/// FMI 3.0 fmi3DeserializeFMUState: `bytes` holds `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: Fmi3Instance,
    bytes: *const u8,
    size: usize,
    state: *mut FmuState,
) -> Status {
    // SAFETY: the master's instance handle, a buffer of `size`, `state` writable.
    unsafe {
        with(instance, |_| {
            let b = slice(bytes, size, "serializedState")?.to_vec();
            store_state(state, b)
        })
    }
}
