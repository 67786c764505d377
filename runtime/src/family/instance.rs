//! A family model sized at construction, behind the runtime's [`Model`] trait, generic
//! over the back end that runs its programs ([`Kernels`]).

use std::cell::{OnceCell, RefCell};

use dae_lang::family::{ConstructError, Construction, Instance, Slot, Spec, Values, construct};
use dae_lang::model::Family;

use super::Kernels;
use super::inputs::{InputError, Inputs};
use super::names::{Decl, NameTable, lookup, lookup_at};
use crate::{Model, ModelInfo};

/// A family model at given sizes: the [`Instance`] built by construction from a
/// [`Spec`], run by the back end `K` (the [`Interpreter`](super::Interpreter) or
/// generated code), with its parameters, inputs and names.
///
/// It implements [`Model`], so the [`Simulator`](crate::Simulator) runs it like any
/// other model. Evaluations allocate nothing: the back end's scratch and the input
/// values are built once and kept in `RefCell`s (the `Model` methods take `&self` and
/// never re-enter).
pub struct FamilyInstance<K: Kernels> {
    kernels: K,
    name: String,
    inst: Instance,
    indices: Vec<usize>,
    /// `mu` for the functions that do not read it.
    zero_mu: Vec<f64>,
    /// `z' = 0`: the rate program gives `beta` with it.
    zero_rates: Vec<f64>,
    inputs: Inputs,
    scratch: RefCell<K::Scratch>,
    names: [OnceCell<NameTable>; 5],
    /// The metadata as one value, built when first asked for (from the tables above).
    info: OnceCell<ModelInfo>,
}

/// The kinds of names, indexing `FamilyInstance::names`.
#[derive(Clone, Copy)]
enum Kind {
    State = 0,
    Alg = 1,
    Constraint = 2,
    Param = 3,
    Input = 4,
}

impl Kind {
    fn words(self) -> &'static str {
        match self {
            Kind::State => "state",
            Kind::Alg => "algebraic unknown",
            Kind::Constraint => "constraint",
            Kind::Param => "parameter",
            Kind::Input => "input",
        }
    }
}

/// A name that is no slot of the model (see [`FamilyInstance::param_index`]).
#[derive(Clone, Debug, PartialEq)]
pub struct UnknownName {
    /// What was looked up (`parameter`, `input`, ...).
    pub kind: &'static str,
    /// The name given.
    pub name: String,
}

impl std::fmt::Display for UnknownName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "no {} named `{}`: write a scalar as `g` or `pivot.x`, an element as `free[3]` or `pin[3].x` (elements count from 0)",
            self.kind, self.name
        )
    }
}

impl std::error::Error for UnknownName {}

impl<K: Kernels> FamilyInstance<K> {
    /// Constructs the model at the sizes, given sets and maps and parameter overrides of
    /// `spec` ([`construct`]: every check that needs sizes, reported with the span of
    /// the declaration concerned), and the back end's scratch.
    pub fn new(kernels: K, spec: &Spec) -> Result<Self, ConstructError> {
        let inst = construct(kernels.construction(), spec)?;
        Ok(Self::from_instance(kernels, inst))
    }

    /// Wraps an instance already built from `kernels.construction()`.
    pub fn from_instance(kernels: K, inst: Instance) -> Self {
        let c = kernels.construction();
        let l = &inst.layout;
        let mut indices = vec![0; l.n_rows];
        for (k, info) in c.constraints.iter().enumerate() {
            for e in 0..inst.set_size(info.over) {
                indices[l.rows[k].at(e)] = info.index;
            }
        }
        let inputs = Inputs::new(c, &inst);
        let scratch = RefCell::new(kernels.scratch(&inst));
        FamilyInstance {
            name: "family".into(),
            zero_mu: vec![0.0; l.n_rows],
            zero_rates: vec![0.0; l.n_algs],
            indices,
            inputs,
            scratch,
            inst,
            kernels,
            names: Default::default(),
            info: OnceCell::new(),
        }
    }

    /// Sets the model's name (reported by [`Model::name`]; `family` by default).
    pub fn with_name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// The instance: sizes, maps, layout, the pattern of `J_Omega`.
    pub fn instance(&self) -> &Instance {
        &self.inst
    }

    /// The back end.
    pub fn kernels(&self) -> &K {
        &self.kernels
    }

    /// The value of the `size` called `name`.
    pub fn size(&self, name: &str) -> Option<i64> {
        let c = self.kernels.construction();
        let i = c.sizes.iter().position(|s| s.name == name)?;
        Some(self.inst.size_values[i])
    }

    /// The number of elements of the set called `name`.
    pub fn set_len(&self, name: &str) -> Option<usize> {
        let c = self.kernels.construction();
        let i = c.sets.iter().position(|s| s.name == name)?;
        Some(self.inst.set_sizes[i])
    }

    fn decls(&self, kind: Kind) -> Vec<Decl<'_>> {
        let c: &Construction = self.kernels.construction();
        let l = &self.inst.layout;
        fn of<'a>(it: impl Iterator<Item = (&'a str, Family)>, slots: &[Slot]) -> Vec<Decl<'a>> {
            it.zip(slots)
                .map(|((name, family), &slot)| Decl { name, family, slot })
                .collect()
        }
        match kind {
            Kind::State => of(c.states.iter().map(|d| (&*d.name, d.family)), &l.states),
            Kind::Alg => of(c.algs.iter().map(|d| (&*d.name, d.family)), &l.algs),
            Kind::Param => of(c.params.iter().map(|d| (&*d.name, d.family)), &l.params),
            Kind::Input => of(c.inputs.iter().map(|d| (&*d.name, d.family)), &l.inputs),
            Kind::Constraint => of(
                c.constraints.iter().map(|d| {
                    let family = Family {
                        over: d.over,
                        dim: 1,
                        component: 0,
                    };
                    (&*d.name, family)
                }),
                &l.rows,
            ),
        }
    }

    fn len(&self, kind: Kind) -> usize {
        let l = &self.inst.layout;
        match kind {
            Kind::State => l.n_states,
            Kind::Alg => l.n_algs,
            Kind::Constraint => l.n_rows,
            Kind::Param => l.n_params,
            Kind::Input => l.n_inputs,
        }
    }

    /// Name `i` of a kind, the table built on first use.
    fn name_of(&self, kind: Kind, i: usize) -> &str {
        self.names[kind as usize]
            .get_or_init(|| NameTable::build(&self.decls(kind), &self.inst, self.len(kind)))
            .get(i)
    }

    fn index_of(&self, kind: Kind, name: &str) -> Result<usize, UnknownName> {
        lookup(&self.decls(kind), &self.inst, name).ok_or_else(|| UnknownName {
            kind: kind.words(),
            name: name.into(),
        })
    }

    fn index_at(&self, kind: Kind, family: &str, element: usize) -> Result<usize, UnknownName> {
        let (base, comp) = match family.split_once('.') {
            Some((b, c)) => (b, Some(c)),
            None => (family, None),
        };
        lookup_at(&self.decls(kind), &self.inst, base, comp, element).ok_or_else(|| UnknownName {
            kind: kind.words(),
            name: match comp {
                Some(c) => format!("{base}[{element}].{c}"),
                None => format!("{base}[{element}]"),
            },
        })
    }

    /// The flat index of the parameter called `name`: a scalar (`g`, `pin0.x`) or an
    /// element of a per-element parameter (`free[3]`, `pin0[3].x`). Costs one pass over
    /// the declarations (not over the elements).
    pub fn param_index(&self, name: &str) -> Result<usize, UnknownName> {
        self.index_of(Kind::Param, name)
    }

    /// The flat index of element `element` of the per-element parameter `family`
    /// (`"free"`, or `"pin0.x"` for a component).
    pub fn param_index_at(&self, family: &str, element: usize) -> Result<usize, UnknownName> {
        self.index_at(Kind::Param, family, element)
    }

    /// Sets the parameter called `name` (as [`FamilyInstance::param_index`] reads it).
    ///
    /// This is how a particle is pinned or released during a run in the example
    /// models: `set_param_named("free[7]", 0.0)` makes particle 7 follow its input
    /// `pin[7]` (set it first, with the derivatives the index needs), `1.0` frees it
    /// again. Nothing is recompiled or reconstructed: `free` is read by the equations.
    pub fn set_param_named(&mut self, name: &str, value: f64) -> Result<(), UnknownName> {
        let i = self.param_index(name)?;
        self.inst.params[i] = value;
        self.initial_values_follow();
        Ok(())
    }

    /// A model without sets, inputs or vector parameters (a version-1 model) computes
    /// its initial values from its parameters as they are now, as its generated code
    /// does: they are evaluated again after a parameter changes (a value that is not
    /// finite then is NaN, which the start of a run reports). A family model keeps the
    /// initial values of its construction (give such parameters in the [`Spec`]).
    fn initial_values_follow(&mut self) {
        let c = self.kernels.construction();
        let scalar =
            c.sets.is_empty() && c.inputs.is_empty() && c.params.iter().all(|p| p.family.dim <= 1);
        if !scalar {
            return;
        }
        let spec = Spec {
            sizes: c
                .sizes
                .iter()
                .zip(&self.inst.size_values)
                .map(|(s, &v)| (s.name.clone(), v))
                .collect(),
            params: c
                .params
                .iter()
                .zip(&self.inst.params)
                .map(|(p, &v)| (p.name.clone(), v))
                .collect(),
            ..Spec::default()
        };
        match construct(c, &spec) {
            Ok(at) => {
                self.inst.states = at.states;
                self.inst.algs = at.algs;
            }
            Err(_) => {
                self.inst.states.fill(f64::NAN);
                self.inst.algs.fill(f64::NAN);
            }
        }
    }

    /// The flat index of the state called `name` (`x[3].y`, or a scalar's name).
    pub fn state_index(&self, name: &str) -> Result<usize, UnknownName> {
        self.index_of(Kind::State, name)
    }

    /// The flat index of element `element` of the state family `family` (`"x.y"`).
    pub fn state_index_at(&self, family: &str, element: usize) -> Result<usize, UnknownName> {
        self.index_at(Kind::State, family, element)
    }

    /// The row of the constraint called `name` (`link[7]`).
    pub fn constraint_index(&self, name: &str) -> Result<usize, UnknownName> {
        self.index_of(Kind::Constraint, name)
    }

    /// Number of inputs (flat: every component of every element).
    pub fn n_inputs(&self) -> usize {
        self.inputs.len()
    }

    /// Name of input `i` (`pin[3].x`, `head.y`).
    pub fn input_name(&self, i: usize) -> &str {
        self.name_of(Kind::Input, i)
    }

    /// How many time derivatives input `i` carries (its declaration's `with K
    /// derivatives`).
    pub fn input_order(&self, i: usize) -> usize {
        self.inputs.order(i)
    }

    /// The flat index of the input called `name` (`pin[3].x`, `head.y`).
    pub fn input_index(&self, name: &str) -> Result<usize, UnknownName> {
        self.index_of(Kind::Input, name)
    }

    /// The flat index of element `element` of the input family `family` (`"pin.x"`).
    pub fn input_index_at(&self, family: &str, element: usize) -> Result<usize, UnknownName> {
        self.index_at(Kind::Input, family, element)
    }

    /// Input `i`'s Taylor data: `t0` and `[value, d1, .., dK]` at `t0`.
    pub fn input(&self, i: usize) -> (f64, &[f64]) {
        self.inputs.taylor(i)
    }

    /// Makes input `i` the polynomial with value and derivatives
    /// `taylor = [value, d1, .., dK']` at time `t0` (`K'` at most the declared `K`; the
    /// derivatives not given are 0). Every later evaluation at time `t` reads the
    /// polynomial and its derivatives at `t`, until the next call for `i` (see the
    /// [module documentation](super) for the rule).
    pub fn set_input(&mut self, i: usize, t0: f64, taylor: &[f64]) -> Result<(), InputError> {
        let n = self.inputs.len();
        if i >= n {
            return Err(InputError::UnknownIndex {
                index: i,
                n_inputs: n,
            });
        }
        let order = self.inputs.order(i);
        if taylor.len() > order + 1 {
            return Err(InputError::TooManyDerivatives {
                name: self.input_name(i).into(),
                given: taylor.len(),
                order,
            });
        }
        if taylor.is_empty() || !t0.is_finite() || taylor.iter().any(|v| !v.is_finite()) {
            return Err(InputError::BadValue {
                name: self.input_name(i).into(),
                values: taylor.to_vec(),
            });
        }
        self.inputs.set(i, t0, taylor);
        Ok(())
    }

    fn values<'a>(
        &'a self,
        t: f64,
        x: &'a [f64],
        z: &'a [f64],
        mu: &'a [f64],
        inputs: &'a [f64],
    ) -> Values<'a> {
        Values {
            params: &self.inst.params,
            states: x,
            algs: z,
            alg_rates: &[],
            mu,
            inputs,
            t,
        }
    }
}

impl<K: Kernels> std::fmt::Debug for FamilyInstance<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FamilyInstance")
            .field("name", &self.name)
            .field("set_sizes", &self.inst.set_sizes)
            .field("n_states", &self.inst.layout.n_states)
            .field("n_constraints", &self.inst.layout.n_rows)
            .field("jacobian_entries", &self.inst.jacobian.entries.len())
            .finish_non_exhaustive()
    }
}

/// The sizes, names and indices are also read directly (without building the whole
/// [`ModelInfo`]): a model of `10^5` links is asked for its sizes more often than for
/// all its names.
impl<K: Kernels> Model for FamilyInstance<K> {
    fn info(&self) -> &ModelInfo {
        self.info.get_or_init(|| {
            let names = |kind: Kind| -> Vec<String> {
                (0..self.len(kind))
                    .map(|i| self.name_of(kind, i).to_string())
                    .collect()
            };
            ModelInfo {
                name: self.name.clone(),
                states: names(Kind::State),
                algs: names(Kind::Alg),
                constraints: names(Kind::Constraint),
                params: names(Kind::Param),
                indices: self.indices.clone(),
            }
        })
    }
    fn name(&self) -> &str {
        &self.name
    }
    fn n_states(&self) -> usize {
        self.inst.layout.n_states
    }
    fn n_constraints(&self) -> usize {
        self.inst.layout.n_rows
    }
    fn n_params(&self) -> usize {
        self.inst.layout.n_params
    }
    fn state_name(&self, i: usize) -> &str {
        self.name_of(Kind::State, i)
    }
    fn alg_name(&self, i: usize) -> &str {
        self.name_of(Kind::Alg, i)
    }
    fn constraint_name(&self, i: usize) -> &str {
        self.name_of(Kind::Constraint, i)
    }
    fn param_name(&self, i: usize) -> &str {
        self.name_of(Kind::Param, i)
    }
    fn indices(&self) -> &[usize] {
        &self.indices
    }
    fn param(&self, i: usize) -> f64 {
        self.inst.params[i]
    }
    fn set_param(&mut self, i: usize, value: f64) {
        self.inst.params[i] = value;
        self.initial_values_follow();
    }
    fn initial_state(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.inst.states);
    }
    fn initial_alg(&self, z: &mut [f64]) {
        z.copy_from_slice(&self.inst.algs);
    }
    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        let inputs = self.inputs.at(t);
        let v = self.values(t, x, z, &self.zero_mu, &inputs);
        self.kernels
            .rhs(&self.inst, &v, &mut self.scratch.borrow_mut(), dx);
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
        let inputs = self.inputs.at(t);
        let v = self.values(t, x, z, mu, &inputs);
        self.kernels.sliding(
            &self.inst,
            &v,
            &mut self.scratch.borrow_mut(),
            w,
            s,
            alpha_hat,
        );
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &self.inst.jacobian.entries
    }
    fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
        let inputs = self.inputs.at(t);
        let v = self.values(t, x, z, &self.zero_mu, &inputs);
        self.kernels
            .jacobian(&self.inst, &v, &mut self.scratch.borrow_mut(), values);
    }
    /// The rate program with the unknowns held (`z' = 0`).
    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        self.omega_rate(t, x, z, &self.zero_rates, beta);
    }
    /// The rate program: `Omega` differentiated along the motion, so `J_Omega zdot`
    /// costs about what `beta` does and `J_Omega` is not evaluated.
    fn omega_rate(&self, t: f64, x: &[f64], z: &[f64], zdot: &[f64], rate: &mut [f64]) -> bool {
        let inputs = self.inputs.at(t);
        let v = Values {
            alg_rates: zdot,
            ..self.values(t, x, z, &self.zero_mu, &inputs)
        };
        self.kernels
            .omega_rate(&self.inst, &v, &mut self.scratch.borrow_mut(), rate);
        true
    }
}
