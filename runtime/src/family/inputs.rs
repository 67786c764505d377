//! Inputs of a sized family model: values the caller sets during a run, each with the
//! time derivatives its declaration promises (`input pin[p in P]: vec3 with 3
//! derivatives`), given as a Taylor polynomial at a time `t0`.
//!
//! **The rule.** `set_input(i, t0, &[c0, c1, .., cK'])` (`K' <= K`) makes input `i`
//! the polynomial `q(t) = sum_k c_k (t - t0)^k / k!` from then on, until the next
//! `set_input` of `i`: every evaluation at time `t` (any `t`, before or after `t0`,
//! RK4 stages included) reads `q(t)` and its derivatives `q'(t) .. q^(K)(t)`, the
//! derivatives not given being zero. Between two calls the polynomial is extrapolated:
//! a caller that drives an input along a curve gives, at each of its own steps, the
//! curve's value and derivatives there (a constant-acceleration hand is exact with
//! `[x, v, a]`). An input never set keeps its declared default with zero derivatives.
//!
//! Only inputs with a nonzero derivative are re-evaluated when `t` changes, so a model
//! with 10^5 pinned-or-free particles and one moving hand pays for one input.

use std::cell::RefCell;

use dae_lang::family::{Construction, Instance};

/// Why `set_input` refused its data.
#[derive(Clone, Debug, PartialEq)]
pub enum InputError {
    /// There is no input with this flat index.
    UnknownIndex {
        /// The index given.
        index: usize,
        /// The number of inputs (flat, over all elements and components).
        n_inputs: usize,
    },
    /// More derivatives than the declaration carries (they would be lost).
    TooManyDerivatives {
        /// The input's name (`pin[3].x`).
        name: String,
        /// Values given (value and derivatives).
        given: usize,
        /// The derivatives the declaration carries (`with K derivatives`).
        order: usize,
    },
    /// No value at all, or a value that is not a finite number.
    BadValue {
        /// The input's name.
        name: String,
        /// What was given.
        values: Vec<f64>,
    },
}

impl std::fmt::Display for InputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InputError::UnknownIndex { index, n_inputs } => write!(
                f,
                "no input {index}: the model has {n_inputs} input values (0..{n_inputs}); look inputs up by name with `input_index`"
            ),
            InputError::TooManyDerivatives { name, given, order } => write!(
                f,
                "input `{name}` carries {order} time derivatives, but {given} values were given (the value and at most {order} derivatives); declare it `with {} derivatives` to use them",
                given - 1
            ),
            InputError::BadValue { name, values } => write!(
                f,
                "input `{name}` needs its value (and derivatives) as finite numbers, got {values:?}"
            ),
        }
    }
}

impl std::error::Error for InputError {}

/// The Taylor data of every input and the values read by the evaluations.
///
/// The coefficients are kept per input (`[c0, .., cK]` together, for `taylor`); the
/// values are in the instance's layout, where the derivatives of one input are a
/// derivative block apart (see `dae_lang::family::Layout`).
#[derive(Debug)]
pub(crate) struct Inputs {
    /// Per flat input index: where its value (derivative 0) sits in the value vector.
    value_at: Vec<u32>,
    /// Per flat input index: the distance between two of its derivatives there.
    step: Vec<u32>,
    /// Per flat input index: its derivative count `K`.
    order: Vec<u8>,
    /// Per flat input index: where its coefficients start in `coeffs`.
    coeffs_at: Vec<u32>,
    /// Taylor coefficients at `t0`, `K + 1` per input, by flat input index.
    coeffs: Vec<f64>,
    /// Per flat input index: the time of its coefficients.
    t0: Vec<f64>,
    /// The inputs with a nonzero derivative (re-evaluated when `t` changes).
    moving: Vec<u32>,
    is_moving: Vec<bool>,
    /// The values at `cache.0` (NaN: stale).
    cache: RefCell<(f64, Vec<f64>)>,
}

impl Inputs {
    pub fn new(c: &Construction, inst: &Instance) -> Inputs {
        let l = &inst.layout;
        let mut value_at = vec![0u32; l.n_inputs];
        let mut step = vec![0u32; l.n_inputs];
        let mut order = vec![0u8; l.n_inputs];
        for (k, d) in c.inputs.iter().enumerate() {
            for e in 0..inst.set_size(d.family.over) {
                let i = l.inputs[k].at(e);
                value_at[i] = l.input_values[k].at(e) as u32;
                step[i] = l.input_derivative_step[k] as u32;
                order[i] = d.derivatives;
            }
        }
        let mut coeffs_at = Vec::with_capacity(l.n_inputs);
        let mut coeffs = Vec::with_capacity(l.n_input_values);
        for i in 0..l.n_inputs {
            coeffs_at.push(coeffs.len() as u32);
            let (a, s) = (value_at[i] as usize, step[i] as usize);
            coeffs.extend((0..=order[i] as usize).map(|j| inst.inputs[a + j * s]));
        }
        Inputs {
            value_at,
            step,
            order,
            coeffs_at,
            coeffs,
            t0: vec![0.0; l.n_inputs],
            moving: Vec::new(),
            is_moving: vec![false; l.n_inputs],
            cache: RefCell::new((f64::NAN, inst.inputs.clone())),
        }
    }

    pub fn len(&self) -> usize {
        self.order.len()
    }

    pub fn order(&self, i: usize) -> usize {
        self.order[i] as usize
    }

    /// The coefficients of input `i`.
    fn coeffs(&self, i: usize) -> &[f64] {
        let a = self.coeffs_at[i] as usize;
        &self.coeffs[a..=a + self.order(i)]
    }

    /// The current Taylor data of input `i`: `t0` and `[c0, .., cK]`.
    pub fn taylor(&self, i: usize) -> (f64, &[f64]) {
        (self.t0[i], self.coeffs(i))
    }

    /// Sets input `i` (checked by the caller: `i` exists, `data` fits).
    pub fn set(&mut self, i: usize, t0: f64, data: &[f64]) {
        let a = self.coeffs_at[i] as usize;
        let k = self.order(i);
        let c = &mut self.coeffs[a..=a + k];
        c.fill(0.0);
        c[..data.len()].copy_from_slice(data);
        self.t0[i] = t0;
        let moving = data[1..].iter().any(|d| *d != 0.0);
        if moving && !self.is_moving[i] {
            self.moving.push(i as u32);
        } else if !moving && self.is_moving[i] {
            let at = self.moving.iter().position(|m| *m as usize == i);
            if let Some(at) = at {
                self.moving.swap_remove(at);
            }
        }
        self.is_moving[i] = moving;
        let (v, s) = (self.value_at[i] as usize, self.step[i] as usize);
        let cache = self.cache.get_mut();
        for (j, cj) in c.iter().enumerate() {
            cache.1[v + j * s] = *cj;
        }
        cache.0 = f64::NAN;
    }

    /// The value vector at time `t` (value and derivatives of every input).
    pub fn at(&self, t: f64) -> std::cell::Ref<'_, Vec<f64>> {
        let stale = self.cache.borrow().0.to_bits() != t.to_bits();
        if stale && !self.moving.is_empty() {
            let mut cache = self.cache.borrow_mut();
            for &i in &self.moving {
                let i = i as usize;
                let (v, s) = (self.value_at[i] as usize, self.step[i] as usize);
                let k = self.order(i);
                let dt = t - self.t0[i];
                let c = self.coeffs(i);
                for j in 0..=k {
                    // q^(j)(t) = sum_{m=0}^{K-j} c_{j+m} dt^m / m!  (Horner)
                    let mut acc = 0.0;
                    for m in (0..=k - j).rev() {
                        acc = acc * dt / (m + 1) as f64 + c[j + m];
                    }
                    cache.1[v + j * s] = acc;
                }
            }
            cache.0 = t;
        }
        std::cell::Ref::map(self.cache.borrow(), |c| &c.1)
    }
}
