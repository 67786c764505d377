//! The FMU's variables, numbered by their value references: `eps`, the parameters, the
//! states, the algebraic unknowns, the constraint errors, the inputs.

use crate::model::Driven;

/// What a variable is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The layer half-width of every constraint (a parameter).
    Eps,
    /// A parameter of the model.
    Param,
    /// A differential state (an output).
    State,
    /// An algebraic unknown (an output).
    Alg,
    /// A constraint's error `g_i(t, x)`, its `w_i` (an output).
    Error,
    /// An input of a family model.
    Input,
}

/// One variable of the FMU.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    /// Its name (`eps`, `m1`, `x[3].x`, `error.link1`).
    pub name: String,
    /// What it is.
    pub kind: Kind,
    /// Its index among the model's quantities of its kind.
    pub index: usize,
    /// The start value of a parameter or input.
    pub start: Option<f64>,
}

/// Every variable of `model`, in the order of their value references (0, 1, ...).
pub(crate) fn of<M: Driven + ?Sized>(model: &M, eps: f64) -> Vec<Variable> {
    let mut vars = vec![Variable {
        name: "eps".into(),
        kind: Kind::Eps,
        index: 0,
        start: Some(eps),
    }];
    let mut push = |name: String, kind, index, start| {
        vars.push(Variable {
            name,
            kind,
            index,
            start,
        })
    };
    for i in 0..model.n_params() {
        push(
            model.param_name(i).into(),
            Kind::Param,
            i,
            Some(model.param(i)),
        );
    }
    for i in 0..model.n_states() {
        push(model.state_name(i).into(), Kind::State, i, None);
    }
    for i in 0..model.n_constraints() {
        push(model.alg_name(i).into(), Kind::Alg, i, None);
    }
    for i in 0..model.n_constraints() {
        push(
            format!("error.{}", model.constraint_name(i)),
            Kind::Error,
            i,
            None,
        );
    }
    for i in 0..model.n_inputs() {
        let start = model.input_taylor(i).first().copied().unwrap_or(0.0);
        push(model.input_name(i).into(), Kind::Input, i, Some(start));
    }
    vars
}
