//! The Rust kernels generated for every family example (compiled here through
//! `dae_runtime::dae_file!`) against the interpreter of the same compiled programs
//! (`dae_lang::family::Program::eval`): at random points (with a random `z'` for the
//! rate program), every output of every function agrees to 1e-12, at sizes 1..6 and
//! one larger size. The generated
//! `construction()` is the compiler's `Construction`, value for value.

use dae_lang::family::{Construction, FamilyModel, Instance, Program, Scratch, Spec, Values};
use dae_runtime::family::Kernels;
use dae_tests::{Rng, close};

mod generated {
    dae_runtime::dae_file!("../examples/models/chain.dae");
    dae_runtime::dae_file!("../examples/models/chain5_family.dae");
    dae_runtime::dae_file!("../examples/models/cloth.dae");
    dae_runtime::dae_file!("../examples/models/double_pendulum_family.dae");
    dae_runtime::dae_file!("../examples/models/hair.dae");
    dae_runtime::dae_file!("models/yz_chain.dae");
    dae_runtime::dae_file!("models/beads_mass.dae");
}

/// The compiled family model of an example file.
fn compiled(stem: &str) -> FamilyModel {
    compiled_at(&dae_tests::models_dir().join(format!("{stem}.dae")))
}

/// The compiled family model of a file.
fn compiled_at(path: &std::path::Path) -> FamilyModel {
    let stem = path.file_stem().expect("a file").to_string_lossy();
    let src = std::fs::read_to_string(path).expect("model file");
    let mut models = dae_lang::compile_source(&src).unwrap_or_else(|e| panic!("{stem}: {e:?}"));
    *models.remove(0).programs
}

/// One evaluation's vectors.
struct Point {
    params: Vec<f64>,
    states: Vec<f64>,
    algs: Vec<f64>,
    /// The direction of the unknowns for `Omega'`.
    zdot: Vec<f64>,
    mu: Vec<f64>,
    inputs: Vec<f64>,
    t: f64,
}

impl Point {
    /// Near the instance's start: the parameters as constructed (a pinned particle stays
    /// pinned), states, inputs and unknowns perturbed, `mu` in (0.1, 1).
    fn random(inst: &Instance, rng: &mut Rng) -> Point {
        let jiggle = |v: &[f64], rng: &mut Rng| -> Vec<f64> {
            v.iter().map(|x| x + rng.uniform(-0.1, 0.1)).collect()
        };
        Point {
            params: inst.params.clone(),
            states: jiggle(&inst.states, rng),
            algs: inst.algs.iter().map(|_| rng.uniform(-2.0, 2.0)).collect(),
            zdot: inst.algs.iter().map(|_| rng.uniform(-3.0, 3.0)).collect(),
            mu: (0..inst.layout.n_rows)
                .map(|_| rng.uniform(0.1, 1.0))
                .collect(),
            inputs: jiggle(&inst.inputs, rng),
            t: rng.uniform(0.0, 1.0),
        }
    }

    fn values(&self) -> Values<'_> {
        Values {
            params: &self.params,
            states: &self.states,
            algs: &self.algs,
            alg_rates: &self.zdot,
            mu: &self.mu,
            inputs: &self.inputs,
            t: self.t,
        }
    }
}

/// Every output of the four functions, `(function, outputs)`, from the interpreter.
fn interpreted(f: &FamilyModel, inst: &Instance, v: &Values<'_>) -> Vec<(&'static str, Vec<f64>)> {
    let l = &inst.layout;
    let run = |p: &Program, lens: &[usize]| -> Vec<f64> {
        let mut outs: Vec<Vec<f64>> = lens.iter().map(|&n| vec![f64::NAN; n]).collect();
        let mut scratch = Scratch::new(p, inst);
        let mut refs: Vec<&mut [f64]> = outs.iter_mut().map(|o| o.as_mut_slice()).collect();
        p.eval(inst, v, &mut scratch, &mut refs);
        outs.concat()
    };
    let nj = inst.jacobian.entries.len();
    vec![
        ("rhs", run(&f.rhs, &[l.n_states])),
        ("sliding", run(&f.sliding, &[l.n_w, l.n_rows, l.n_rows])),
        ("jacobian", run(&f.jacobian, &[nj])),
        ("rate", run(&f.rate, &[l.n_rows])),
    ]
}

/// The same from generated kernels; outputs start as NaN, so a slot never written
/// shows.
fn generated<K: Kernels>(k: &K, inst: &Instance, v: &Values<'_>) -> Vec<(&'static str, Vec<f64>)> {
    let l = &inst.layout;
    let mut scratch = k.scratch(inst);
    let nan = |n: usize| vec![f64::NAN; n];
    let mut dx = nan(l.n_states);
    k.rhs(inst, v, &mut scratch, &mut dx);
    let (mut w, mut s, mut ah) = (nan(l.n_w), nan(l.n_rows), nan(l.n_rows));
    k.sliding(inst, v, &mut scratch, &mut w, &mut s, &mut ah);
    let mut jac = nan(inst.jacobian.entries.len());
    k.jacobian(inst, v, &mut scratch, &mut jac);
    let mut rate = nan(l.n_rows);
    k.omega_rate(inst, v, &mut scratch, &mut rate);
    // Twice: the scratch carries nothing from one evaluation to the next.
    k.omega_rate(inst, v, &mut scratch, &mut rate);
    vec![
        ("rhs", dx),
        ("sliding", [w, s, ah].concat()),
        ("jacobian", jac),
        ("rate", rate),
    ]
}

/// Generated against interpreted at `points` random points of each size.
fn agree<K: Kernels>(stem: &str, kernels: &K, sizes: &[Vec<(&str, i64)>], points: usize) {
    agree_on(stem, &compiled(stem), kernels, sizes, points);
}

/// The same for the compiled model `f`.
fn agree_on<K: Kernels>(
    stem: &str,
    f: &FamilyModel,
    kernels: &K,
    sizes: &[Vec<(&str, i64)>],
    points: usize,
) {
    // As text: a per-element parameter's default is NaN, which `==` never equals.
    assert!(
        format!("{:?}", kernels.construction()) == format!("{:?}", f.construction),
        "{stem}: the generated construction differs from the compiler's"
    );
    let mut rng = Rng::new(0x5eed_0000 + stem.len() as u64);
    for size in sizes {
        let spec = Spec {
            sizes: size.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
            ..Spec::default()
        };
        let inst = dae_lang::family::construct(&f.construction, &spec)
            .unwrap_or_else(|e| panic!("{stem} at {size:?}: {e}"));
        for _ in 0..points {
            let p = Point::random(&inst, &mut rng);
            let v = p.values();
            let want = interpreted(f, &inst, &v);
            let got = generated(kernels, &inst, &v);
            for ((name, a), (_, b)) in want.iter().zip(&got) {
                assert_eq!(a.len(), b.len(), "{stem} {size:?} {name}: lengths");
                assert!(
                    !a.is_empty() || *name == "jacobian",
                    "{stem} {name}: no outputs"
                );
                for (i, (x, y)) in a.iter().zip(b).enumerate() {
                    assert!(
                        x.is_finite() && close(*x, *y, 1e-12),
                        "{stem} at {size:?}: {name}[{i}]: interpreter {x}, generated {y}"
                    );
                }
            }
        }
    }
}

/// `name = 1..=6` and `name = big`.
fn sizes(name: &'static str, big: i64) -> Vec<Vec<(&'static str, i64)>> {
    (1..=6).chain([big]).map(|n| vec![(name, n)]).collect()
}

#[test]
fn chain_kernels_agree_with_the_interpreter() {
    agree("chain", &generated::Chain::kernels(), &sizes("N", 300), 3);
}

#[test]
fn chain5_family_kernels_agree_with_the_interpreter() {
    agree(
        "chain5_family",
        &generated::Chain5Family::kernels(),
        &sizes("N", 300),
        3,
    );
}

#[test]
fn cloth_kernels_agree_with_the_interpreter() {
    // A cloth needs two particles a side.
    let sizes: Vec<_> = (2..=7).chain([20]).map(|w| vec![("W", w)]).collect();
    agree("cloth", &generated::Cloth::kernels(), &sizes, 3);
}

#[test]
fn hair_kernels_agree_with_the_interpreter() {
    let mut sizes: Vec<Vec<(&str, i64)>> = (1..=6).map(|n| vec![("S", 2), ("N", n)]).collect();
    sizes.extend((1..=6).map(|s| vec![("S", s), ("N", 3)]));
    sizes.push(vec![("S", 20), ("N", 16)]);
    agree("hair", &generated::Hair::kernels(), &sizes, 3);
}

/// A model that reads only the second and third components of a vector family (the
/// generated code takes them as one array starting a component before the first one
/// read) and writes a vector's derivatives in two loops, partly in each.
#[test]
fn yz_chain_kernels_that_read_from_the_second_component_agree_with_the_interpreter() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/yz_chain.dae");
    let f = compiled_at(&path);
    agree_on(
        "yz_chain",
        &f,
        &generated::YzChain::kernels(),
        &sizes("N", 300),
        3,
    );
}

/// A 2 x 2 mass matrix per element (`tests/models/beads_mass.dae`): the eliminated
/// derivatives in the kernels.
#[test]
fn per_element_mass_matrix_kernels_agree_with_the_interpreter() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/beads_mass.dae");
    let f = compiled_at(&path);
    agree_on(
        "beads_mass",
        &f,
        &generated::Beads::kernels(),
        &sizes("N", 100),
        3,
    );
}

#[test]
fn double_pendulum_family_kernels_agree_with_the_interpreter() {
    // Fixed sets (no sizes): the default instance only.
    agree(
        "double_pendulum_family",
        &generated::DoublePendulumFamily::kernels(),
        &[vec![]],
        20,
    );
}

/// The generated construction is a `Construction` the runtime can build from: every
/// example's default instance builds, as the compiler's does.
#[test]
fn generated_construction_builds_the_default_instance() {
    let c: Construction = generated::Chain::construction_data();
    let inst = dae_lang::family::construct(&c, &Spec::default()).expect("default chain");
    assert_eq!(inst.set_sizes, [11, 10]);
}

/// Item 2 end to end: `Chain::new(&spec)` (the runtime's sized family model over the
/// generated kernels) and the same model over the runtime's interpreter agree through
/// the `Model` trait (names, pattern, every function) with an input set, at N = 10 and
/// N = 1000, from one compiled binary.
#[test]
fn generated_chain_model_agrees_with_the_interpreted_one() {
    use dae_runtime::Model;
    use dae_runtime::family::{FamilyInstance, Interpreter};
    for n in [10, 1000] {
        let spec = Spec {
            sizes: vec![("N".into(), n)],
            params: vec![("m_end".into(), 5.0)],
            ..Spec::default()
        };
        let mut code = generated::Chain::new(&spec).expect("chain");
        let src = std::fs::read_to_string(dae_tests::models_dir().join("chain.dae")).unwrap();
        let interp = Interpreter::new(dae_lang::compile_source(&src).unwrap().remove(0));
        let mut oracle = FamilyInstance::new(interp, &spec).expect("chain");
        assert_eq!(code.name(), "Chain");
        assert_eq!(code.n_states(), 6 * (n as usize + 1));
        assert_eq!(code.n_constraints(), n as usize);
        assert_eq!(code.jacobian_pattern(), oracle.jacobian_pattern());
        assert_eq!(code.state_name(4), oracle.state_name(4));
        // Pin particle 0 to a moving point (value and 3 derivatives): both read it.
        let pin = code.input_index_at("pin.x", 0).expect("pin.x[0]");
        for m in [&mut code as &mut dyn PinInput, &mut oracle] {
            m.pin(pin, &[0.01, 0.2, -0.3, 0.4]);
        }
        let mut rng = Rng::new(n as u64);
        let mut x = vec![0.0; code.n_states()];
        code.initial_state(&mut x);
        for v in &mut x {
            *v += rng.uniform(-0.01, 0.01);
        }
        let k = code.n_constraints();
        let z: Vec<f64> = (0..k).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let mu: Vec<f64> = (0..k).map(|_| rng.uniform(0.1, 1.0)).collect();
        let nw: usize = code.indices().iter().sum();
        let eval = |m: &dyn Model| {
            let mut dx = vec![0.0; m.n_states()];
            m.rhs(0.3, &x, &z, &mut dx);
            let (mut w, mut s, mut ah) = (vec![0.0; nw], vec![0.0; k], vec![0.0; k]);
            m.sliding(0.3, &x, &z, &mu, &mut w, &mut s, &mut ah);
            let mut j = vec![0.0; m.jacobian_pattern().len()];
            m.jacobian(0.3, &x, &z, &mut j);
            let mut b = vec![0.0; k];
            m.beta(0.3, &x, &z, &mut b);
            [dx, w, s, ah, j, b].concat()
        };
        let (a, b) = (eval(&code), eval(&oracle));
        assert_eq!(a.len(), b.len());
        for (i, (p, q)) in a.iter().zip(&b).enumerate() {
            assert!(
                p.is_finite() && close(*p, *q, 1e-12),
                "N = {n}, output {i}: {p} vs {q}"
            );
        }
    }
}

/// Sets an input on either back end.
trait PinInput {
    fn pin(&mut self, i: usize, taylor: &[f64]);
}

impl<K: Kernels> PinInput for dae_runtime::family::FamilyInstance<K> {
    fn pin(&mut self, i: usize, taylor: &[f64]) {
        self.set_input(i, 0.0, taylor).expect("input set");
    }
}

mod inline {
    // The token front end (`dae!`) on a family model: a hanging chain of N planar links.
    dae_runtime::dae! {
        model TinyChain {
            size N = 3;
            set P = N + 1;
            set L = N;
            map a[l in L] -> P = l;
            map b[l in L] -> P = l + 1;
            param g = 9.81;
            param free[p in P] = if p == 0 then 0 else 1;
            state x[p in P]: vec2 = vec2(p, 0);
            state v[p in P]: vec2 = vec2(0, 0);
            alg z[l in L] = 0;
            let d[l in L] = x[b[l]] - x[a[l]];
            der(x[p]) = v[p];
            der(v[p]) = free[p] * (sum(l in L where a[l] == p) z[l] * d[l]
                                 - sum(l in L where b[l] == p) z[l] * d[l] + vec2(0, -g));
            constraint link[l in L]: dot(d[l], d[l]) = 1;
        }
    }
}

/// `dae!` on a family model gives the same kind of type as `dae_file!`, sized at run
/// time.
#[test]
fn dae_macro_compiles_a_family_model() {
    use dae_runtime::Model;
    for n in [1, 3, 50] {
        let spec = Spec {
            sizes: vec![("N".into(), n)],
            ..Spec::default()
        };
        let m = inline::TinyChain::new(&spec).expect("tiny chain");
        assert_eq!(m.n_states(), 4 * (n as usize + 1));
        assert_eq!(m.n_constraints(), n as usize);
        // A chain at rest with zero tensions: the free particles fall at g. States: x
        // (2 (N + 1) values, components interleaved), then v.
        let mut x = vec![0.0; m.n_states()];
        m.initial_state(&mut x);
        let mut dx = vec![0.0; m.n_states()];
        m.rhs(0.0, &x, &vec![0.0; m.n_constraints()], &mut dx);
        let v_y = |p: usize| 2 * (n as usize + 1) + 2 * p + 1;
        assert_eq!(dx[v_y(0)], 0.0, "the pinned particle does not move");
        assert_eq!(dx[v_y(n as usize)], -9.81);
    }
}
