//! Construction: from sizes, given sets and maps and parameter overrides to an
//! [`Instance`] (set sizes, map arrays, layout, parameter values, initial values, the
//! pattern of `J_Omega`), with the checks that need sizes. This is the reference the
//! back ends follow (the runtime's construction for generated code does the same steps
//! in the same order, with the same checks and messages).
//!
//! Steps, each an error (a [`ConstructError`] with the span of the declaration) when it
//! fails:
//!
//! 1. sizes: the default of each `size`, or the caller's value (an integer >= 0; an
//!    unknown name is an error);
//! 2. set sizes, in declaration order: the formula at these sizes, or the caller's value
//!    for a set given at construction; a set must have at least one element;
//! 3. maps: a given map's array from the caller (one value per element of its domain,
//!    each inside its codomain); every other map evaluated element by element
//!    ([`MapKind`]: a formula's value must lie in `0..|codomain|`, a map read inside a
//!    formula at an element outside its domain is an error, integer overflow is an
//!    error; a chain applies its maps in order; identity; to the unit: 0);
//! 4. the layout ([`Layout::new`]);
//! 5. parameters, in declaration order (a per-element parameter element by element): the
//!    caller's override for a scalar parameter, else its value expression; each value
//!    must be finite;
//! 6. initial states, initial algebraic guesses and the inputs' defaults (value = the
//!    default, derivatives = 0): element by element; each must be finite;
//! 7. incidence ([`Incidence`]): every element of the target set of incidence sums must
//!    be reached by at least one of their maps (a particle in no link);
//! 8. counts: as many constraint rows as algebraic unknowns;
//! 9. the pattern of `J_Omega` from the couplings ([`JacobianPattern::build`]).

use super::ceval::{Env, EvalError, Val};
use super::layout::Layout;
use super::{Construction, Coupling};
use crate::MapId;
use crate::ast::Span;
use crate::diag::Diagnostic;
use crate::model::{MapKind, RExpr};

/// What the caller gives at construction, by name: sizes (the others keep their
/// defaults), the sizes of the sets given at construction, the given maps (edge lists:
/// one value per element of the domain), and overrides of scalar parameters.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spec {
    /// `size` values.
    pub sizes: Vec<(String, i64)>,
    /// Sizes of the sets declared `set NAME;`.
    pub sets: Vec<(String, usize)>,
    /// Values of the maps declared without a formula.
    pub maps: Vec<(String, Vec<u32>)>,
    /// Values of scalar parameters (by name; a vector component as `name.x`).
    pub params: Vec<(String, f64)>,
}

/// Why [`Spec::assign`] refused `name = value`.
#[derive(Clone, Debug, PartialEq)]
pub enum AssignError {
    /// `name` is a size and `value` not a whole number >= 0 (or too large).
    NotWhole,
    /// `name` is a per-element parameter (one value per element of its set), whose
    /// family is given.
    PerElement(String),
    /// The model has no size or scalar parameter `name`.
    Unknown,
}

impl Spec {
    /// Gives a size or a scalar parameter of the model `c` by name (`N = 1000`,
    /// `m_end = 10`), as `daec --set` and an FMU's export do.
    pub fn assign(&mut self, c: &Construction, name: &str, value: f64) -> Result<(), AssignError> {
        if c.sizes.iter().any(|s| s.name == name) {
            if value.fract() != 0.0 || value < 0.0 || value > i64::MAX as f64 / 2.0 {
                return Err(AssignError::NotWhole);
            }
            self.sizes.push((name.to_string(), value as i64));
        } else if c
            .params
            .iter()
            .any(|p| p.name == name && p.family.over.is_none())
        {
            self.params.push((name.to_string(), value));
        } else if let Some(p) = c
            .params
            .iter()
            .find(|p| p.name.split('.').next() == Some(name.split('[').next().unwrap_or("")))
        {
            let family = p.name.split('.').next().unwrap_or(&p.name);
            return Err(AssignError::PerElement(family.to_string()));
        } else {
            return Err(AssignError::Unknown);
        }
        Ok(())
    }
}

/// A construction-time error: what, where (the declaration), and a hint.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstructError {
    /// One line saying what is wrong.
    pub message: String,
    /// The declaration concerned (byte span in the model's source).
    pub span: Span,
    /// How to fix it.
    pub hint: String,
}

impl ConstructError {
    /// As a diagnostic (to render with the source).
    pub fn to_diagnostic(&self) -> Diagnostic {
        self.diagnostic("at construction")
    }

    pub(crate) fn diagnostic(&self, label: &str) -> Diagnostic {
        Diagnostic::new(self.message.clone(), self.span, label).hint(self.hint.clone())
    }
}

impl std::fmt::Display for ConstructError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({})", self.message, self.hint)
    }
}

impl std::error::Error for ConstructError {}

fn cerr(message: String, span: Span, hint: &str) -> ConstructError {
    ConstructError {
        message,
        span,
        hint: hint.into(),
    }
}

fn from_eval(e: EvalError, span: Span) -> ConstructError {
    ConstructError {
        message: e.message,
        span: if e.span == Span::default() {
            span
        } else {
            e.span
        },
        hint: e.hint,
    }
}

/// The pattern of `J_Omega` of an instance: its entries `(row, column)` (sorted,
/// row-major, each once) and, per coupling, the list of `[entry, l, k]` it contributes
/// to (row element `l` of the coupling's constraint, column element `k` of its
/// algebraic unknown).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JacobianPattern {
    /// `(row, column)` of each entry.
    pub entries: Vec<(usize, usize)>,
    /// Per coupling (in the order of the couplings), `[entry, l, k]`.
    pub lists: Vec<Vec<[u32; 3]>>,
}

/// A family model at given sizes: everything construction fixes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Instance {
    /// Value of each `size` (by `SizeId`).
    pub size_values: Vec<i64>,
    /// Number of elements of each set (by `SetId`).
    pub set_sizes: Vec<usize>,
    /// Every map as an array (by `MapId`): element `e` of the domain goes to
    /// `maps[m][e]` (a map from the unit has one value).
    pub maps: Vec<Vec<u32>>,
    /// Where the values live.
    pub layout: Layout,
    /// The parameter vector.
    pub params: Vec<f64>,
    /// Initial states.
    pub states: Vec<f64>,
    /// Initial algebraic guesses.
    pub algs: Vec<f64>,
    /// Input values (each with its derivatives), at their defaults.
    pub inputs: Vec<f64>,
    /// The pattern of `J_Omega`.
    pub jacobian: JacobianPattern,
}

impl Instance {
    /// The size of a set (`None`: the unit, size 1).
    pub fn set_size(&self, s: Option<crate::SetId>) -> usize {
        s.map_or(1, |s| self.set_sizes[s.index()])
    }
}

/// Builds the instance of `c` for `spec`; see the module documentation for the steps and
/// their errors.
pub fn construct(c: &Construction, spec: &Spec) -> Result<Instance, ConstructError> {
    // 1. sizes
    for (name, _) in &spec.sizes {
        if !c.sizes.iter().any(|s| &s.name == name) {
            return Err(cerr(
                format!("unknown size `{name}`"),
                Span::default(),
                "the sizes are declared with `size`",
            ));
        }
    }
    let mut size_values = Vec::with_capacity(c.sizes.len());
    for s in &c.sizes {
        let v = spec
            .sizes
            .iter()
            .find(|(n, _)| n == &s.name)
            .map_or(s.default, |x| x.1);
        if v < 0 {
            return Err(cerr(
                format!("size `{}` = {v} is negative", s.name),
                s.span,
                "a size is a whole number >= 0",
            ));
        }
        size_values.push(v);
    }
    // 2. set sizes
    let set_names: Vec<String> = c.sets.iter().map(|s| s.name.clone()).collect();
    let no_params: Vec<Vec<f64>> = Vec::new();
    let mut set_sizes: Vec<Option<usize>> = vec![None; c.sets.len()];
    for (i, s) in c.sets.iter().enumerate() {
        let n: i64 = match &s.size {
            Some(f) => {
                let mut none = vec![None; c.maps.len()];
                let mut env = Env {
                    sizes: &size_values,
                    set_sizes: &set_sizes,
                    map_defs: &c.maps,
                    maps: &mut none,
                    params: &no_params,
                    set_names: &set_names,
                };
                match env.eval(f, 0).map_err(|e| from_eval(e, s.span))? {
                    Val::I(n) => n,
                    _ => {
                        return Err(cerr(
                            format!("the size of set `{}` is not an integer", s.name),
                            s.span,
                            "a set's size is an integer formula",
                        ));
                    }
                }
            }
            None => match spec.sets.iter().find(|(n, _)| n == &s.name) {
                Some((_, n)) => *n as i64,
                None => {
                    return Err(cerr(
                        format!(
                            "set `{}` is given at construction, but its size was not given",
                            s.name
                        ),
                        s.span,
                        "give the size of this set (or the topology that defines it)",
                    ));
                }
            },
        };
        if n < 1 {
            let sizes = c
                .sizes
                .iter()
                .zip(&size_values)
                .map(|(s, v)| format!("{} = {v}", s.name))
                .collect::<Vec<_>>()
                .join(", ");
            return Err(cerr(
                format!(
                    "set `{}` has {n} elements{}",
                    s.name,
                    if sizes.is_empty() {
                        String::new()
                    } else {
                        format!(" with {sizes}")
                    }
                ),
                s.span,
                "a set needs at least one element: choose larger sizes",
            ));
        }
        set_sizes[i] = Some(n as usize);
    }
    for (name, _) in &spec.sets {
        if !c.sets.iter().any(|s| &s.name == name && s.size.is_none()) {
            return Err(cerr(
                format!("`{name}` is not a set given at construction"),
                Span::default(),
                "only sets declared `set NAME;` take a size at construction",
            ));
        }
    }
    // 3. maps
    let mut maps: Vec<Option<Vec<u32>>> = vec![None; c.maps.len()];
    for (name, values) in &spec.maps {
        let Some(m) = c
            .maps
            .iter()
            .position(|d| &d.name == name && d.kind == MapKind::Given)
        else {
            return Err(cerr(
                format!("`{name}` is not a map given at construction"),
                Span::default(),
                "only maps declared without a formula are given",
            ));
        };
        let def = &c.maps[m];
        let (dn, cn) = (
            size_of(&set_sizes, def.domain),
            size_of(&set_sizes, def.codomain),
        );
        if values.len() != dn {
            return Err(cerr(
                format!(
                    "map `{name}` has {} values, but its domain has {dn} elements",
                    values.len()
                ),
                def.span,
                "give one value per element of the map's domain",
            ));
        }
        if let Some((e, v)) = values.iter().enumerate().find(|(_, v)| **v as usize >= cn) {
            return Err(cerr(
                format!(
                    "map `{name}` points outside its set: element {e} goes to {v}, but the codomain has {cn} elements (0..{cn})"
                ),
                def.span,
                "check the edge list against the set sizes (elements count from 0)",
            ));
        }
        maps[m] = Some(values.clone());
    }
    let mut env = Env {
        sizes: &size_values,
        set_sizes: &set_sizes,
        map_defs: &c.maps,
        maps: &mut maps,
        params: &no_params,
        set_names: &set_names,
    };
    for m in 0..c.maps.len() {
        env.ensure_map(MapId::new(m))
            .map_err(|e| from_eval(e, c.maps[m].span))?;
    }
    // Every map is evaluated: the environments below read them without copying.
    let mut env_maps = maps;
    let maps: Vec<Vec<u32>> = env_maps
        .iter()
        .map(|m| m.clone().unwrap_or_default())
        .collect();
    let set_sizes: Vec<usize> = set_sizes.into_iter().map(|s| s.unwrap_or(1)).collect();
    // 4. layout
    let layout = Layout::new(c, &set_sizes);
    // 5. parameters
    let opt_sizes: Vec<Option<usize>> = set_sizes.iter().map(|&s| Some(s)).collect();
    for (name, _) in &spec.params {
        if !c
            .params
            .iter()
            .any(|p| &p.name == name && p.family.over.is_none())
        {
            return Err(cerr(
                format!("`{name}` is not a scalar parameter"),
                Span::default(),
                "overrides name scalar parameters (`name`, or `name.x` for a component)",
            ));
        }
    }
    let mut param_values: Vec<Vec<f64>> = Vec::with_capacity(c.params.len());
    for p in &c.params {
        let n = size_of(&opt_sizes, p.family.over);
        let values = match spec.params.iter().find(|(name, _)| name == &p.name) {
            Some((_, v)) if p.family.over.is_none() => vec![*v],
            _ => {
                let mut env = Env {
                    sizes: &size_values,
                    set_sizes: &opt_sizes,
                    map_defs: &c.maps,
                    maps: &mut env_maps,
                    params: &param_values,
                    set_names: &set_names,
                };
                eval_all(
                    &mut env,
                    &p.value,
                    n,
                    &format!("the value of parameter `{}`", p.name),
                    p.span,
                )?
            }
        };
        param_values.push(values);
    }
    let mut params = vec![0.0; layout.n_params];
    scatter(&mut params, &layout.params, &param_values);
    // 6. initial values
    let mut env = Env {
        sizes: &size_values,
        set_sizes: &opt_sizes,
        map_defs: &c.maps,
        maps: &mut env_maps,
        params: &param_values,
        set_names: &set_names,
    };
    let mut initial = |defs: &[(String, crate::model::Family, &RExpr, Span)],
                       slots: &[super::layout::Slot],
                       len: usize,
                       what: &str| {
        let mut out = vec![0.0; len];
        for ((name, fam, e, span), slot) in defs.iter().zip(slots) {
            let n = size_of(&opt_sizes, fam.over);
            let values = eval_all(&mut env, e, n, &format!("the {what} of `{name}`"), *span)?;
            for (k, v) in values.into_iter().enumerate() {
                out[slot.at(k)] = v;
            }
        }
        Ok::<Vec<f64>, ConstructError>(out)
    };
    let states = initial(
        &c.states
            .iter()
            .map(|s| (s.name.clone(), s.family, &s.init, s.span))
            .collect::<Vec<_>>(),
        &layout.states,
        layout.n_states,
        "initial value",
    )?;
    let algs = initial(
        &c.algs
            .iter()
            .map(|s| (s.name.clone(), s.family, &s.init, s.span))
            .collect::<Vec<_>>(),
        &layout.algs,
        layout.n_algs,
        "initial guess",
    )?;
    let inputs = initial(
        &c.inputs
            .iter()
            .map(|s| (s.name.clone(), s.family, &s.default, s.span))
            .collect::<Vec<_>>(),
        &layout.input_values,
        layout.n_input_values,
        "default",
    )?;
    // 7. incidence
    for inc in &c.incidence {
        let n = set_sizes[inc.set.index()];
        let mut reached = vec![false; n];
        for m in &inc.maps {
            for &q in &maps[m.index()] {
                reached[q as usize] = true;
            }
        }
        if let Some(q) = reached.iter().position(|r| !r) {
            let set = &c.sets[inc.set.index()];
            let how: Vec<String> = inc.maps.iter().map(|m| map_words(c, *m)).collect();
            return Err(cerr(
                format!(
                    "element {q} of `{}` is in no sum: no element has {} equal to {q}",
                    set.name,
                    how.join(" or ")
                ),
                inc.span,
                "every element of a set summed over by incidence must be reached (a particle in no link): check the maps and sizes",
            ));
        }
    }
    // 8. counts
    if layout.n_rows != layout.n_algs {
        let span = c.constraints.first().map_or(Span::default(), |k| k.span);
        return Err(cerr(
            format!(
                "{} constraints but {} algebraic unknowns with these sizes",
                layout.n_rows, layout.n_algs
            ),
            span,
            "each constraint determines one algebraic unknown: the families must have as many elements",
        ));
    }
    let mut inst = Instance {
        size_values,
        set_sizes,
        maps,
        layout,
        params,
        states,
        algs,
        inputs,
        jacobian: JacobianPattern::default(),
    };
    // 9. the pattern; a small model without sets lists every entry, as its tapes do
    inst.jacobian = JacobianPattern::build(&c.couplings, &inst);
    let m = inst.layout.n_rows;
    if c.sets.is_empty() && m <= crate::DENSE_JACOBIAN_MAX {
        inst.jacobian = inst.jacobian.dense(m);
    }
    Ok(inst)
}

/// How a map reads in a message: `a[l]`, or the map's printed name.
fn map_words(c: &Construction, m: MapId) -> String {
    let d = &c.maps[m.index()];
    let elem = d
        .domain
        .map_or("0".to_string(), |s| c.sets[s.index()].elem.clone());
    if d.name.is_empty() {
        format!("the formula of element `{elem}`")
    } else {
        format!("{}[{elem}]", d.name)
    }
}

fn size_of(sizes: &[Option<usize>], s: Option<crate::SetId>) -> usize {
    s.map_or(1, |s| sizes[s.index()].unwrap_or(1))
}

/// The values of `e` at elements `0..n`, each finite and real.
fn eval_all(
    env: &mut Env<'_>,
    e: &RExpr,
    n: usize,
    what: &str,
    span: Span,
) -> Result<Vec<f64>, ConstructError> {
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let v = env.eval(e, k).map_err(|x| from_eval(x, span))?;
        let v = match v {
            Val::B(_) => {
                return Err(cerr(
                    format!("{what} is a condition"),
                    span,
                    "write `if c then 1 else 0`",
                ));
            }
            v => v.real(),
        };
        if !v.is_finite() {
            let at = if n > 1 {
                format!(" at element {k}")
            } else {
                String::new()
            };
            return Err(cerr(
                format!("{what} is {v}{at}"),
                span,
                "look for a division by zero, an overflow, or a function outside its domain (ln, sqrt, asin, acos)",
            ));
        }
        out.push(v);
    }
    Ok(out)
}

fn scatter(out: &mut [f64], slots: &[super::layout::Slot], values: &[Vec<f64>]) {
    for (slot, vs) in slots.iter().zip(values) {
        for (k, v) in vs.iter().enumerate() {
            out[slot.at(k)] = *v;
        }
    }
}

impl JacobianPattern {
    /// The pattern of `J_Omega` from the couplings: for each coupling (constraint `c`
    /// over `L`, algebraic unknown `a` over `K`, maps `r: L -> X`, `q: K -> X`), the
    /// entries `(row(c, l), col(a, k))` for every `l` and every `k` with `q(k) == r(l)`
    /// (found through the inverse of `q`); entries of several couplings at the same
    /// place are one entry; entries sorted by row, then column. Linear in the number of
    /// entries (plus a sort).
    pub fn build(couplings: &[Coupling], inst: &Instance) -> JacobianPattern {
        let mut raw: Vec<(usize, usize, u32, u32, u32)> = Vec::new(); // row, col, coupling, l, k
        for (ci, c) in couplings.iter().enumerate() {
            let row_map = &inst.maps[c.row_map.index()];
            let col_map = &inst.maps[c.col_map.index()];
            let x = col_map
                .iter()
                .chain(row_map)
                .map(|&v| v as usize + 1)
                .max()
                .unwrap_or(0);
            // Inverse of the column map as CSR: for each x, the k with q(k) == x.
            let mut start = vec![0u32; x + 1];
            for &v in col_map {
                start[v as usize + 1] += 1;
            }
            for i in 1..start.len() {
                start[i] += start[i - 1];
            }
            let mut fill = start.clone();
            let mut ks = vec![0u32; col_map.len()];
            for (k, &v) in col_map.iter().enumerate() {
                ks[fill[v as usize] as usize] = k as u32;
                fill[v as usize] += 1;
            }
            let rows = inst.layout.rows[c.constraint.index()];
            let cols = inst.layout.algs[c.alg.index()];
            for (l, &v) in row_map.iter().enumerate() {
                let v = v as usize;
                if v + 1 >= start.len() {
                    continue;
                }
                for &k in &ks[start[v] as usize..start[v + 1] as usize] {
                    raw.push((rows.at(l), cols.at(k as usize), ci as u32, l as u32, k));
                }
            }
        }
        raw.sort_unstable_by_key(|&(r, c, ..)| (r, c));
        let mut entries: Vec<(usize, usize)> = Vec::new();
        let mut lists = vec![Vec::new(); couplings.len()];
        for (r, c, ci, l, k) in raw {
            if entries.last() != Some(&(r, c)) {
                entries.push((r, c));
            }
            lists[ci as usize].push([(entries.len() - 1) as u32, l, k]);
        }
        JacobianPattern { entries, lists }
    }

    /// The same pattern with every entry of the `m x m` matrix listed (the structural
    /// zeros too), row-major; each coupling's list points at the same places.
    fn dense(self, m: usize) -> JacobianPattern {
        let at = |(r, c): (usize, usize)| (r * m + c) as u32;
        let lists = self
            .lists
            .iter()
            .map(|list| {
                list.iter()
                    .map(|&[e, l, k]| [at(self.entries[e as usize]), l, k])
                    .collect()
            })
            .collect();
        let entries = (0..m).flat_map(|r| (0..m).map(move |c| (r, c))).collect();
        JacobianPattern { entries, lists }
    }
}
