//! Printed expressions read back with the real front end (`parse`, `check`, lowering),
//! not only with the test reader: the text `daec derive` prints is meant to be pasted
//! into a model.

use proptest::prelude::*;

use super::tests::{T, build, build_with, has_kept_constant_power, names, tree};
use super::{Arena, Id};
use crate::analysis::lower;
use crate::{AlgId, ParamId, StateId};

/// The expression as `let e = <text>;` in a model declaring every name the printer may
/// use: `x`, `y` (states), `z` (algebraic), `p` and `mu1` (parameters; the realization
/// parameter is a parameter once the text is back in a model).
fn model_text(text: &str) -> String {
    format!(
        "model RoundTrip {{
    param p = 0.5, mu1 = 0.25;
    state x = 0.1, y = 0.2;
    alg z = 0.3;
    let e = {text};
    der(x) = 0;
    der(y) = 0;
    constraint z = 0;
}}"
    )
}

/// Parse, check and lower the model; the arena and the node of `e`, and the leaves in
/// that arena (x, y, z, p, t, mu1 -> the parameter `mu1`).
fn parse_back(text: &str) -> (Arena, Id, [Id; 6]) {
    let src = model_text(text);
    let file = crate::parse(&src).unwrap_or_else(|d| panic!("{text}: {}", d[0].message));
    // Without the values at the initial point: a printed expression need not be defined
    // at the model's start (`ln(-1)` prints and reads back like any other).
    let model = crate::check::check_model_with(&file.models[0], false)
        .unwrap_or_else(|d| panic!("{text}: {}", d[0].render("e.dae", &src, false)));
    let mut low = lower(&model, true);
    let a = &mut low.arena;
    let leaves = [
        a.state(StateId::new(0)),
        a.state(StateId::new(1)),
        a.alg(AlgId::new(0)),
        a.param(ParamId::new(0)),
        a.time(),
        a.param(ParamId::new(1)),
    ];
    (low.arena, low.lets[0], leaves)
}

fn round_trip(t: &T) -> Result<(), TestCaseError> {
    let mut a = Arena::new();
    let e = build(&mut a, t);
    let text = a.display(e, &names());
    let (mut b, back, leaves) = parse_back(&text);
    // The same tree built directly in the parsed model's arena.
    let want = build_with(&mut b, t, &leaves);
    // As in the reader test: a kept power of a constant (`(-1)^0.5`) may fold differently.
    if !has_kept_constant_power(&a, e) {
        prop_assert_eq!(back, want, "{}", text);
    }
    Ok(())
}

#[test]
fn hand_picked_texts_read_back_through_the_parser() {
    use super::tests::T::*;
    let x = || Box::new(Leaf(0));
    let y = || Box::new(Leaf(1));
    let mu = || Box::new(Leaf(5));
    for t in [
        Neg(Box::new(PowN(x(), 2.0))),
        Bin(3, Box::new(Bin(0, x(), y())), Box::new(Neg(x()))),
        Bin(4, x(), Box::new(Neg(Box::new(Leaf(4))))),
        PowN(Box::new(Bin(1, y(), x())), -1.5),
        Bin(2, mu(), Box::new(Num(1e-7))),
        F2(crate::Func::Atan2, y(), Box::new(Num(-2.5))),
    ] {
        round_trip(&t).unwrap();
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn printed_text_parses_back_to_the_same_node(t in tree()) {
        round_trip(&t)?;
    }
}
