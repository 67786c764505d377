//! Where every value of a family model lives in the flat vectors of the runtime, once the
//! sets have their sizes.
//!
//! * **Parameters** (`params`): the scalar parameters (every component of a scalar
//!   declaration) first, in declaration order; then each per-element declaration in
//!   declaration order, `|S| * dim` values, element-major with the components
//!   interleaved (`m[p]` at `off + p`, `pin0[p].y` at `off + 3 p + 1`).
//! * **States** (`x`, `dx`) and **algebraic unknowns** (`z`): declarations in order; a
//!   scalar declaration takes `dim` slots, a family over `S` takes `|S| * dim`,
//!   element-major, components interleaved.
//! * **Constraints** (rows of `J_Omega`, `s`, `alpha_hat`, `beta`, `mu`): declarations
//!   in order, one row for a single constraint, `|S|` rows for a family over `S`
//!   (element-major). **Columns** of `J_Omega` are the algebraic unknowns' slots.
//! * **w** (the derivatives of the constraints): constraint-major as in version 1, the
//!   `r` derivatives of a row together: family `c` with index `r`, element `l`,
//!   derivative `j` at `w_off(c) + r l + j`.
//! * **Inputs**: each input component element `(e, c)` has a flat *input index*
//!   (declarations in order, `|S| * dim` each, element-major, components interleaved:
//!   the index of `set_input`), and `K + 1` *input values* (the value and its `K` time
//!   derivatives). A declaration's values are derivative-major: all its values
//!   (element-major, components interleaved, as a state), then all its first
//!   derivatives, and so on: derivative `j` of `(e, c)` at
//!   `values_off(decl) + j |S| dim + dim e + c` (`|S| = 1` for a scalar). A function
//!   that reads only the value (`rhs`, `J_Omega`) so streams only the value block, not
//!   the derivatives beside it.
//!
//! Every slot of a component family is `offset + stride * e` for element `e` (stride 0
//! for a scalar): a [`Slot`].

use super::Construction;
use crate::model::Family;

/// The slots of one component family: element `e` at `offset + stride * e`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Slot {
    /// The slot of element 0.
    pub offset: usize,
    /// The distance between the slots of two consecutive elements (0 for a scalar).
    pub stride: usize,
}

impl Slot {
    /// The slot of element `e`.
    #[inline]
    pub fn at(self, e: usize) -> usize {
        self.offset + self.stride * e
    }
}

/// The layout of a family model at given set sizes; see the module documentation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layout {
    /// By parameter component (`ParamId`).
    pub params: Vec<Slot>,
    /// Length of the parameter vector.
    pub n_params: usize,
    /// By state component (`StateId`).
    pub states: Vec<Slot>,
    /// Length of the state vector.
    pub n_states: usize,
    /// By algebraic component (`AlgId`): also the columns of `J_Omega`.
    pub algs: Vec<Slot>,
    /// Length of the algebraic vector (the number of columns).
    pub n_algs: usize,
    /// By constraint declaration (`ConstraintId`): rows.
    pub rows: Vec<Slot>,
    /// Number of constraints (rows).
    pub n_rows: usize,
    /// By constraint declaration: the slot of `w^(0)` of each element (stride = index).
    pub w: Vec<Slot>,
    /// Length of the w vector (`sum r_i` over rows).
    pub n_w: usize,
    /// By input component (`InputId`): the slot of the value (derivative 0) of each
    /// element; derivative `j` is `j * input_derivative_step[i]` further (see
    /// [`Layout::input_value`]).
    pub input_values: Vec<Slot>,
    /// By input component: the distance between two consecutive derivatives of one
    /// element (the length of its declaration's block of one derivative).
    pub input_derivative_step: Vec<usize>,
    /// Length of the input value vector.
    pub n_input_values: usize,
    /// By input component: the flat input index of each element.
    pub inputs: Vec<Slot>,
    /// Number of input components over all elements.
    pub n_inputs: usize,
}

/// Lays out the component families `fams` (in id order; consecutive components of one
/// declaration share a block), each with `k` blocks (`k` > 1: an input's derivatives):
/// a declaration of `dim` components over `S` takes `k` blocks of `|S| * dim` values,
/// element-major with the components interleaved. Scalars come first if
/// `scalars_first` (parameters), else everything is in declaration order. Returns the
/// slots of block 0, the length of one block by component, and the total length.
fn lay_out(
    fams: &[(Family, usize)],
    set_sizes: &[usize],
    scalars_first: bool,
) -> (Vec<Slot>, Vec<usize>, usize) {
    let mut slots = vec![Slot::default(); fams.len()];
    let mut blocks = vec![0; fams.len()];
    let mut next = 0;
    let passes: &[Option<bool>] = if scalars_first {
        &[Some(true), Some(false)]
    } else {
        &[None]
    };
    for pass in passes {
        let mut i = 0;
        while i < fams.len() {
            let (f, k) = fams[i];
            let dim = f.dim.max(1) as usize;
            let scalar = f.over.is_none();
            if pass.is_none_or(|want_scalar| want_scalar == scalar) {
                let n = f.over.map_or(1, |s| set_sizes[s.index()]);
                for c in 0..dim {
                    slots[i + c] = Slot {
                        offset: next + c,
                        stride: if scalar { 0 } else { dim },
                    };
                    blocks[i + c] = n * dim;
                }
                next += n * dim * k;
            }
            i += dim;
        }
    }
    (slots, blocks, next)
}

impl Layout {
    /// The slots of derivative `j` (0: the value) of input component `i`.
    #[inline]
    pub fn input_value(&self, i: usize, j: usize) -> Slot {
        let v = self.input_values[i];
        Slot {
            offset: v.offset + j * self.input_derivative_step[i],
            stride: v.stride,
        }
    }

    /// The layout of `c` with these set sizes (by `SetId`).
    pub fn new(c: &Construction, set_sizes: &[usize]) -> Layout {
        let fam = |f: Family| (f, 1);
        let params: Vec<(Family, usize)> = c.params.iter().map(|p| fam(p.family)).collect();
        let states: Vec<(Family, usize)> = c.states.iter().map(|s| fam(s.family)).collect();
        let algs: Vec<(Family, usize)> = c.algs.iter().map(|a| fam(a.family)).collect();
        let inputs: Vec<(Family, usize)> = c.inputs.iter().map(|i| fam(i.family)).collect();
        let input_values: Vec<(Family, usize)> = c
            .inputs
            .iter()
            .map(|i| (i.family, i.derivatives as usize + 1))
            .collect();
        let (params, _, n_params) = lay_out(&params, set_sizes, true);
        let (states, _, n_states) = lay_out(&states, set_sizes, false);
        let (algs, _, n_algs) = lay_out(&algs, set_sizes, false);
        let (inputs, _, n_inputs) = lay_out(&inputs, set_sizes, false);
        let (input_values, input_derivative_step, n_input_values) =
            lay_out(&input_values, set_sizes, false);
        let mut rows = Vec::with_capacity(c.constraints.len());
        let mut w = Vec::with_capacity(c.constraints.len());
        let (mut n_rows, mut n_w) = (0, 0);
        for k in &c.constraints {
            let n = k.over.map_or(1, |s| set_sizes[s.index()]);
            let scalar = k.over.is_none();
            rows.push(Slot {
                offset: n_rows,
                stride: usize::from(!scalar),
            });
            w.push(Slot {
                offset: n_w,
                stride: if scalar { 0 } else { k.index },
            });
            n_rows += n;
            n_w += n * k.index;
        }
        Layout {
            params,
            n_params,
            states,
            n_states,
            algs,
            n_algs,
            rows,
            n_rows,
            w,
            n_w,
            input_values,
            input_derivative_step,
            n_input_values,
            inputs,
            n_inputs,
        }
    }
}
