//! The `mass` item: what a valid one becomes, and each error it can meet, with its
//! message and place.

use dae_lang::{check_source, line_col};

/// A cart with a pendulum; `MASS` is replaced by the item under test.
const CART: &str = "model Cart {
    param mc = 1, mp = 0.5, l = 0.8, g = 9.81;
    state x = 0, th = 0.3, v = 0, om = 0;
    alg F = 0;
    let c = mp * l * cos(th);
    let cf = c * F;
    der(x) = v;
    der(th) = om;
    MASS
    der(v) = F + mp * l * om^2 * sin(th);
    der(om) = -mp * g * l * sin(th);
    constraint track: x = 0;
}";

fn with(mass: &str) -> String {
    CART.replace("MASS", mass)
}

/// Every error as (message, line, column); each has a label and a hint.
fn errors(src: &str) -> Vec<(String, (usize, usize))> {
    match check_source(src) {
        Ok(m) => panic!("expected errors, got {:?}", m[0].mass),
        Err(d) => d
            .iter()
            .map(|x| {
                assert!(x.hint.is_some() && !x.label.is_empty(), "{x:?}");
                (x.message.clone(), line_col(src, x.span))
            })
            .collect(),
    }
}

#[test]
fn a_mass_matrix_lists_its_states_and_keeps_its_entries_row_major() {
    let src = with("mass [v, om] = [mc + mp, c; c, mp * l^2];");
    let m = check_source(&src).expect("checks").remove(0);
    assert_eq!(m.mass.len(), 1);
    let idx: Vec<usize> = m.mass[0].states.iter().map(|s| s.index()).collect();
    assert_eq!(idx, [2, 3]);
    assert_eq!(m.mass[0].entries.len(), 4);
    assert_eq!(
        m.mass[0].entries[1], m.mass[0].entries[2],
        "both are the let `c`"
    );
}

#[test]
fn the_listed_names_must_be_distinct_states() {
    let e = errors(&with("mass [v, F] = [1, 0; 0, 1];"));
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(
        e[0].0.contains("`F` is an algebraic variable, not a state"),
        "{e:?}"
    );
    assert_eq!(e[0].1, (9, 14));
    let e = errors(&with("mass [v, w] = [1, 0; 0, 1];"));
    assert!(e[0].0.contains("unknown name `w`"), "{e:?}");
    let e = errors(&with("mass [v] = [1]; mass [om, v] = [1, 0; 0, 1];"));
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].0, "state `v` is listed twice in mass matrices");
    assert_eq!(e[0].1, (9, 31));
}

#[test]
fn the_matrix_must_be_square_over_its_states() {
    let e = errors(&with("mass [v, om] = [1, 0];"));
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].0, "the mass matrix over 2 states has 1 row");
    assert_eq!(e[0].1, (9, 5));
    let e = errors(&with("mass [v, om] = [1, 0; 0, 1, 2];"));
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(
        e[0].0,
        "a row of the mass matrix over 2 states has 3 entries"
    );
    assert_eq!(e[0].1, (9, 27));
}

#[test]
fn no_entry_may_depend_on_an_algebraic_unknown() {
    let e = errors(&with("mass [v, om] = [1 + F, 0; 0, 1];"));
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(
        e[0].0,
        "a mass matrix entry depends on the algebraic unknown `F`"
    );
    assert_eq!(e[0].1, (9, 21));
    let e = errors(&with("mass [v, om] = [1, 0; 0, 1 + cf];"));
    assert_eq!(
        e[0].0,
        "a mass matrix entry depends on the `let` `cf`, which reads an algebraic unknown"
    );
}

#[test]
fn a_matrix_singular_at_the_initial_point_is_reported_with_its_pivot() {
    // c = mp l cos(0.3) at the start: the 2 x 2 below has determinant 0 there.
    let e = errors(&with("mass [v, om] = [c, c; c, c];"));
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(
        e[0].0
            .starts_with("the mass matrix is singular at the initial point")
            && e[0].0.contains("pivot 2 (the row of `der(om)`)"),
        "{e:?}"
    );
    // A zero in the first pivot: elimination in the written order needs it non-zero.
    let e = errors(&with("mass [v, om] = [0, 1; 1, 0];"));
    assert!(e[0].0.contains("pivot 1 (the row of `der(v)`)"), "{e:?}");
}

/// A family with a vector state: `MASS` is replaced by the item under test.
const FAMILY: &str = "model Fam {
    size N = 2;
    set P = N;
    set Q = 1;
    param m[p in P] = 1 + p;
    state x[p in P]: vec2 = vec2(p, 0), v[p in P]: vec2 = vec2(0, 0);
    state y[q in Q] = 0, w[q in Q] = 0;
    alg z[p in P] = 0;
    der(x[p]) = v[p];
    der(y[q]) = w[q];
    der(w[q]) = 0;
    MASS
    der(v[p]) = vec2(-x[p].x, z[p]);
    constraint c[p in P]: x[p].y = 0;
}";

#[test]
fn a_family_lists_its_states_at_an_element_one_matrix_per_element() {
    let src = FAMILY.replace("MASS", "mass [v[p]] = [m[p], 0.5; 0.5, m[p]];");
    let m = check_source(&src).expect("checks").remove(0);
    assert_eq!(m.mass.len(), 1);
    // The two components of v, in order.
    let idx: Vec<usize> = m.mass[0].states.iter().map(|s| s.index()).collect();
    assert_eq!(idx, [2, 3]);
    assert_eq!(m.mass[0].entries.len(), 4);
}

#[test]
fn a_family_state_in_a_mass_matrix_is_named_at_an_element_of_one_set() {
    let with = |mass: &str| FAMILY.replace("MASS", mass);
    let e = errors(&with("mass [v] = [1, 0; 0, 1];"));
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].0, "`v` is a family over `P`");
    assert_eq!(e[0].1, (12, 11));
    let e = errors(&with("mass [v[p], w[q]] = [1, 0, 0; 0, 1, 0; 0, 0, 1];"));
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].0, "`w` is not over the set of the first state listed");
    let e = errors(&with("mass [v[p]] = [1, z[p]; 0, 1];"));
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(
        e[0].0,
        "a mass matrix entry depends on the algebraic unknown `z`"
    );
    let e = errors(&with("mass [v[p]] = [1, 0];"));
    assert_eq!(e[0].0, "the mass matrix over 2 states has 1 row");
    let e = errors(&with("mass [v[p]] = [x[p], 0; 0, 1];"));
    assert_eq!(e[0].0, "a mass matrix entry is a vec2");
}

#[test]
fn a_malformed_mass_item_is_a_syntax_error_at_its_place() {
    // The `]` left out: the next item reads as a third row up to its `=`.
    let src = with("mass [v, om] = [1, 0; 0, 1;");
    let e = errors(&src);
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].1, (10, 12), "{e:?}");
    assert!(e[0].0.starts_with("expected `,`, `;`, `]`"), "{e:?}");
}
