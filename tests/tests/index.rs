//! Index analysis of models written as `.dae` text, against answers derived by hand (the
//! derivations are in the comments): indices, the algebraic unknowns in each `Omega`,
//! `Omega` and `J_Omega` at the initial point, and the errors for a constraint without an
//! index and for a singular `J_Omega`.

use dae_lang::{Analysis, AnalysisOptions, Diagnostic, Point, analyze, line_col};

fn analyse(src: &str) -> Result<Analysis, Vec<Diagnostic>> {
    let models = dae_lang::check_source(src).unwrap_or_else(|d| {
        panic!(
            "{}",
            d.iter()
                .map(|x| x.render("m.dae", src, false))
                .collect::<String>()
        )
    });
    assert_eq!(models.len(), 1);
    analyze(&models[0], &AnalysisOptions::default())
}

fn ok(src: &str) -> Analysis {
    analyse(src).unwrap_or_else(|d| {
        panic!(
            "{}",
            d.iter()
                .map(|x| x.render("m.dae", src, false))
                .collect::<String>()
        )
    })
}

/// A value of the analysis at the initial point.
fn at_initial(a: &Analysis, id: dae_lang::Id) -> f64 {
    a.symbolic().arena.eval(
        id,
        &Point {
            params: &a.initial.params,
            states: &a.initial.states,
            algs: &a.initial.algs,
            t: 0.0,
            mu: &[],
        },
    )
}

fn close(got: f64, want: f64) -> bool {
    (got - want).abs() <= 1e-12 * (1.0 + want.abs())
}

fn depends(a: &Analysis) -> Vec<Vec<&str>> {
    a.constraints
        .iter()
        .map(|c| c.depends_on.iter().map(String::as_str).collect())
        .collect()
}

#[test]
fn index_1_the_unknown_is_in_the_constraint() {
    // w = z^3 + z - x contains z: r = 1, Omega = w, J = dw/dz = 3 z^2 + 1 = 4 at z = 1,
    // and w(0) = 1 + 1 - 2 = 0.
    let a = ok("model I1 {
        state x = 2;
        alg z = 1;
        der(x) = -x + z;
        constraint c: z^3 + z = x;
    }");
    assert_eq!(a.indices(), [1]);
    assert_eq!(depends(&a), [["z"]]);
    assert_eq!(a.jacobian_at_initial, [4.0]);
    assert_eq!(at_initial(&a, a.symbolic().constraints[0].omega), 0.0);
    assert_eq!(a.condition_number, 1.0);
}

#[test]
fn index_2_the_unknown_appears_after_one_derivative() {
    // w = x - sin(t); w' = k z - cos(t) contains z: r = 2, J = k = 3.
    // At x = 0, z = 0.5: Omega = 3 * 0.5 - 1 = 0.5.
    let a = ok("model I2 {
        param k = 3;
        state x = 0;
        alg z = 0.5;
        der(x) = k * z;
        constraint follow: x = sin(t);
    }");
    assert_eq!(a.indices(), [2]);
    assert_eq!(depends(&a), [["z"]]);
    assert_eq!(a.jacobian_at_initial, [3.0]);
    assert!(close(
        at_initial(&a, a.symbolic().constraints[0].omega),
        0.5
    ));
}

#[test]
fn index_3_cartesian_pendulum() {
    // w = x^2 + y^2 - L^2, w' = 2 (x vx + y vy),
    // w'' = 2 (vx^2 + vy^2) + 2 (x (-lambda x) + y (-lambda y - g)) contains lambda: r = 3,
    // J = -2 (x^2 + y^2) = -2 * 0.64 - 2 * 0.36 = -2 at (0.8, -0.6).
    // Omega(0) = 2 (0.25 + 0) + 2 (0.8 (-0.8) - 0.6 (0.6 + 9.81))... with lambda = 1:
    // x ax = 0.8 * (-0.8) = -0.64, y ay = -0.6 * (0.6 - 9.81) = 5.526, so
    // Omega = 2 * 0.25 + 2 * (-0.64 + 5.526) = 0.5 + 9.772 = 10.272.
    let a = ok("model Pendulum {
        param L = 1, g = 9.81;
        state x = 0.8, y = -0.6, vx = 0.5, vy = 0;
        alg lambda = 1;
        der(x) = vx;
        der(y) = vy;
        der(vx) = -lambda * x;
        der(vy) = -lambda * y - g;
        constraint rod: x^2 + y^2 = L^2;
    }");
    assert_eq!(a.indices(), [3]);
    assert_eq!(depends(&a), [["lambda"]]);
    assert!(close(a.jacobian_at_initial[0], -2.0));
    assert!(close(
        at_initial(&a, a.symbolic().constraints[0].omega),
        10.272
    ));
}

#[test]
fn index_4_triple_integrator_tracking_a_parabola() {
    // w = x1 - t^2, w' = x2 - 2t, w'' = x3 - 2, w''' = k z contains z: r = 4, J = k = 0.5.
    let a = ok("model I4 {
        param k = 0.5;
        state x1 = 0, x2 = 0, x3 = 2;
        alg z = 0;
        der(x1) = x2;
        der(x2) = x3;
        der(x3) = k * z;
        constraint x1 = t^2;
    }");
    assert_eq!(a.indices(), [4]);
    assert_eq!(a.constraints[0].name, "c1");
    assert_eq!(a.jacobian_at_initial, [0.5]);
    // w'' = x3 - 2 = 0 at the start (the state is on the trajectory).
    assert_eq!(at_initial(&a, a.symbolic().constraints[0].w[2]), 0.0);
}

#[test]
fn mixed_indices_in_one_model() {
    // c_alg: w = z1 - a: r = 1, row (1, 0, 0).
    // c_vel: w = a - t, w' = z2 - 1: r = 2, row (0, 1, 0).
    // c_pos: w = p, w' = v, w'' = z3 + z1: r = 3, row (1, 0, 1).
    // J = [[1, 0, 0], [0, 1, 0], [1, 0, 1]].
    let a = ok(MIXED);
    assert_eq!(a.indices(), [1, 2, 3]);
    assert_eq!(depends(&a), vec![vec!["z1"], vec!["z2"], vec!["z1", "z3"]]);
    assert_eq!(
        a.jacobian_at_initial,
        [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0]
    );
    // J^T J = [[2, 0, 1], [0, 1, 0], [1, 0, 1]] has eigenvalues 1 and (3 +- sqrt 5)/2, so
    // cond_2 J = sqrt((3 + sqrt 5)/(3 - sqrt 5)) = (3 + sqrt 5)/2.
    assert!(close(a.condition_number, (3.0 + 5f64.sqrt()) / 2.0));
}

/// The mixed-index model (also used by the CLI tests through a file of the same text).
const MIXED: &str = "model Mixed {
    state a = 0, p = 0, v = 0;
    alg z1 = 0, z2 = 1, z3 = 0;
    der(a) = z2;
    der(p) = v;
    der(v) = z3 + z1;
    constraint c_alg: z1 = a;
    constraint c_vel: a = t;
    constraint c_pos: p = 0;
}";

#[test]
fn time_dependent_pendulum_length() {
    // Rod length L(t) = L0 + e sin(w t):
    // w0 = x^2 + y^2 - L(t)^2,
    // w1 = 2 (x vx + y vy) - 2 L L',            L' = e w cos(w t),
    // w2 = 2 (vx^2 + vy^2) + 2 (x ax + y ay) - 2 L'^2 - 2 L L'',  L'' = -e w^2 sin(w t).
    // ax = -lambda x, ay = -lambda y - g: r = 3, J = -2 (x^2 + y^2) = -2 * 1.44 = -2.88.
    // At t = 0 (L = L0, L' = e w, L'' = 0), x = 1.2, y = 0, vx = 0, vy = 0.5, lambda = 0:
    // w1 = -2 L0 e w = -2 * 1.2 * 0.1 * 2 = -0.48, w2 = 2 * 0.25 + 0 - 2 * 0.04 = 0.42.
    let a = ok("model Breathing {
        param L0 = 1.2, e = 0.1, w = 2, g = 9.81;
        state x = 1.2, y = 0, vx = 0, vy = 0.5;
        alg lambda = 0;
        let L = L0 + e * sin(w * t);
        der(x) = vx;
        der(y) = vy;
        der(vx) = -lambda * x;
        der(vy) = -lambda * y - g;
        constraint rod: x^2 + y^2 = L^2;
    }");
    assert_eq!(a.indices(), [3]);
    assert!(close(a.jacobian_at_initial[0], -2.88));
    let c = &a.symbolic().constraints[0];
    assert!(close(at_initial(&a, c.w[0]), 0.0));
    assert!(close(at_initial(&a, c.w[1]), -0.48));
    assert!(close(at_initial(&a, c.w[2]), 0.42));
}

#[test]
fn prescribed_trajectory_of_a_forced_mass() {
    // m x'' = F: the force F that makes x follow cos(t).
    // w = x - cos(t), w' = v + sin(t), w'' = F/m + cos(t): r = 3, J = 1/m = 0.25.
    // At x = 1, v = 0, F = -4 (the exact force m x'' = -m cos 0): w'' = -1 + 1 = 0.
    let a = ok("model Track {
        param m = 4;
        state x = 1, v = 0;
        alg F = -4;
        der(x) = v;
        der(v) = F / m;
        constraint path: x = cos(t);
    }");
    assert_eq!(a.indices(), [3]);
    assert_eq!(depends(&a), [["F"]]);
    assert!(close(a.jacobian_at_initial[0], 0.25));
    for &w in &a.symbolic().constraints[0].w {
        assert!(close(at_initial(&a, w), 0.0));
    }
}

/// A planar chain of `n` links hanging from the origin, as `.dae` text. Particle k
/// (1..=n) has mass m_k = 1 + k/2 and starts on a zigzag, x_k = k, y_k = -(k mod 2)/2 -
/// k/4; link k joins particles k-1 and k (particle 0 is the fixed origin) with tension z_k:
/// m_k V_k' = z_k rhat_{k,k-1} + z_{k+1} rhat_{k,k+1} - m_k g j.
fn chain_text(n: usize) -> String {
    let mut s = format!("model Chain{n} {{\n    param g = 9.81;\n");
    let pos = |k: usize| -> (f64, f64) {
        if k == 0 {
            (0.0, 0.0)
        } else {
            (k as f64, -((k % 2) as f64) / 2.0 - k as f64 / 4.0)
        }
    };
    for k in 1..=n {
        let (x, y) = pos(k);
        s += &format!(
            "    param m{k} = {}, L{k} = 1;\n    state x{k} = {x}, y{k} = {y}, vx{k} = 0, vy{k} = 0;\n    alg z{k} = 0;\n",
            1.0 + k as f64 / 2.0
        );
    }
    let coord = |c: &str, k: usize| {
        if k == 0 {
            "0".to_string()
        } else {
            format!("{c}{k}")
        }
    };
    for k in 1..=n {
        s += &format!(
            "    let l{k} = sqrt(({} - {})^2 + ({} - {})^2);\n",
            coord("x", k),
            coord("x", k - 1),
            coord("y", k),
            coord("y", k - 1)
        );
    }
    for k in 1..=n {
        for (c, extra) in [("x", ""), ("y", " - g")] {
            let mut force = format!("z{k} * ({} - {c}{k}) / l{k}", coord(c, k - 1));
            if k < n {
                force += &format!(" + z{} * ({c}{} - {c}{k}) / l{}", k + 1, k + 1, k + 1);
            }
            s += &format!(
                "    der({c}{k}) = v{c}{k};\n    der(v{c}{k}) = ({force}) / m{k}{extra};\n"
            );
        }
        s += &format!("    constraint link{k}: l{k} = L{k};\n");
    }
    s += "}\n";
    s
}

/// The closed form of docs/method.md section 7 for the chain of `chain_text`: diagonal
/// -(1/m_a + 1/m_b) (-1/m_1 for the pinned first link), off-diagonal (i, i+1) through
/// their shared particle c = i: -(rhat_{c,i} . rhat_{c,i+1}) / m_c.
fn chain_jacobian(n: usize) -> Vec<f64> {
    let pos = |k: usize| -> [f64; 2] {
        if k == 0 {
            [0.0, 0.0]
        } else {
            [k as f64, -((k % 2) as f64) / 2.0 - k as f64 / 4.0]
        }
    };
    let mass = |k: usize| 1.0 + k as f64 / 2.0;
    let unit = |from: usize, to: usize| {
        let (a, b) = (pos(from), pos(to));
        let d = [b[0] - a[0], b[1] - a[1]];
        let l = d[0].hypot(d[1]);
        [d[0] / l, d[1] / l]
    };
    let mut j = vec![0.0; n * n];
    for i in 1..=n {
        // Link i joins particles i-1 and i.
        j[(i - 1) * n + (i - 1)] = if i == 1 {
            -1.0 / mass(1)
        } else {
            -(1.0 / mass(i - 1) + 1.0 / mass(i))
        };
        if i < n {
            // Links i and i+1 share particle c = i; link i goes from c to i-1, link i+1
            // from c to i+1.
            let (u, v) = (unit(i, i - 1), unit(i, i + 1));
            let off = -(u[0] * v[0] + u[1] * v[1]) / mass(i);
            j[(i - 1) * n + i] = off;
            j[i * n + (i - 1)] = off;
        }
    }
    j
}

#[test]
fn planar_chains_of_3_and_10_links_have_index_3_and_the_tridiagonal_jacobian() {
    for n in [3, 10] {
        let a = ok(&chain_text(n));
        assert_eq!(a.indices(), vec![3; n], "chain of {n}");
        for (i, c) in a.constraints.iter().enumerate() {
            let want: Vec<String> = (i.max(1)..=(i + 2).min(n))
                .map(|k| format!("z{k}"))
                .collect();
            assert_eq!(c.depends_on, want, "link{}", i + 1);
        }
        let want = chain_jacobian(n);
        for (k, (&got, &w)) in a.jacobian_at_initial.iter().zip(&want).enumerate() {
            assert!(
                (got - w).abs() <= 1e-12,
                "chain of {n}, J({}, {}): {got} vs closed form {w}",
                k / n,
                k % n
            );
        }
        // Nothing outside the three diagonals, structurally: each row lists only its
        // neighbours' columns.
        for c in &a.symbolic().constraints {
            assert!(c.jacobian_row.len() <= 3);
        }
    }
}

#[test]
fn a_constraint_without_index_names_itself_and_its_variables() {
    // x' = -x never involves z: every w^(j) = (-1)^j x (plus a constant for j = 0), so no
    // unknown appears after the 8 derivatives allowed.
    let src = "model NoIndex {
    param x0 = 1;
    state x = x0, y = 0;
    alg z = 0;
    der(x) = -x;
    der(y) = z;
    constraint stuck: x = x0;
}";
    let errs = analyse(src).unwrap_err();
    assert_eq!(errs.len(), 1);
    let e = &errs[0];
    assert_eq!(
        e.message,
        "constraint `stuck` has no index: no algebraic unknown appears after 8 time derivatives"
    );
    assert_eq!(e.label, "depends on x, x0");
    assert_eq!(line_col(src, e.span), (7, 5));
    let shown = e.render("noindex.dae", src, false);
    assert!(shown.contains("noindex.dae:7:5"), "{shown}");
    assert!(shown.contains("constraint stuck: x = x0;"), "{shown}");
}

#[test]
fn a_singular_jacobian_names_the_constraints_and_the_condition_number() {
    // Both Omegas are linear in z1 + z2: w_a' = z1 + z2, w_b' = 2 (z1 + z2), so
    // J = [[1, 1], [2, 2]] has rank 1.
    let src = "model Singular {
    state x = 0, y = 0;
    alg z1 = 0, z2 = 0;
    der(x) = z1 + z2;
    der(y) = 2 * (z1 + z2);
    constraint a: x = t;
    constraint b: y = 2 * t;
}";
    let errs = analyse(src).unwrap_err();
    assert_eq!(errs.len(), 1);
    let e = &errs[0];
    assert!(
        e.message
            .starts_with("J_Omega is singular at the initial point")
            || e.message
                .starts_with("J_Omega is ill-conditioned at the initial point"),
        "{}",
        e.message
    );
    assert!(
        e.message.contains("`a`") && e.message.contains("`b`"),
        "{}",
        e.message
    );
    assert!(e.label.contains("condition number"), "{}", e.label);
    assert_eq!(line_col(src, e.span), (6, 5));
    assert_eq!(e.related.len(), 1);
    assert_eq!(line_col(src, e.related[0].0), (7, 5));
    let shown = e.render("singular.dae", src, false);
    assert!(shown.contains("singular.dae:6:5"), "{shown}");
}
