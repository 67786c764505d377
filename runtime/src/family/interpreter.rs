//! The interpreter of compiled models: a `.dae` file runs as soon as it is checked, with
//! no Rust generated or compiled, and the generated code has an independent oracle.
//! Every model's four programs (a model without sets has programs of one group each)
//! are run by [`Program::eval`](dae_lang::family::Program::eval), each instruction over
//! chunks of elements, behind [`Kernels`] ([`Interpreter`], in a
//! [`FamilyInstance`](super::FamilyInstance): [`Interpreted`]).

use dae_lang::CompiledModel;
use dae_lang::family::{
    ConstructError, Construction, FamilyModel, Instance, Program, Scratch, Spec, Values,
};

use super::{FamilyInstance, Kernels};

/// A compiled model run by the interpreter, at the sizes it was constructed at
/// ([`FamilyInstance::from_compiled`]).
pub type Interpreted = FamilyInstance<Interpreter>;

/// Runs a compiled model's programs with the vectorised interpreter of `dae-lang`: no
/// Rust is generated or compiled, so a `.dae` file runs as soon as it is checked
/// (`daec run`).
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
    /// The interpreter of a compiled model.
    pub fn new(compiled: CompiledModel) -> Interpreter {
        Interpreter {
            name: compiled.name,
            model: *compiled.programs,
        }
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

impl FamilyInstance<Interpreter> {
    /// The interpreted model at the sizes of `spec`, named after the model.
    pub fn interpreted(kernels: Interpreter, spec: &Spec) -> Result<Self, ConstructError> {
        let name = kernels.name.clone();
        Ok(Self::new(kernels, spec)?.with_name(name))
    }

    /// `compiled` run by the interpreter at the sizes of `spec` (`Spec::default()`: the
    /// model's own sizes, all a model without sets has).
    pub fn from_compiled(compiled: CompiledModel, spec: &Spec) -> Result<Self, ConstructError> {
        Self::interpreted(Interpreter::new(compiled), spec)
    }
}
