//! A vector family's components of one element, read and written as one array.
//!
//! The components of a `vec3` family sit side by side in their vector (the layout puts
//! component `j` of element `e` at `offset + 3 e + j`, and `w^(j)` of a constraint of
//! index `r` at `offset + r e + j`). Indexed one by one, each component costs a bounds
//! check, and the checks of `x + 3 e`, `x + 3 e + 1` and `x + 3 e + 2` are three: the
//! compiler cannot merge them, since it does not know the three offsets are consecutive.
//! A loop body that reads two or more components of one element (at `e`, or through a
//! map at `m[e]`) takes them once, as a `&[f64; dim]` from one range check, and reads
//! the components from it at constant positions; a body that writes two or more of an
//! element's outputs of one family writes them through one `&mut [f64; dim]`. The
//! values and the operations on them are the same, so the results are the same bits.
//!
//! `Kernels::scratch` checks once per instance that the layout's offsets are
//! consecutive ([`offset_check`]), as it checks the strides.

use std::collections::BTreeMap;

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use dae_lang::family::{Construction, Dest, Group, Sink};
use dae_lang::model::Family;
use dae_lang::tape::Operand;
use dae_lang::{AlgId, InputId, ParamId, StateId, VarRef};

use crate::literals::{lang, map_ident, usize_lit, var_ident, var_source};

/// Where a declared variable stands among the declarations of its kind (`None` for
/// `t`, `mu`, elements and sizes).
fn position(v: VarRef) -> Option<usize> {
    match v {
        VarRef::Param(i) => Some(i.index()),
        VarRef::State(i) => Some(i.index()),
        VarRef::Alg(i) | VarRef::AlgRate(i) => Some(i.index()),
        VarRef::Input(i, _) => Some(i.index()),
        VarRef::Mu(_) | VarRef::Time | VarRef::Elem(_) | VarRef::Size(_) => None,
    }
}

/// The family of declaration `k` of `v`'s kind: parameters, states, algebraic unknowns
/// (for `z` and `z'`) or inputs; `None` past their end and for the other leaves.
fn family_at(v: VarRef, k: usize, c: &Construction) -> Option<Family> {
    match v {
        VarRef::Param(_) => c.params.get(k).map(|d| d.family),
        VarRef::State(_) => c.states.get(k).map(|d| d.family),
        VarRef::Alg(_) | VarRef::AlgRate(_) => c.algs.get(k).map(|d| d.family),
        VarRef::Input(..) => c.inputs.get(k).map(|d| d.family),
        _ => None,
    }
}

/// The family of a declared variable (`None` for `t`, `mu`, elements and sizes).
pub(crate) fn family_of(v: VarRef, c: &Construction) -> Option<Family> {
    family_at(v, position(v)?, c)
}

/// The families of the declarations of each layout table with a slot per declared
/// component, by the table's name in the layout.
pub(crate) fn layout_families(c: &Construction) -> [(&'static str, Vec<Family>); 4] {
    [
        ("params", c.params.iter().map(|d| d.family).collect()),
        ("states", c.states.iter().map(|d| d.family).collect()),
        ("algs", c.algs.iter().map(|d| d.family).collect()),
        ("input_values", c.inputs.iter().map(|d| d.family).collect()),
    ]
}

/// A component of a vector family: the variable of its component 0, which component it
/// is, and how many there are. `None` for a scalar or a single-component family.
pub(crate) fn vector_component(v: VarRef, c: &Construction) -> Option<(VarRef, usize, usize)> {
    let i = position(v)?;
    let f = family_at(v, i, c)?;
    let (j, dim) = (usize::from(f.component), usize::from(f.dim));
    if f.over.is_none() || dim < 2 {
        return None;
    }
    let first = i - j;
    // The components of one declaration are consecutive ids (`Construction`); anything
    // else is read one component at a time.
    let consecutive = (0..dim).all(|k| {
        family_at(v, first + k, c).is_some_and(|g| {
            g.over == f.over && usize::from(g.dim) == dim && usize::from(g.component) == k
        })
    });
    if !consecutive {
        return None;
    }
    let base = match v {
        VarRef::Param(_) => VarRef::Param(ParamId::new(first)),
        VarRef::State(_) => VarRef::State(StateId::new(first)),
        VarRef::Alg(_) => VarRef::Alg(AlgId::new(first)),
        VarRef::AlgRate(_) => VarRef::AlgRate(AlgId::new(first)),
        VarRef::Input(_, d) => VarRef::Input(InputId::new(first), d),
        _ => unreachable!("matched above"),
    };
    Some((base, j, dim))
}

/// Where a group reads an element: at `e`, or through map `m` at `m[e]`.
type At = Option<usize>;

/// The vector reads of one loop body: for each family (its component 0) and place,
/// the components read, and the local the array is bound to.
pub(crate) struct VectorReads {
    reads: BTreeMap<(VarRef, At), Read>,
}

struct Read {
    dim: usize,
    /// Component `j` and the variable it is, for each component read.
    components: BTreeMap<usize, VarRef>,
}

impl VectorReads {
    /// The reads of `g` worth taking as arrays: two components or more of one element.
    pub(crate) fn of(g: &Group, c: &Construction) -> VectorReads {
        let mut reads: BTreeMap<(VarRef, At), Read> = BTreeMap::new();
        if g.over.is_some() {
            for o in g.tape.operands() {
                let (v, at) = match o {
                    Operand::Input(v) => (v, None),
                    Operand::Gather(v, m) => (v, Some(m.index())),
                    _ => continue,
                };
                if let Some((base, j, dim)) = vector_component(v, c) {
                    let read = reads.entry((base, at)).or_insert(Read {
                        dim,
                        components: BTreeMap::new(),
                    });
                    read.components.insert(j, v);
                }
            }
        }
        reads.retain(|_, r| r.components.len() >= 2);
        VectorReads { reads }
    }

    fn local(base: VarRef, at: At) -> Ident {
        let v = var_ident(base);
        match at {
            None => format_ident!("{v}_e"),
            Some(m) => format_ident!("{v}_m{m}"),
        }
    }

    /// The read of `v` (at `e`, or through map `at`) from its array, if it is one.
    pub(crate) fn operand(&self, v: VarRef, at: At, c: &Construction) -> Option<TokenStream> {
        let (base, j, _) = vector_component(v, c)?;
        self.reads.get(&(base, at))?;
        let local = Self::local(base, at);
        let j = usize_lit(j);
        Some(quote!(#local[#j]))
    }

    /// The `let`s at the top of the loop body: each array from one range of its vector.
    /// The start is the slot of the first component read, less its component.
    pub(crate) fn bindings(&self) -> TokenStream {
        let lets = self.reads.iter().map(|(&(base, at), read)| {
            let local = Self::local(base, at);
            let (&j, &v) = read
                .components
                .iter()
                .next()
                .expect("two components or more");
            let (vec, _) = var_source(v).expect("a variable read from a vector");
            let slot = var_ident(v);
            let dim = usize_lit(read.dim);
            let element = match at {
                None => quote!(e),
                Some(m) => {
                    let m = map_ident(m);
                    quote!((#m[e] as usize))
                }
            };
            let first = if j == 0 {
                quote!(#slot)
            } else {
                let j = usize_lit(j);
                quote!((#slot - #j))
            };
            quote! {
                let #local: &[f64; #dim] = {
                    let at = #first + #dim * #element;
                    <&[f64; #dim]>::try_from(&#vec[at..at + #dim]).unwrap()
                };
            }
        });
        quote!(#(#lets)*)
    }
}

/// The outputs of one loop body that go out as arrays, by output and family: the
/// output vector, where the element's array starts (less `dim * e`), and the values by
/// component.
pub(crate) struct VectorWrites {
    writes: BTreeMap<(usize, usize), Write>,
}

#[derive(Default)]
struct Write {
    dim: usize,
    out: TokenStream,
    start: TokenStream,
    values: BTreeMap<usize, TokenStream>,
}

impl VectorWrites {
    /// Where an output of `g` goes in an array: its output, its family's key, its
    /// component and the dimension; `None` where it is written alone.
    fn place(g: &Group, d: Dest, c: &Construction) -> Option<((usize, usize), usize, usize)> {
        g.over?;
        match d {
            Dest::Rhs(x) => {
                let (_, j, dim) = vector_component(VarRef::State(x), c)?;
                Some(((d.output(), x.index() - j), j, dim))
            }
            Dest::W(k, j) => {
                let r = c.constraints[k.index()].index;
                (r >= 2).then_some(((d.output(), k.index()), j as usize, r))
            }
            Dest::S(_) | Dest::AlphaHat(_) | Dest::Rate(_) => None,
        }
    }

    /// The output families of `g` with two or more outputs in it: only those are
    /// worth an array.
    pub(crate) fn of(g: &Group, c: &Construction) -> VectorWrites {
        let mut count: BTreeMap<(usize, usize), usize> = BTreeMap::new();
        for s in &g.sinks {
            if let Sink::Out(d) = *s {
                if let Some((key, _, _)) = Self::place(g, d, c) {
                    *count.entry(key).or_default() += 1;
                }
            }
        }
        let writes = count
            .into_iter()
            .filter(|&(_, n)| n >= 2)
            .map(|(key, _)| (key, Write::default()))
            .collect();
        VectorWrites { writes }
    }

    /// Takes `value` for output `d` if it goes out in an array; gives it back otherwise.
    /// `slot` is the local holding `d`'s slot of element 0: a state component's own
    /// (the array starts `j` before it), `w^(0)`'s for any `w^(j)`.
    pub(crate) fn take(
        &mut self,
        g: &Group,
        d: Dest,
        c: &Construction,
        out: &TokenStream,
        slot: &Ident,
        value: TokenStream,
    ) -> Option<TokenStream> {
        let Some((key, j, dim)) = Self::place(g, d, c) else {
            return Some(value);
        };
        let Some(w) = self.writes.get_mut(&key) else {
            return Some(value);
        };
        if w.values.is_empty() {
            w.dim = dim;
            w.out = out.clone();
            w.start = match d {
                Dest::Rhs(_) if j > 0 => {
                    let j = usize_lit(j);
                    quote!((#slot - #j))
                }
                _ => quote!(#slot),
            };
        }
        w.values.insert(j, value);
        None
    }

    /// The writes, one block per array, after the body's other sinks.
    pub(crate) fn blocks(&self) -> TokenStream {
        let blocks = self.writes.values().map(|w| {
            let dim = usize_lit(w.dim);
            let (out, start) = (&w.out, &w.start);
            let sets = w.values.iter().map(|(&j, v)| {
                let j = usize_lit(j);
                quote!(o[#j] = #v;)
            });
            quote! {{
                let at = #start + #dim * e;
                let o = <&mut [f64; #dim]>::try_from(&mut #out[at..at + #dim]).unwrap();
                #(#sets)*
            }}
        });
        quote!(#(#blocks)*)
    }
}

/// The check, once per instance, that each vector family's components sit side by
/// side in the instance's layout (what the arrays above read and write).
pub(crate) fn offset_check(c: &Construction) -> TokenStream {
    let pairs = |families: Vec<Family>| -> Vec<(usize, usize)> {
        families
            .iter()
            .enumerate()
            .filter(|(_, f)| f.over.is_some() && f.dim >= 2 && f.component > 0)
            .map(|(i, f)| (i, i - usize::from(f.component)))
            .collect()
    };
    let tables = layout_families(c).map(|(table, families)| (table, pairs(families)));
    let checks: Vec<TokenStream> = tables
        .iter()
        .filter(|(_, v)| !v.is_empty())
        .map(|(table, pairs)| {
            let t = format_ident!("{table}");
            let pairs = pairs.iter().map(|&(i, first)| {
                let (i, first) = (usize_lit(i), usize_lit(first));
                quote!((#i, #first))
            });
            let pairs = quote!(&[#(#pairs),*]);
            let steps = (*table == "input_values").then(|| {
                quote! {
                    for &(i, first) in #pairs {
                        let step = &inst.layout.input_derivative_step;
                        assert_eq!(step[i], step[first], "the instance's layout is not the generated code's");
                    }
                }
            });
            quote! {
                side_by_side(&inst.layout.#t, #pairs);
                #steps
            }
        })
        .collect();
    if checks.is_empty() {
        return TokenStream::new();
    }
    let dl = lang();
    quote! {
        // Component `i` of a vector family right after component `first`'s slot.
        let side_by_side = |slots: &[#dl::family::Slot], pairs: &[(usize, usize)]| {
            for &(i, first) in pairs {
                let ok = slots[i].offset == slots[first].offset + (i - first);
                assert!(ok, "the instance's layout is not the generated code's");
            }
        };
        #(#checks)*
    }
}
