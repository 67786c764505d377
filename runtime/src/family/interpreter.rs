//! The interpreter back end of family models: the four programs of the compiled form
//! run by [`Program::eval`](dae_lang::family::Program::eval), each instruction over
//! chunks of elements.

use dae_lang::CompiledModel;
use dae_lang::family::{Construction, FamilyModel, Instance, Program, Scratch, Values};

use super::Kernels;

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
    /// families (version 1: see `daec`'s `Interpreted`).
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
