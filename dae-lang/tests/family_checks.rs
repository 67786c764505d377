//! Family models against independent oracles: their scalar versions (chain5 and the 3-D
//! double pendulum written as families agree with the version-1 examples at matching
//! points), the closed form of a particle system's J_Omega (docs/method.md section 7,
//! the pinned cases included), finite differences of J_Omega and beta, and the
//! examples' starts (nonsingular once expanded, which the runtime's check needs).

use dae_lang::family::{Instance, Program, Scratch, Spec, Values, construct, expand};
use dae_lang::{AnalysisOptions, CompiledModel, analyze, compile};

mod common;
use common::{Rng, close, models_dir};

fn example(name: &str) -> String {
    std::fs::read_to_string(models_dir().join(name)).expect("example model")
}

fn compiled(src: &str) -> CompiledModel {
    let models = dae_lang::check_source(src).unwrap_or_else(|e| panic!("{e:#?}"));
    let a = analyze(&models[0], &AnalysisOptions::default()).unwrap_or_else(|e| panic!("{e:#?}"));
    compile(&a)
}

fn instance(c: &CompiledModel, spec: &Spec) -> Instance {
    construct(&c.programs.construction, spec).unwrap_or_else(|e| panic!("{e}"))
}

/// A point of evaluation in an instance's layout.
#[derive(Clone)]
struct Point {
    params: Vec<f64>,
    states: Vec<f64>,
    algs: Vec<f64>,
    /// `z' = 0`: the rate program gives `beta` with it.
    held: Vec<f64>,
    mu: Vec<f64>,
    inputs: Vec<f64>,
    t: f64,
}

impl Point {
    fn values(&self) -> Values<'_> {
        Values {
            params: &self.params,
            states: &self.states,
            algs: &self.algs,
            alg_rates: &self.held,
            mu: &self.mu,
            inputs: &self.inputs,
            t: self.t,
        }
    }

    fn random(inst: &Instance, rng: &mut Rng, spread: f64) -> Point {
        Point {
            params: inst.params.clone(),
            states: inst
                .states
                .iter()
                .map(|x| x + rng.uniform(-spread, spread))
                .collect(),
            algs: inst.algs.iter().map(|_| rng.uniform(-1.0, 1.0)).collect(),
            held: vec![0.0; inst.algs.len()],
            mu: (0..inst.layout.n_rows)
                .map(|_| rng.uniform(0.01, 0.2))
                .collect(),
            inputs: inst
                .inputs
                .iter()
                .map(|x| x + rng.uniform(-spread, spread))
                .collect(),
            t: rng.uniform(0.0, 1.0),
        }
    }
}

fn run(p: &Program, inst: &Instance, x: &Point, lens: &[usize]) -> Vec<Vec<f64>> {
    let mut outs: Vec<Vec<f64>> = lens.iter().map(|&n| vec![f64::NAN; n]).collect();
    let mut refs: Vec<&mut [f64]> = outs.iter_mut().map(|v| v.as_mut_slice()).collect();
    let mut scratch = Scratch::new(p, inst);
    p.eval(inst, &x.values(), &mut scratch, &mut refs);
    outs
}

/// J_Omega of an instance at a point, dense (rows x columns).
fn jacobian(c: &CompiledModel, inst: &Instance, x: &Point) -> Vec<Vec<f64>> {
    let f = &c.programs;
    let values = run(&f.jacobian, inst, x, &[inst.jacobian.entries.len()]).remove(0);
    let mut j = vec![vec![0.0; inst.layout.n_algs]; inst.layout.n_rows];
    for (&(r, col), v) in inst.jacobian.entries.iter().zip(values) {
        j[r][col] = v;
    }
    j
}

/// `Omega` of every row (the last derivative of w).
fn omega(c: &CompiledModel, inst: &Instance, x: &Point) -> Vec<f64> {
    let f = &c.programs;
    let l = &inst.layout;
    let w = run(&f.sliding, inst, x, &[l.n_w, l.n_rows, l.n_rows]).remove(0);
    let mut out = Vec::with_capacity(l.n_rows);
    for (k, info) in f.construction.constraints.iter().enumerate() {
        for e in 0..inst.set_size(info.over) {
            out.push(w[l.w[k].at(e) + info.index - 1]);
        }
    }
    out
}

#[test]
fn particle_jacobian_has_the_closed_form_of_the_method() {
    // docs/method.md section 7: off the diagonal, links i and j sharing particle c give
    // -(rhat_ci . rhat_cj) / m_c (rhat_ci: the unit vector from c along link i); on the
    // diagonal -(1/m_a + 1/m_b), -1/m_free when one end is pinned. A pinned particle
    // (free = 0) contributes nothing: those cases come out of `free`, not written by hand.
    for (file, spec) in [
        ("chain.dae", vec![("N".to_string(), 6)]),
        ("hair.dae", vec![("S".to_string(), 3), ("N".to_string(), 4)]),
        ("cloth.dae", vec![("W".to_string(), 4)]),
    ] {
        let c = compiled(&example(file));
        let spec = Spec {
            sizes: spec,
            ..Spec::default()
        };
        let inst = instance(&c, &spec);
        let mut rng = Rng::new(3);
        let x = Point::random(&inst, &mut rng, 0.05);
        let j = jacobian(&c, &inst, &x);
        // Positions, masses and pins of the particles, ends of the links (layout: x
        // first, three components per particle; params m / mass and free).
        let f = &c.programs;
        let cons = &f.construction;
        let find = |name: &str| cons.params.iter().position(|p| p.name == name);
        let free_p = find("free").expect("free");
        let mass = |p: usize| match find("m") {
            Some(i) => x.params[inst.layout.params[i].at(p)],
            None => x.params[inst.layout.params[find("mass").expect("mass")].at(0)],
        };
        let free = |p: usize| x.params[inst.layout.params[free_p].at(p)];
        let map =
            |name: &str| &inst.maps[cons.maps.iter().position(|m| m.name == name).expect("map")];
        let (a, b) = (map("a"), map("b"));
        // X = free x + (1 - free) pin: position of particle p.
        let pin = cons.inputs.iter().position(|i| i.name == "pin.x");
        let head = cons.inputs.iter().position(|i| i.name == "head.x");
        let pos = |p: usize| -> [f64; 3] {
            let mut r = [0.0; 3];
            for (k, rk) in r.iter_mut().enumerate() {
                let xs = x.states[inst.layout.states[k].at(p)];
                let pinned = match (pin, head) {
                    (Some(i), _) => x.inputs[inst.layout.input_values[i + k].at(p)],
                    (None, Some(h)) => {
                        let radius = x.params[inst.layout.params[find("R").unwrap()].at(0)];
                        let dir = x.params[inst.layout.params[find("dir.x").unwrap() + k].at(p)];
                        x.inputs[inst.layout.input_values[h + k].at(0)] + radius * dir
                    }
                    _ => 0.0,
                };
                *rk = free(p) * xs + (1.0 - free(p)) * pinned;
            }
            r
        };
        let unit = |from: usize, to: usize| {
            let (p, q) = (pos(from), pos(to));
            let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            [d[0] / n, d[1] / n, d[2] / n]
        };
        let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        let nl = a.len();
        for i in 0..nl {
            for k in 0..nl {
                let (ai, bi, ak, bk) = (a[i] as usize, b[i] as usize, a[k] as usize, b[k] as usize);
                let expected = if i == k {
                    -(free(ai) / mass(ai) + free(bi) / mass(bi))
                } else {
                    let mut v = 0.0;
                    for cpart in [ai, bi] {
                        if cpart == ak || cpart == bk {
                            let other_i = if cpart == ai { bi } else { ai };
                            let other_k = if cpart == ak { bk } else { ak };
                            v -= dot(unit(cpart, other_i), unit(cpart, other_k)) * free(cpart)
                                / mass(cpart);
                        }
                    }
                    v
                };
                assert!(
                    close(j[i][k], expected, 1e-10),
                    "{file}: J({i}, {k}) = {} but the closed form gives {expected}",
                    j[i][k]
                );
            }
        }
    }
}

#[test]
fn jacobian_and_beta_match_finite_differences() {
    // The cloth with shear springs and moving pins (the inputs' derivatives are not zero).
    let c = compiled(&example("cloth.dae"));
    let spec = Spec {
        sizes: vec![("W".into(), 4)],
        params: vec![("k_shear".into(), 30.0)],
        ..Spec::default()
    };
    let inst = instance(&c, &spec);
    let f = &c.programs;
    let mut rng = Rng::new(11);
    let x = Point::random(&inst, &mut rng, 0.05);
    // J_Omega = dOmega/dz (central differences).
    let j = jacobian(&c, &inst, &x);
    let h = 1e-6;
    for k in 0..inst.layout.n_algs {
        let (mut up, mut down) = (x.clone(), x.clone());
        up.algs[k] += h;
        down.algs[k] -= h;
        let (o1, o0) = (omega(&c, &inst, &up), omega(&c, &inst, &down));
        for (r, row) in j.iter().enumerate() {
            let fd = (o1[r] - o0[r]) / (2.0 * h);
            assert!(
                close(row[k], fd, 1e-5),
                "J({r}, {k}) = {} vs finite difference {fd}",
                row[k]
            );
        }
    }
    // beta = d/dt Omega along the flow with z fixed: t, x along f, inputs along their
    // Taylor polynomials.
    let l = &inst.layout;
    let rhs = run(&f.rhs, &inst, &x, &[l.n_states]).remove(0);
    let beta = run(&f.rate, &inst, &x, &[l.n_rows]).remove(0);
    let moved = |s: f64| {
        let mut p = x.clone();
        p.t += s;
        for (xi, fi) in p.states.iter_mut().zip(&rhs) {
            *xi += s * fi;
        }
        for (i, input) in f.construction.inputs.iter().enumerate() {
            let k = input.derivatives as usize;
            for e in 0..inst.set_size(input.family.over) {
                let d: Vec<f64> = (0..=k)
                    .map(|j| x.inputs[l.input_value(i, j).at(e)])
                    .collect();
                for j in 0..=k {
                    // Taylor: value j at t + s.
                    let mut v = 0.0;
                    let mut fact = 1.0;
                    for (q, dq) in d.iter().enumerate().skip(j) {
                        if q > j {
                            fact *= (q - j) as f64;
                        }
                        v += dq * s.powi((q - j) as i32) / fact;
                    }
                    p.inputs[l.input_value(i, j).at(e)] = v;
                }
            }
        }
        p
    };
    let h = 1e-6;
    let (o1, o0) = (omega(&c, &inst, &moved(h)), omega(&c, &inst, &moved(-h)));
    for (r, b) in beta.iter().enumerate() {
        let fd = (o1[r] - o0[r]) / (2.0 * h);
        assert!(
            close(*b, fd, 1e-4),
            "beta[{r}] = {b} vs finite difference {fd}"
        );
    }
    assert!(
        beta.iter().any(|b| b.abs() > 1e-3),
        "beta is exercised: {beta:?}"
    );
}

/// The entries of `J_Omega` of a model without sets, in the order of its values.
fn scalar_pattern(c: &CompiledModel) -> Vec<(usize, usize)> {
    construct(&c.programs.construction, &Spec::default())
        .expect("a model without sets builds")
        .jacobian
        .entries
}

/// Evaluates a version-1 compiled model (all functions: its programs, scheduled
/// without sets) at a point: `rhs`, `w ++ s ++ alpha_hat`, the values of `J_Omega` at
/// [`scalar_pattern`], `beta`.
fn scalar_outputs(
    c: &CompiledModel,
    params: &[f64],
    x: &[f64],
    z: &[f64],
    mu: &[f64],
    t: f64,
) -> Vec<Vec<f64>> {
    let inst = construct(&c.programs.construction, &Spec::default()).expect("builds");
    let l = &inst.layout;
    let zero = vec![0.0; l.n_algs];
    let run = |prog: &Program, alg_rates: &[f64], lens: &[usize]| {
        let v = Values {
            params,
            states: x,
            algs: z,
            alg_rates,
            mu,
            inputs: &[],
            t,
        };
        let mut outs: Vec<Vec<f64>> = lens.iter().map(|&n| vec![0.0; n]).collect();
        let mut refs: Vec<&mut [f64]> = outs.iter_mut().map(|o| o.as_mut_slice()).collect();
        prog.eval(&inst, &v, &mut Scratch::new(prog, &inst), &mut refs);
        outs.concat()
    };
    let p = &c.programs;
    vec![
        run(&p.rhs, &[], &[l.n_states]),
        run(&p.sliding, &[], &[l.n_w, l.n_rows, l.n_rows]),
        run(&p.jacobian, &[], &[inst.jacobian.entries.len()]),
        run(&p.rate, &zero, &[l.n_rows]),
    ]
}

/// A family model and its scalar version agree: states matched by name (`scalar(name)`
/// gives the scalar name of a family state component element, or `None` for a state the
/// scalar version does not have), constraints and unknowns in the same order.
fn agree(family_file: &str, scalar_file: &str, scalar: impl Fn(&str) -> Option<String>) {
    let c = compiled(&example(family_file));
    let s = compiled(&example(scalar_file));
    let inst = instance(&c, &Spec::default());
    let f = &c.programs;
    let l = &inst.layout;
    // The family's state names in layout order, mapped to the scalar ones.
    let mut names = vec![String::new(); l.n_states];
    for (k, st) in f.construction.states.iter().enumerate() {
        for e in 0..inst.set_size(st.family.over) {
            let (base, comp) = st.name.split_once('.').unwrap_or((&st.name, ""));
            names[l.states[k].at(e)] = format!("{base}[{e}].{comp}");
        }
    }
    let index: Vec<Option<usize>> = names
        .iter()
        .map(|n| {
            scalar(n).map(|sn| {
                s.states
                    .iter()
                    .position(|x| *x == sn)
                    .unwrap_or_else(|| panic!("{sn}"))
            })
        })
        .collect();
    assert_eq!(
        index.iter().flatten().count(),
        s.states.len(),
        "every scalar state is matched"
    );
    assert_eq!(l.n_rows, s.constraints.len());
    let mut rng = Rng::new(5);
    for _ in 0..5 {
        let mut x = Point::random(&inst, &mut rng, 0.3);
        // The states the scalar version does not have keep their initial values.
        for (i, ix) in index.iter().enumerate() {
            if ix.is_none() {
                x.states[i] = inst.states[i];
            }
        }
        x.inputs = inst.inputs.iter().map(|_| 0.0).collect();
        let mut sx = vec![0.0; s.states.len()];
        for (i, ix) in index.iter().enumerate() {
            if let Some(j) = ix {
                sx[*j] = x.states[i];
            }
        }
        let sp: Vec<f64> = s.params.iter().map(|p| p.1).collect();
        let so = scalar_outputs(&s, &sp, &sx, &x.algs, &x.mu, x.t);
        let rhs = run(&f.rhs, &inst, &x, &[l.n_states]).remove(0);
        for (i, ix) in index.iter().enumerate() {
            if let Some(j) = ix {
                assert!(
                    close(rhs[i], so[0][*j], 1e-12),
                    "der({}) {} vs {}",
                    names[i],
                    rhs[i],
                    so[0][*j]
                );
            }
        }
        let sl = run(&f.sliding, &inst, &x, &[l.n_w, l.n_rows, l.n_rows]);
        let flat: Vec<f64> = sl.concat();
        for (a, b) in flat.iter().zip(&so[1]) {
            assert!(close(*a, *b, 1e-12), "sliding {flat:?} vs {:?}", so[1]);
        }
        let j = jacobian(&c, &inst, &x);
        for (k, &(r, col)) in scalar_pattern(&s).iter().enumerate() {
            assert!(
                close(j[r][col], so[2][k], 1e-12),
                "J({r}, {col}) {} vs {}",
                j[r][col],
                so[2][k]
            );
        }
        let beta = run(&f.rate, &inst, &x, &[l.n_rows]).remove(0);
        for (a, b) in beta.iter().zip(&so[3]) {
            assert!(close(*a, *b, 1e-12), "beta {beta:?} vs {:?}", so[3]);
        }
    }
}

#[test]
fn chain5_family_agrees_with_chain5_planar() {
    // Family particle k is scalar particle k (1..5); particle 0 is the pin.
    agree("chain5_family.dae", "chain5_planar.dae", |n| {
        let (base, rest) = n.split_once('[')?;
        let (k, comp) = rest.split_once("].")?;
        let k: usize = k.parse().ok()?;
        if k == 0 {
            return None;
        }
        Some(match (base, comp) {
            ("x", "x") => format!("x{k}"),
            ("x", "y") => format!("y{k}"),
            ("v", "x") => format!("vx{k}"),
            _ => format!("vy{k}"),
        })
    });
}

#[test]
fn double_pendulum_family_agrees_with_the_3d_double_pendulum() {
    // Family particle k is R_k (k = 1, 2); particle 0 is the pivot (an input at rest).
    agree(
        "double_pendulum_family.dae",
        "double_pendulum_3d.dae",
        |n| {
            let (base, rest) = n.split_once('[')?;
            let (k, comp) = rest.split_once("].")?;
            let k: usize = k.parse().ok()?;
            if k == 0 {
                return None;
            }
            Some(match base {
                "x" => format!("p{k}{comp}"),
                _ => format!("v{k}{comp}"),
            })
        },
    );
}

#[test]
fn the_family_examples_start_nonsingular() {
    // The runtime refuses a singular J_Omega at the start; expanded at small sizes and
    // analysed by the version-1 pipeline (which checks the initial point), every family
    // example passes.
    for (file, sizes) in [
        ("chain.dae", vec![("N".to_string(), 8)]),
        ("hair.dae", vec![("S".to_string(), 4), ("N".to_string(), 5)]),
        ("cloth.dae", vec![("W".to_string(), 6)]),
        ("chain5_family.dae", vec![]),
        ("double_pendulum_family.dae", vec![]),
    ] {
        let src = example(file);
        let models = dae_lang::check_source(&src).unwrap();
        let c = compiled(&src);
        let inst = instance(
            &c,
            &Spec {
                sizes,
                ..Spec::default()
            },
        );
        let e = expand(&models[0], &inst);
        let a = analyze(&e.model, &AnalysisOptions::default())
            .unwrap_or_else(|d| panic!("{file}: {}", d[0].message));
        assert!(
            a.condition_number.is_finite() && a.condition_number < 1e9,
            "{file}: cond {}",
            a.condition_number
        );
    }
}

#[test]
fn input_values_are_derivative_major() {
    // All values of an input declaration (element-major, components interleaved), then
    // all its first derivatives, ...: a function that reads only the values streams one
    // contiguous block. Checked on the slots and on the expanded model's names of them.
    for (file, sizes, n, name) in [
        ("chain.dae", vec![("N".to_string(), 3)], 4, "pin"),
        (
            "hair.dae",
            vec![("S".to_string(), 2), ("N".to_string(), 2)],
            1,
            "head",
        ),
    ] {
        let src = example(file);
        let models = dae_lang::check_source(&src).unwrap();
        let c = compiled(&src);
        let inst = instance(
            &c,
            &Spec {
                sizes,
                ..Spec::default()
            },
        );
        let l = &inst.layout;
        let cons = &c.programs.construction;
        let first = cons
            .inputs
            .iter()
            .position(|i| i.name == format!("{name}.x"));
        let first = first.expect("the input");
        assert_eq!(l.n_input_values, 4 * 3 * n, "{file}");
        let ex = expand(&models[0], &inst);
        let mut seen = vec![false; l.n_input_values];
        for (k, comp) in ["x", "y", "z"].into_iter().enumerate() {
            for j in 0..=3 {
                for e in 0..n {
                    let at = l.input_value(first + k, j).at(e);
                    assert_eq!(
                        at,
                        j * 3 * n + 3 * e + k,
                        "{file}: {name}[{e}].{comp} ({j})"
                    );
                    assert!(!seen[at], "{file}: slot {at} twice");
                    seen[at] = true;
                    let primes = "'".repeat(j);
                    let want = if n == 1 {
                        format!("{name}{primes}.{comp}")
                    } else {
                        format!("{name}{primes}[{e}].{comp}")
                    };
                    assert_eq!(ex.model.params[ex.input_params + at].name, want);
                }
            }
        }
    }
}
