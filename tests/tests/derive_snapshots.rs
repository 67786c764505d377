//! Snapshots of the `daec derive` text of every example model (one snapshot file per
//! model; `daec derive FILE` prints exactly `Analysis::derive_text`, which `cli/tests`
//! checks), and the real parser reading every right-hand side of that text back.
//!
//! Review a changed snapshot with `cargo insta review` (or `INSTA_UPDATE=always`, then
//! read the `.snap` files): they are the derivatives users see.

use dae_lang::model::Model;
use dae_lang::{Analysis, AnalysisOptions, Point, analyze};
use std::path::PathBuf;

const EXAMPLES: [&str; 5] = [
    "circuit_index1.dae",
    "double_pendulum_3d.dae",
    "double_pendulum_planar.dae",
    "integrator_chain_index4.dae",
    "tank_level_index2.dae",
];

fn source(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/models")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn analysed(src: &str) -> (Model, Analysis) {
    let mut models = dae_lang::check_source(src).expect("the example checks");
    assert_eq!(models.len(), 1);
    let m = models.remove(0);
    let a = analyze(&m, &AnalysisOptions::default()).expect("the example analyses");
    (m, a)
}

#[test]
fn derive_text_of_every_example() {
    for name in EXAMPLES {
        let (_, a) = analysed(&source(name));
        let snap = name.trim_end_matches(".dae");
        insta::assert_snapshot!(snap, a.derive_text());
    }
}

/// The `name = rhs` equations of a derive text (comments after the right-hand side kept:
/// the parser must skip them too).
fn equations(text: &str) -> Vec<(&str, &str)> {
    text.lines()
        .filter(|l| !l.is_empty() && !l.starts_with("//"))
        .map(|l| l.split_once(" = ").expect("an equation"))
        .collect()
}

/// The nodes the derive text prints, in its order.
fn printed_ids(a: &Analysis) -> Vec<dae_lang::Id> {
    let sym = a.symbolic();
    let mut ids = sym.lets.clone();
    for c in &sym.constraints {
        ids.extend(&c.w);
        ids.extend(c.jacobian_row.iter().map(|e| e.1));
        ids.extend([c.beta, c.s, c.alpha, c.alpha_hat]);
    }
    ids
}

/// Every right-hand side, pasted into its own model as `let derive_rhs_<k> = <rhs>;` (with
/// `mu1, mu2, ...` declared as parameters), parses, checks, and evaluates to the value of
/// the expression it was printed from, at the initial point and at a point away from it.
#[test]
fn every_right_hand_side_parses_back_with_the_real_parser() {
    for name in EXAMPLES {
        let src = source(name);
        let (model, a) = analysed(&src);
        let text = a.derive_text();
        let eqs = equations(&text);
        let ids = printed_ids(&a);
        assert_eq!(
            eqs.len(),
            ids.len(),
            "{name}: one equation per printed node"
        );
        let m = a.constraints.len();
        let mut extra = String::new();
        if m > 0 {
            let mus: Vec<String> = (1..=m).map(|i| format!("mu{i} = 0.{i}5")).collect();
            extra.push_str(&format!("    param {};\n", mus.join(", ")));
        }
        for (k, (lhs, rhs)) in eqs.iter().enumerate() {
            // A line break before `;` keeps the trailing `// link1 / z2` a comment.
            extra.push_str(&format!(
                "    // {lhs}\n    let derive_rhs_{k} = {rhs}\n    ;\n"
            ));
        }
        let close = src.rfind('}').expect("the model's closing brace");
        let pasted = format!("{}{extra}{}", &src[..close], &src[close..]);
        let back = match dae_lang::check_source(&pasted) {
            Ok(mut ms) => ms.remove(0),
            Err(d) => panic!(
                "{name}: {}",
                d.iter()
                    .map(|x| x.render(name, &pasted, false))
                    .collect::<String>()
            ),
        };
        let low = dae_lang::lower(&back, true);
        let mu: Vec<f64> = (1..=m)
            .map(|i| format!("0.{i}5").parse().unwrap())
            .collect();
        for (shift, t) in [(0.0, 0.0), (0.0625, 0.375)] {
            let states: Vec<f64> = a
                .initial
                .states
                .iter()
                .enumerate()
                .map(|(k, x)| x + shift * (1.0 + k as f64 * 0.25))
                .collect();
            let algs: Vec<f64> = a.initial.algs.iter().map(|z| z + shift).collect();
            let original = Point {
                params: &a.initial.params,
                states: &states,
                algs: &algs,
                t,
                mu: &mu,
            };
            let mut params = a.initial.params.clone();
            params.extend(&mu);
            let pasted_point = Point {
                params: &params,
                states: &states,
                algs: &algs,
                t,
                mu: &[],
            };
            for (k, (&id, (lhs, rhs))) in ids.iter().zip(&eqs).enumerate() {
                let j = back
                    .lets
                    .iter()
                    .position(|l| l.name == format!("derive_rhs_{k}"))
                    .expect("the pasted let");
                let want = a.symbolic().arena.eval(id, &original);
                let got = low.arena.eval(low.lets[j], &pasted_point);
                assert!(
                    (got - want).abs() <= 1e-9 * (1.0 + want.abs()),
                    "{name}, {lhs} = {rhs}: parsed back {got}, printed from {want}"
                );
            }
        }
        assert_eq!(model.name, back.name);
    }
}
