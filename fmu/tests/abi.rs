//! The FMU's C interface called as an importer calls it, against the runtime's own run
//! of the same model with the same settings and cuts (the independent side: the
//! simulator driven directly, without the FMU's layers).

use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use dae_fmu::abi::*;
use dae_fmu::{Config, Kind, export};
use dae_runtime::design::{Online, consistent_start};
use dae_runtime::family::Interpreted;
use dae_runtime::trace::NoTrace;
use dae_runtime::{Model, Simulator};

const OK: c_int = 0;
const WARNING: c_int = 1;
const ERROR: c_int = 3;

fn models() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/models")
}

/// The library file is only needed by the archive; these tests load the crate itself.
fn fake_library(dir: &Path) -> PathBuf {
    let p = dir.join("lib.so");
    std::fs::write(&p, b"not a library").unwrap();
    p
}

/// The files of a stored zip archive (the only kind the packager writes).
fn unzip(bytes: &[u8], into: &Path) {
    let mut at = 0;
    while bytes[at..at + 4] == 0x0403_4b50u32.to_le_bytes() {
        let u16_at = |o: usize| u16::from_le_bytes([bytes[at + o], bytes[at + o + 1]]) as usize;
        let size = u32::from_le_bytes(bytes[at + 22..at + 26].try_into().unwrap()) as usize;
        let (name_len, extra) = (u16_at(26), u16_at(28));
        let name = std::str::from_utf8(&bytes[at + 30..at + 30 + name_len]).unwrap();
        let data = at + 30 + name_len + extra;
        let path = into.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, &bytes[data..data + size]).unwrap();
        at = data + size;
    }
}

/// An exported FMU unpacked into a fresh folder: (folder, guid, variable names).
fn unpacked(file: &str, config: Config, tag: &str) -> (PathBuf, String, Vec<(String, Kind)>) {
    let dir = std::env::temp_dir().join(format!("dae-fmu-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let src = std::fs::read_to_string(models().join(file)).unwrap();
    let fmu = dir.join("m.fmu");
    let e = export(&src, config, &fake_library(&dir), &fmu).unwrap();
    unzip(&std::fs::read(&fmu).unwrap(), &dir.join("x"));
    let names = e
        .variables
        .iter()
        .map(|v| (v.name.clone(), v.kind))
        .collect();
    (dir.join("x"), e.guid, names)
}

static LOG: Mutex<Vec<(c_int, String)>> = Mutex::new(Vec::new());

/// The logger of the test, as an importer written without C variadics writes it (FMPy's
/// ctypes callback is the same): the FMU passes no variable arguments.
unsafe extern "C" fn logger(
    _env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    _category: *const c_char,
    message: *const c_char,
) {
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    LOG.lock().unwrap().push((status, text));
}

fn callbacks() -> CallbackFunctions {
    CallbackFunctions {
        // SAFETY: the same arguments in the same registers (x86-64 System V), and the
        // FMU never passes variable arguments.
        logger: Some(unsafe {
            std::mem::transmute::<
                unsafe extern "C" fn(
                    *mut c_void,
                    *const c_char,
                    c_int,
                    *const c_char,
                    *const c_char,
                ),
                Logger,
            >(logger)
        }),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    }
}

fn instantiate(dir: &Path, guid: &str, cb: &CallbackFunctions) -> *mut c_void {
    let uri = CString::new(format!("file://{}", dir.join("resources").display())).unwrap();
    let guid = CString::new(guid).unwrap();
    unsafe { fmi2Instantiate(c"m".as_ptr(), 1, guid.as_ptr(), uri.as_ptr(), cb, 0, 0) }
}

fn get(c: *mut c_void, vrs: &[u32]) -> Vec<f64> {
    let mut out = vec![0.0; vrs.len()];
    assert_eq!(
        unsafe { fmi2GetReal(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) },
        OK
    );
    out
}

fn vrs_of(names: &[(String, Kind)], kind: Kind) -> Vec<u32> {
    (0..names.len() as u32)
        .filter(|&i| names[i as usize].1 == kind)
        .collect()
}

#[test]
fn the_double_pendulum_steps_as_the_runtime_runs_it() {
    let (dir, guid, names) = unpacked(
        "double_pendulum_3d.dae",
        Config::new("DoublePendulum3D", 1e-3, 2.0),
        "dp",
    );
    let cb = callbacks();
    let c = instantiate(&dir, &guid, &cb);
    assert!(!c.is_null(), "{:?}", LOG.lock().unwrap());
    let h = 1.0 / 60.0;
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 1.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
    }
    let states = vrs_of(&names, Kind::State);
    let algs = vrs_of(&names, Kind::Alg);
    let errors = vrs_of(&names, Kind::Error);

    // The oracle: the simulator itself, with the online settings and the same cuts.
    let src = std::fs::read_to_string(models().join("double_pendulum_3d.dae")).unwrap();
    let model = Interpreted::from_compiled(
        dae_lang::compile_source(&src).unwrap().remove(0),
        &Default::default(),
    )
    .expect("constructed at its sizes");
    let mut settings = Online::frame(h).settings(vec![1e-3; 2]).unwrap().t_end(1.0);
    let (mut x0, mut z0) = (vec![0.0; model.n_states()], vec![0.0; 2]);
    model.initial_state(&mut x0);
    model.initial_alg(&mut z0);
    let z0 = consistent_start(&model, 0.0, &x0, &z0).unwrap().z0;
    settings = settings.initial(x0, z0);
    let mut sim = Simulator::new(&model, settings).unwrap();
    sim.start(&mut NoTrace).unwrap();

    let mut t = 0.0;
    for k in 1..=60 {
        let next = k as f64 * h;
        assert_eq!(unsafe { fmi2DoStep(c, t, next - t, 1) }, OK, "step {k}");
        sim.advance_to(t + (next - t), &mut NoTrace).unwrap();
        assert_eq!(get(c, &states), sim.state(), "states at step {k}");
        assert_eq!(get(c, &algs), sim.alg(), "algebraic unknowns at step {k}");
        // The errors are each constraint's w (its g(t, x)) at the oracle's point.
        let (mut w, mut s, mut ah) = (vec![0.0; 6], vec![0.0; 2], vec![0.0; 2]);
        model.sliding(
            sim.time(),
            sim.state(),
            sim.alg(),
            &[1.0; 2],
            &mut w,
            &mut s,
            &mut ah,
        );
        assert_eq!(
            get(c, &errors),
            [w[0], w[3]],
            "constraint errors at step {k}"
        );
        t = next;
    }
    // Fixed parameters are refused once running; stepping past the stop is an error.
    unsafe {
        let eps = [1e-2];
        assert_eq!(fmi2SetReal(c, [0u32].as_ptr(), 1, eps.as_ptr()), ERROR);
        assert_eq!(fmi2DoStep(c, t, h, 1), ERROR);
        // Reset: back to the state after instantiation, and the same run again.
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 1.0), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        assert_eq!(fmi2DoStep(c, 0.0, h, 1), OK);
        fmi2FreeInstance(c);
    }
    let log = LOG.lock().unwrap();
    assert!(
        log.iter()
            .any(|(s, m)| *s == ERROR && m.contains("fixed parameter")),
        "{log:?}"
    );
}

#[test]
fn a_pin_that_jumps_is_a_lost_layer_reported_as_a_warning() {
    let mut config = Config::new("Chain", 1e-3, 1.0);
    config.sets = vec![("N".into(), 10.0)];
    let (dir, guid, names) = unpacked("chain.dae", config, "chain");
    let pin_x = names.iter().position(|(n, _)| n == "pin[0].x").unwrap() as u32;
    let cb = callbacks();
    let c = instantiate(&dir, &guid, &cb);
    assert!(!c.is_null());
    let h = 1.0 / 60.0;
    let mut statuses = Vec::new();
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 1.0), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        let mut t = 0.0;
        for k in 1..=30 {
            if k == 20 {
                // The pin jumps 5 cm: link 0 is suddenly 5 cm too long.
                let v = [0.05];
                assert_eq!(fmi2SetReal(c, [pin_x].as_ptr(), 1, v.as_ptr()), OK);
            }
            let next = k as f64 * h;
            statuses.push(fmi2DoStep(c, t, next - t, 1));
            t = next;
        }
        fmi2FreeInstance(c);
    }
    assert!(statuses[..19].iter().all(|&s| s == OK), "{statuses:?}");
    assert_eq!(statuses[19], WARNING, "{statuses:?}");
    assert!(statuses[20..].iter().all(|&s| s == OK), "{statuses:?}");
    let log = LOG.lock().unwrap();
    assert!(
        log.iter().any(|(s, m)| *s == WARNING
            && m.contains("the layer was left")
            && m.contains("link[0]")),
        "{log:?}"
    );
}

#[test]
fn a_wrong_guid_or_a_missing_resource_is_refused_with_its_reason() {
    let (dir, _guid, _) = unpacked(
        "double_pendulum_3d.dae",
        Config::new("DoublePendulum3D", 1e-3, 1.0),
        "guid",
    );
    let cb = callbacks();
    assert!(instantiate(&dir, "{not-this}", &cb).is_null());
    assert!(instantiate(&dir.join("nowhere"), "{x}", &cb).is_null());
    let log = LOG.lock().unwrap();
    assert!(
        log.iter().any(|(_, m)| m.contains("is not this FMU's")),
        "{log:?}"
    );
    assert!(log.iter().any(|(_, m)| m.contains("reading")), "{log:?}");
}
