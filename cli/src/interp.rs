//! The interpreter: a [`CompiledModel`]'s tapes evaluated directly, behind the runtime's
//! [`Model`] trait, so that `daec run` simulates a `.dae` file without compiling Rust and
//! so that generated code has an independent oracle.

use std::cell::RefCell;

use dae_lang::CompiledModel;
use dae_lang::tape::{Inputs, Tape};
use dae_runtime::{Model, ModelInfo};

/// A model evaluated from its tapes.
#[derive(Debug)]
pub struct Interpreted {
    model: CompiledModel,
    params: Vec<f64>,
    /// Scratch slots, sized for the longest tape. `Model` methods take `&self`, so the
    /// buffer sits in a `RefCell`; evaluation never re-enters, so the borrow cannot fail.
    slots: RefCell<Vec<f64>>,
    info: ModelInfo,
}

impl Interpreted {
    /// Wrap a compiled model with its default parameters.
    pub fn new(model: CompiledModel) -> Self {
        let params = model.params.iter().map(|(_, v)| *v).collect();
        let sliding = model.sliding.n_slots() + model.w_len() + 2 * model.algs.len();
        let longest = model
            .functions()
            .iter()
            .map(|(_, t)| t.n_slots())
            .fold(sliding, usize::max);
        let info = ModelInfo {
            name: model.name.clone(),
            states: model.states.clone(),
            algs: model.algs.clone(),
            constraints: model.constraints.clone(),
            params: model.params.iter().map(|(name, _)| name.clone()).collect(),
            indices: model.indices.clone(),
        };
        Interpreted {
            model,
            params,
            slots: RefCell::new(vec![0.0; longest]),
            info,
        }
    }

    /// The compiled model.
    pub fn compiled(&self) -> &CompiledModel {
        &self.model
    }

    /// Index of the parameter called `name`.
    pub fn param_index(&self, name: &str) -> Option<usize> {
        self.model.params.iter().position(|(p, _)| p == name)
    }

    fn run(&self, tape: &Tape, t: f64, x: &[f64], z: &[f64], mu: &[f64], out: &mut [f64]) {
        let inputs = Inputs {
            params: &self.params,
            states: x,
            algs: z,
            mu,
            t,
        };
        tape.eval(&inputs, &mut self.slots.borrow_mut(), out);
    }
}

impl Model for Interpreted {
    fn info(&self) -> &ModelInfo {
        &self.info
    }
    fn param(&self, i: usize) -> f64 {
        self.params[i]
    }
    fn set_param(&mut self, i: usize, value: f64) {
        self.params[i] = value;
    }
    fn initial_state(&self, x: &mut [f64]) {
        self.run(&self.model.init_state, 0.0, &[], &[], &[], x);
    }
    fn initial_alg(&self, z: &mut [f64]) {
        self.run(&self.model.init_alg, 0.0, &[], &[], &[], z);
    }
    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        self.run(&self.model.rhs, t, x, z, &[], dx);
    }
    fn sliding(
        &self,
        t: f64,
        x: &[f64],
        z: &[f64],
        mu: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        alpha_hat: &mut [f64],
    ) {
        // One tape computes all three arrays so that they share sub-expressions; its
        // outputs land back to back in the tail of the preallocated scratch buffer.
        let nw = w.len();
        let m = s.len();
        let total = nw + 2 * m;
        let inputs = Inputs {
            params: &self.params,
            states: x,
            algs: z,
            mu,
            t,
        };
        let mut slots = self.slots.borrow_mut();
        let tape = &self.model.sliding;
        let (scratch, out) = slots.split_at_mut(tape.n_slots());
        debug_assert!(out.len() >= total, "slots buffer sized for sliding outputs");
        let out = &mut out[..total];
        tape.eval(&inputs, scratch, out);
        w.copy_from_slice(&out[..nw]);
        s.copy_from_slice(&out[nw..nw + m]);
        alpha_hat.copy_from_slice(&out[nw + m..]);
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &self.model.jacobian_pattern
    }
    fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
        self.run(&self.model.jacobian, t, x, z, &[], values);
    }
    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        self.run(&self.model.beta, t, x, z, &[], beta);
    }
}
