//! The FMI 2.0 co-simulation interface: the C functions an importer calls, each a thin
//! shell over the instance of the model (its variables, its set-up, its steps).
//!
//! Safety: every function takes the pointers of the standard, and is sound when they
//! are what it says they are (a component from `fmi2Instantiate`, arrays of the lengths
//! given, NUL-terminated strings). A panic does not cross the boundary: it is caught and
//! returned as `fmi2Fatal`.
//!
//! Each function is the standard's function of its name, with its arguments and its
//! meaning (FMI 2.0, sections 2.1 and 4.2), so they carry no documentation of their own.
#![allow(clippy::missing_safety_doc, missing_docs, non_snake_case)]

use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use crate::config::{CONFIG_FILE, Config, SOURCE_FILE};
use crate::instance::{Instance, Status};
use crate::model::{Driven, load};

/// `fmi2Status`.
pub type Fmi2Status = c_int;
const OK: Fmi2Status = 0;
const WARNING: Fmi2Status = 1;
const DISCARD: Fmi2Status = 2;
const ERROR: Fmi2Status = 3;
const FATAL: Fmi2Status = 4;

/// `fmi2CallbackLogger` (its `message` is a printf format; the variable arguments are
/// never used here).
pub type Logger = unsafe extern "C" fn(
    env: *mut c_void,
    instance: *const c_char,
    status: Fmi2Status,
    category: *const c_char,
    message: *const c_char,
    ...
);

/// `fmi2CallbackFunctions`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct CallbackFunctions {
    /// Where log messages go.
    pub logger: Option<Logger>,
    /// Unused: the FMU allocates with Rust's allocator.
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// Unused.
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// Unused: `fmi2DoStep` never returns `fmi2Pending`.
    pub step_finished: Option<unsafe extern "C" fn(*mut c_void, Fmi2Status)>,
    /// Passed back to the logger.
    pub component_environment: *mut c_void,
}

/// The methods of an instance, whatever its model.
trait Component {
    fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), String>;
    fn exit_initialization(&mut self) -> Result<(), String>;
    fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String>;
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String>;
    fn set_input_derivatives(&mut self, v: &[u32], o: &[i32], x: &[f64]) -> Result<(), String>;
    fn do_step(&mut self, t: f64, h: f64) -> Result<Status, String>;
    fn time(&self) -> f64;
}

impl<M: Driven> Component for Instance<M> {
    fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), String> {
        Instance::setup_experiment(self, start, stop)
    }
    fn exit_initialization(&mut self) -> Result<(), String> {
        Instance::exit_initialization(self)
    }
    fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        Instance::get_real(self, vrs, out)
    }
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        Instance::set_real(self, vrs, values)
    }
    fn set_input_derivatives(&mut self, v: &[u32], o: &[i32], x: &[f64]) -> Result<(), String> {
        Instance::set_input_derivatives(self, v, o, x)
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<Status, String> {
        Instance::do_step(self, t, h)
    }
    fn time(&self) -> f64 {
        Instance::time(self)
    }
}

/// What `fmi2Instantiate` returns a pointer to.
struct Handle {
    name: CString,
    callbacks: CallbackFunctions,
    logging: bool,
    resources: PathBuf,
    guid: String,
    component: Box<dyn Component>,
}

impl Handle {
    fn log(&self, status: Fmi2Status, category: &str, message: &str) {
        if status == OK && !self.logging {
            return;
        }
        log_to(&self.callbacks, &self.name, status, category, message);
    }

    /// The status of an outcome, its message logged.
    fn report<T>(&self, what: &str, r: Result<T, String>) -> Fmi2Status {
        match r {
            Ok(_) => OK,
            Err(e) => {
                self.log(ERROR, "logStatusError", &format!("{what}: {e}"));
                ERROR
            }
        }
    }
}

fn log_to(cb: &CallbackFunctions, name: &CStr, status: Fmi2Status, category: &str, message: &str) {
    let Some(logger) = cb.logger else { return };
    // The message is a printf format: a `%` of ours is written `%%`.
    let text = CString::new(message.replace('%', "%%").replace('\0', " ")).unwrap_or_default();
    let category = CString::new(category).unwrap_or_default();
    // SAFETY: the importer gave a logger of the standard's type; every string is ours
    // and NUL-terminated, and the format has no conversions.
    unsafe {
        logger(
            cb.component_environment,
            name.as_ptr(),
            status,
            category.as_ptr(),
            text.as_ptr(),
        )
    };
}

/// The path of a `file:` URI (`file:///a/b`, `file:/a/b`, with `%XX` escapes).
fn file_path(uri: &str) -> Result<PathBuf, String> {
    let rest = uri
        .strip_prefix("file://")
        .map(|r| r.strip_prefix("localhost").unwrap_or(r))
        .or_else(|| uri.strip_prefix("file:"))
        .ok_or_else(|| format!("the resource location `{uri}` is not a file: URI"))?;
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(b)) => {
                out.push(b);
                i += 3;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8(out)
        .map(PathBuf::from)
        .map_err(|_| format!("the resource location `{uri}` is not UTF-8"))
}

/// An instance from the files under `resources`, checked against `guid`.
fn instantiate(resources: &Path, guid: &str) -> Result<Box<dyn Component>, String> {
    let read = |file: &str| {
        let path = resources.join(file);
        std::fs::read_to_string(&path).map_err(|e| format!("reading `{}`: {e}", path.display()))
    };
    let config: Config =
        serde_json::from_str(&read(CONFIG_FILE)?).map_err(|e| format!("`{CONFIG_FILE}`: {e}"))?;
    config
        .check()
        .map_err(|e| format!("`{CONFIG_FILE}`: {e}"))?;
    if config.guid != guid {
        return Err(format!(
            "the guid {guid} is not this FMU's ({}): the modelDescription.xml and the resources are of different exports",
            config.guid
        ));
    }
    let src = read(SOURCE_FILE)?;
    Ok(Box::new(Instance::new(*load(&src, &config)?, config)))
}

unsafe fn text(p: *const c_char) -> String {
    if p.is_null() {
        return String::new();
    }
    // SAFETY: a NUL-terminated string from the importer.
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

/// Runs `f` on the handle behind `c`, a panic caught as `fmi2Fatal`.
unsafe fn with(c: *mut c_void, f: impl FnOnce(&mut Handle) -> Fmi2Status) -> Fmi2Status {
    if c.is_null() {
        return ERROR;
    }
    // SAFETY: `c` came from `fmi2Instantiate` and is not freed yet.
    let h = unsafe { &mut *(c as *mut Handle) };
    match catch_unwind(AssertUnwindSafe(|| f(h))) {
        Ok(s) => s,
        Err(_) => FATAL,
    }
}

unsafe fn slice<'a, T>(p: *const T, n: usize) -> &'a [T] {
    if n == 0 || p.is_null() {
        &[]
    } else {
        // SAFETY: the importer gives `n` elements at `p`.
        unsafe { std::slice::from_raw_parts(p, n) }
    }
}

unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> &'a mut [T] {
    if n == 0 || p.is_null() {
        &mut []
    } else {
        // SAFETY: the importer gives room for `n` elements at `p`.
        unsafe { std::slice::from_raw_parts_mut(p, n) }
    }
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    name: *const c_char,
    fmu_type: c_int,
    guid: *const c_char,
    resource_location: *const c_char,
    callbacks: *const CallbackFunctions,
    _visible: c_int,
    logging_on: c_int,
) -> *mut c_void {
    if callbacks.is_null() {
        return std::ptr::null_mut();
    }
    // SAFETY: the standard's arguments.
    let (cb, name, guid, location) =
        unsafe { (*callbacks, text(name), text(guid), text(resource_location)) };
    let cname = CString::new(name).unwrap_or_default();
    let made = catch_unwind(AssertUnwindSafe(|| {
        if fmu_type != 1 {
            return Err(
                "this FMU is for co-simulation only (fmuType fmi2CoSimulation)".to_string(),
            );
        }
        let resources = file_path(&location)?;
        let component = instantiate(&resources, &guid)?;
        Ok((resources, component))
    }));
    match made {
        Ok(Ok((resources, component))) => Box::into_raw(Box::new(Handle {
            name: cname,
            callbacks: cb,
            logging: logging_on != 0,
            resources,
            guid,
            component,
        })) as *mut c_void,
        Ok(Err(e)) => {
            log_to(
                &cb,
                &cname,
                ERROR,
                "logStatusError",
                &format!("fmi2Instantiate: {e}"),
            );
            std::ptr::null_mut()
        }
        Err(_) => std::ptr::null_mut(),
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: *mut c_void) {
    if !c.is_null() {
        // SAFETY: `c` came from `fmi2Instantiate`; the importer frees it once.
        drop(unsafe { Box::from_raw(c as *mut Handle) });
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: *mut c_void,
    logging_on: c_int,
    _n: usize,
    _categories: *const *const c_char,
) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            h.logging = logging_on != 0;
            OK
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: *mut c_void,
    _tolerance_defined: c_int,
    _tolerance: f64,
    start: f64,
    stop_defined: c_int,
    stop: f64,
) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            let r = h
                .component
                .setup_experiment(start, (stop_defined != 0).then_some(stop));
            h.report("fmi2SetupExperiment", r)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: *mut c_void) -> Fmi2Status {
    unsafe { with(c, |_| OK) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: *mut c_void) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            let r = h.component.exit_initialization();
            h.report("fmi2ExitInitializationMode", r)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: *mut c_void) -> Fmi2Status {
    unsafe { with(c, |_| OK) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: *mut c_void) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            let r = instantiate(&h.resources, &h.guid).map(|fresh| h.component = fresh);
            h.report("fmi2Reset", r)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: *mut c_void,
    vr: *const u32,
    n: usize,
    values: *mut f64,
) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            let r = h.component.get_real(slice(vr, n), slice_mut(values, n));
            h.report("fmi2GetReal", r)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: *mut c_void,
    vr: *const u32,
    n: usize,
    values: *const f64,
) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            let r = h.component.set_real(slice(vr, n), slice(values, n));
            h.report("fmi2SetReal", r)
        })
    }
}

/// The model has no variables of this type: only an empty request succeeds.
unsafe fn none_of(c: *mut c_void, n: usize, what: &str) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            let r = if n == 0 {
                Ok(())
            } else {
                Err(format!("the FMU has no {what} variables"))
            };
            h.report(what, r)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(
    c: *mut c_void,
    _: *const u32,
    n: usize,
    _: *mut c_int,
) -> Fmi2Status {
    unsafe { none_of(c, n, "Integer") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: *mut c_void,
    _: *const u32,
    n: usize,
    _: *mut c_int,
) -> Fmi2Status {
    unsafe { none_of(c, n, "Boolean") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(
    c: *mut c_void,
    _: *const u32,
    n: usize,
    _: *mut *const c_char,
) -> Fmi2Status {
    unsafe { none_of(c, n, "String") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(
    c: *mut c_void,
    _: *const u32,
    n: usize,
    _: *const c_int,
) -> Fmi2Status {
    unsafe { none_of(c, n, "Integer") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: *mut c_void,
    _: *const u32,
    n: usize,
    _: *const c_int,
) -> Fmi2Status {
    unsafe { none_of(c, n, "Boolean") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(
    c: *mut c_void,
    _: *const u32,
    n: usize,
    _: *const *const c_char,
) -> Fmi2Status {
    unsafe { none_of(c, n, "String") }
}

/// What the FMU declares it cannot do (`canGetAndSetFMUstate`,
/// `providesDirectionalDerivative`, `canRunAsynchronuously` are false).
unsafe fn unsupported(c: *mut c_void, what: &str) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            h.log(
                ERROR,
                "logStatusError",
                &format!("{what}: not supported by this FMU (see its modelDescription.xml)"),
            );
            ERROR
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: *mut c_void, _: *mut *mut c_void) -> Fmi2Status {
    unsafe { unsupported(c, "fmi2GetFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: *mut c_void, _: *mut c_void) -> Fmi2Status {
    unsafe { unsupported(c, "fmi2SetFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: *mut c_void, _: *mut *mut c_void) -> Fmi2Status {
    unsafe { unsupported(c, "fmi2FreeFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: *mut c_void,
    _: *mut c_void,
    _: *mut usize,
) -> Fmi2Status {
    unsafe { unsupported(c, "fmi2SerializedFMUstateSize") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: *mut c_void,
    _: *mut c_void,
    _: *mut u8,
    _: usize,
) -> Fmi2Status {
    unsafe { unsupported(c, "fmi2SerializeFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: *mut c_void,
    _: *const u8,
    _: usize,
    _: *mut *mut c_void,
) -> Fmi2Status {
    unsafe { unsupported(c, "fmi2DeSerializeFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: *mut c_void,
    _: *const u32,
    _: usize,
    _: *const u32,
    _: usize,
    _: *const f64,
    _: *mut f64,
) -> Fmi2Status {
    unsafe { unsupported(c, "fmi2GetDirectionalDerivative") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: *mut c_void,
    vr: *const u32,
    n: usize,
    order: *const c_int,
    values: *const f64,
) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            let r =
                h.component
                    .set_input_derivatives(slice(vr, n), slice(order, n), slice(values, n));
            h.report("fmi2SetRealInputDerivatives", r)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: *mut c_void,
    _: *const u32,
    _: usize,
    _: *const c_int,
    _: *mut f64,
) -> Fmi2Status {
    unsafe {
        unsupported(
            c,
            "fmi2GetRealOutputDerivatives (maxOutputDerivativeOrder is 0)",
        )
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: *mut c_void,
    t: f64,
    h_step: f64,
    _no_set_prior: c_int,
) -> Fmi2Status {
    unsafe {
        with(c, |h| match h.component.do_step(t, h_step) {
            Ok(Status::Ok) => OK,
            Ok(Status::Warning(w)) => {
                h.log(WARNING, "logStatusWarning", &format!("fmi2DoStep: {w}"));
                WARNING
            }
            Err(e) => {
                h.log(ERROR, "logStatusError", &format!("fmi2DoStep: {e}"));
                ERROR
            }
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: *mut c_void) -> Fmi2Status {
    unsafe { unsupported(c, "fmi2CancelStep (steps are never pending)") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(c: *mut c_void, _: c_int, _: *mut Fmi2Status) -> Fmi2Status {
    unsafe { with(c, |_| DISCARD) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: *mut c_void,
    kind: c_int,
    value: *mut f64,
) -> Fmi2Status {
    unsafe {
        with(c, |h| {
            // fmi2LastSuccessfulTime
            if kind == 2 && !value.is_null() {
                *value = h.component.time();
                OK
            } else {
                DISCARD
            }
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: *mut c_void,
    _: c_int,
    _: *mut c_int,
) -> Fmi2Status {
    unsafe { with(c, |_| DISCARD) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: *mut c_void,
    _: c_int,
    _: *mut c_int,
) -> Fmi2Status {
    unsafe { with(c, |_| DISCARD) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: *mut c_void,
    _: c_int,
    _: *mut *const c_char,
) -> Fmi2Status {
    unsafe { with(c, |_| DISCARD) }
}

#[cfg(test)]
mod tests {
    use super::file_path;
    use std::path::PathBuf;

    #[test]
    fn file_uris_of_importers_give_their_paths() {
        for uri in [
            "file:///tmp/a%20b/resources",
            "file:/tmp/a%20b/resources",
            "file://localhost/tmp/a%20b/resources",
        ] {
            assert_eq!(
                file_path(uri).unwrap(),
                PathBuf::from("/tmp/a b/resources"),
                "{uri}"
            );
        }
        assert!(file_path("http://x/resources").is_err());
    }
}
