//! The interpreter of compiled models: a `.dae` file runs as soon as it is checked, with
//! no Rust generated or compiled, and the generated code has an independent oracle. A
//! version-1 model's tapes are evaluated by [`Tape::eval`] behind the [`Model`] trait
//! ([`Interpreted`]); a family model's four programs by
//! [`Program::eval`](dae_lang::family::Program::eval), each instruction over chunks of
//! elements, behind [`Kernels`] ([`Interpreter`], run in a
//! [`FamilyInstance`](super::FamilyInstance)).

use std::cell::RefCell;

use dae_lang::CompiledModel;
use dae_lang::family::{Construction, FamilyModel, Instance, Program, Scratch, Values};
use dae_lang::tape::{Inputs, Tape};

use super::Kernels;
use crate::{Model, ModelInfo};

/// Runs a compiled family model's programs with the vectorised interpreter of
/// `dae-lang`: no Rust is generated or compiled, so a `.dae` file runs as soon as it
/// is checked (`daec run`).
#[derive(Clone, Debug)]
pub struct Interpreter {
    name: String,
    model: FamilyModel,
}

/// One [`Scratch`] per program.
#[derive(Clone, Debug)]
pub struct InterpreterScratch {
    rhs: Scratch,
    sliding: Scratch,
    jacobian: Scratch,
    rate: Scratch,
}

impl Interpreter {
    /// The interpreter of a compiled family model, or `None` for a model without
    /// families (version 1: [`Interpreted`]).
    pub fn new(compiled: CompiledModel) -> Option<Interpreter> {
        let model = *compiled.family?;
        Some(Interpreter {
            name: compiled.name,
            model,
        })
    }

    /// The model's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The compiled form it runs.
    pub fn model(&self) -> &FamilyModel {
        &self.model
    }
}

fn run(p: &Program, inst: &Instance, v: &Values<'_>, s: &mut Scratch, out: &mut [&mut [f64]]) {
    p.eval(inst, v, s, out);
}

impl Kernels for Interpreter {
    type Scratch = InterpreterScratch;

    fn construction(&self) -> &Construction {
        &self.model.construction
    }

    fn scratch(&self, inst: &Instance) -> InterpreterScratch {
        InterpreterScratch {
            rhs: Scratch::new(&self.model.rhs, inst),
            sliding: Scratch::new(&self.model.sliding, inst),
            jacobian: Scratch::new(&self.model.jacobian, inst),
            rate: Scratch::new(&self.model.rate, inst),
        }
    }

    fn rhs(&self, inst: &Instance, v: &Values<'_>, s: &mut InterpreterScratch, dx: &mut [f64]) {
        run(&self.model.rhs, inst, v, &mut s.rhs, &mut [dx]);
    }

    fn sliding(
        &self,
        inst: &Instance,
        v: &Values<'_>,
        s: &mut InterpreterScratch,
        w: &mut [f64],
        sl: &mut [f64],
        alpha_hat: &mut [f64],
    ) {
        run(
            &self.model.sliding,
            inst,
            v,
            &mut s.sliding,
            &mut [w, sl, alpha_hat],
        );
    }

    fn jacobian(
        &self,
        inst: &Instance,
        v: &Values<'_>,
        s: &mut InterpreterScratch,
        values: &mut [f64],
    ) {
        run(
            &self.model.jacobian,
            inst,
            v,
            &mut s.jacobian,
            &mut [values],
        );
    }

    fn omega_rate(
        &self,
        inst: &Instance,
        v: &Values<'_>,
        s: &mut InterpreterScratch,
        rate: &mut [f64],
    ) {
        run(&self.model.rate, inst, v, &mut s.rate, &mut [rate]);
    }
}

impl super::FamilyInstance<Interpreter> {
    /// The interpreted model at the sizes of `spec`, named after the model.
    pub fn interpreted(
        kernels: Interpreter,
        spec: &dae_lang::family::Spec,
    ) -> Result<Self, dae_lang::family::ConstructError> {
        let name = kernels.name.clone();
        Ok(Self::new(kernels, spec)?.with_name(name))
    }
}

/// A version-1 model evaluated from its tapes.
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
