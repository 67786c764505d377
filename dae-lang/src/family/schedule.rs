//! From the template expressions of a family model to its programs.
//!
//! Scheduling: the *level* of a node is 0 for a leaf (and a leaf read through a map),
//! the maximum of its children's for arithmetic, and one more than its child's for a
//! sum (whose body runs in a loop over the summation set before the sum is read) and a
//! gather of a non-leaf (which reads the array the child was stored in). An arithmetic
//! node is computed in the group `(level, context)`; groups run by level, the scalar
//! group of a level first, then one loop per set. A node used by another group (or read
//! through a map) is stored into an array over its context; leaves never are. The body
//! of a sum is scatter-added into the sum's array by a loop over the summation set.
//! Sums into one codomain that only a linear combination reads, with equal or opposite
//! coefficients there, share one array: the chain's `sum(l where a[l] == p) z[l] u[l] -
//! sum(l where b[l] == p) z[l] u[l]` is one accumulator, added into at `a[l]` and
//! subtracted from at `b[l]` ([`shared_accumulators`]). A version-1 model is scheduled
//! here too: it has no sets, so each program is one group run once.

use std::collections::{BTreeMap, HashMap};

use super::program::{ArrayDef, Dest, EntryLoop, Factor, Group, Program, Sink};
use crate::sym::{Arena, Id, Node};
use crate::tape::Operand;
use crate::tape::emit::Emitter;
use crate::{ArrayId, SetId, VarRef};

/// A root of a program: a node and where its value goes.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Root {
    /// Written to an output for every element of the set (or once).
    Out(Id, Dest, Option<SetId>),
    /// A factor of a `J_Omega` kernel: stored in an array over its own context.
    Factor(Id),
}

/// A group key: level, then context (scalar first, then by set).
type Key = (u32, Option<SetId>);

struct Scheduler<'a> {
    arena: &'a Arena,
    level: HashMap<Id, u32>,
    /// Array of each materialised node (and the accumulator of each sum).
    arrays: HashMap<Id, ArrayId>,
    defs: Vec<ArrayDef>,
    /// Per group: the sinks to add after its computed nodes: (node read, sink).
    sinks: BTreeMap<Key, Vec<(Id, Sink)>>,
    computed: BTreeMap<Key, Vec<Id>>,
}

fn is_leaf(n: &Node) -> bool {
    matches!(n, Node::Const(_) | Node::Var(_))
}

fn is_computed(n: &Node) -> bool {
    !matches!(
        n,
        Node::Const(_) | Node::Var(_) | Node::Gather(..) | Node::Sum(..)
    )
}

impl Scheduler<'_> {
    fn group(&self, id: Id) -> Key {
        (self.level[&id], self.arena.ctx(id))
    }

    fn array(&mut self, id: Id, over: Option<SetId>, accumulate: bool) -> ArrayId {
        if let Some(&a) = self.arrays.get(&id) {
            return a;
        }
        let a = ArrayId::new(self.defs.len());
        self.defs.push(ArrayDef { over, accumulate });
        self.arrays.insert(id, a);
        a
    }

    /// Stores computed node `id` into its array (once).
    fn materialise(&mut self, id: Id) -> ArrayId {
        if let Some(&a) = self.arrays.get(&id) {
            return a;
        }
        let a = self.array(id, self.arena.ctx(id), false);
        let key = self.group(id);
        self.sinks
            .entry(key)
            .or_default()
            .push((id, Sink::Store(a)));
        a
    }

    /// Node `c` is read by group `key`: materialise it if computed elsewhere.
    fn use_in(&mut self, c: Id, key: Key) {
        if is_computed(self.arena.node(c)) && self.group(c) != key {
            self.materialise(c);
        }
    }

    /// The operand of node `c` read from group `key` (after `use_in`).
    fn operand(&self, c: Id, key: Key, slots: &HashMap<Id, Operand>) -> Operand {
        match self.arena.node(c) {
            Node::Const(v) => Operand::Const(v.0),
            Node::Var(v) => Operand::Input(*v),
            Node::Gather(m, inner) => match self.arena.node(*inner) {
                Node::Var(v) => Operand::Gather(*v, *m),
                _ => Operand::ArrayAt(self.arrays[inner], *m),
            },
            Node::Sum(..) => Operand::Array(self.arrays[&c]),
            _ if self.group(c) == key => slots[&c],
            _ => Operand::Array(self.arrays[&c]),
        }
    }
}

/// The sums that accumulate into another's array: `sum -> (lead, subtracted)`. A sum
/// joins the first sum of the same linear combination (`Node::Add`) into the same
/// codomain when both are read by nothing else and their coefficients there are equal
/// (added) or opposite (subtracted); the combination then reads the lead's array once
/// with the lead's coefficient. One array and one pass over the codomain fewer per
/// merged sum, and no subtraction after the loops.
fn shared_accumulators(arena: &Arena, nodes: &[Id], roots: &[Id]) -> HashMap<Id, (Id, bool)> {
    // Readers of each node: its parents among `nodes` (which holds the roots) and each
    // time it is a root.
    let mut uses: HashMap<Id, u32> = HashMap::new();
    for &id in nodes {
        for c in arena.children(id) {
            *uses.entry(c).or_default() += 1;
        }
    }
    for &r in roots {
        *uses.entry(r).or_default() += 1;
    }
    let mut merged = HashMap::new();
    for &id in nodes {
        let Node::Add(_, terms) = arena.node(id) else {
            continue;
        };
        // (codomain, lead sum, its coefficient)
        let mut leads: Vec<(Option<SetId>, Id, f64)> = Vec::new();
        for &(t, a) in terms.iter() {
            let Node::Sum(m, _) = arena.node(t) else {
                continue;
            };
            if uses.get(&t) != Some(&1) {
                continue;
            }
            let codomain = arena.maps().codomain(*m);
            let joins = leads
                .iter()
                .find(|&&(c, _, k)| c == codomain && (a.0 == k || a.0 == -k));
            match joins {
                Some(&(_, lead, k)) => {
                    merged.insert(t, (lead, a.0 != k));
                }
                None => leads.push((codomain, t, a.0)),
            }
        }
    }
    merged
}

/// Builds the program computing `roots`; for the jacobian, `kernels` gives, per
/// coupling, the `(row factor, column factor)` nodes of its terms.
pub(crate) fn program(
    arena: &Arena,
    roots: &[Root],
    kernels: &[(usize, Vec<(Id, Id)>)],
) -> Program {
    let root_ids: Vec<Id> = roots
        .iter()
        .map(|r| match *r {
            Root::Out(id, ..) | Root::Factor(id) => id,
        })
        .collect();
    let nodes = arena.reachable(&root_ids);
    let mut s = Scheduler {
        arena,
        level: HashMap::with_capacity(nodes.len()),
        arrays: HashMap::new(),
        defs: Vec::new(),
        sinks: BTreeMap::new(),
        computed: BTreeMap::new(),
    };
    // Levels, children first (ids increase from children to parents).
    for &id in &nodes {
        let lvl = match arena.node(id) {
            Node::Const(_) | Node::Var(_) => 0,
            Node::Gather(_, c) if is_leaf(arena.node(*c)) => 0,
            Node::Gather(_, c) | Node::Sum(_, c) => s.level[c] + 1,
            _ => arena
                .children(id)
                .iter()
                .map(|c| s.level[c])
                .max()
                .unwrap_or(0),
        };
        s.level.insert(id, lvl);
    }
    let merged = shared_accumulators(arena, &nodes, &root_ids);
    // Groups of the computed nodes, and the arrays their uses need.
    for &id in &nodes {
        let node = arena.node(id).clone();
        match node {
            Node::Gather(_, c) if is_computed(arena.node(c)) => {
                s.materialise(c);
            }
            Node::Sum(m, b) => {
                let k = arena.maps().domain(m);
                let codomain = arena.maps().codomain(m);
                let sink = match merged.get(&id) {
                    Some(&(lead, subtracted)) => {
                        let acc = s.array(lead, codomain, true);
                        s.arrays.insert(id, acc);
                        if subtracted {
                            Sink::ScatterSub(acc, m)
                        } else {
                            Sink::ScatterAdd(acc, m)
                        }
                    }
                    None => Sink::ScatterAdd(s.array(id, codomain, true), m),
                };
                let key = (s.level[&id] - 1, k);
                s.use_in(b, key);
                s.sinks.entry(key).or_default().push((b, sink));
            }
            ref n if is_computed(n) => {
                let key = s.group(id);
                s.computed.entry(key).or_default().push(id);
                for c in arena.children(id) {
                    s.use_in(c, key);
                }
            }
            _ => {}
        }
    }
    let mut factor_arrays: HashMap<Id, Factor> = HashMap::new();
    for r in roots {
        match *r {
            Root::Out(id, dest, set) => {
                let key = (s.level[&id], set);
                s.use_in(id, key);
                s.sinks.entry(key).or_default().push((id, Sink::Out(dest)));
            }
            Root::Factor(id) => {
                let f = match arena.node(id) {
                    Node::Const(v) => Factor::Const(v.0),
                    _ if s.arrays.contains_key(&id) && !is_computed(arena.node(id)) => {
                        Factor::Array(s.arrays[&id])
                    }
                    _ => {
                        let key = s.group(id);
                        if is_computed(arena.node(id)) {
                            Factor::Array(s.materialise(id))
                        } else {
                            let a = s.array(id, arena.ctx(id), false);
                            s.sinks.entry(key).or_default().push((id, Sink::Store(a)));
                            Factor::Array(a)
                        }
                    }
                };
                factor_arrays.insert(id, f);
            }
        }
    }
    // Emit the groups in order.
    let mut keys: Vec<Key> = s.computed.keys().chain(s.sinks.keys()).copied().collect();
    keys.sort_by_key(|&(l, c)| (l, c.map_or(0, |c| c.index() + 1)));
    keys.dedup();
    let mut groups = Vec::with_capacity(keys.len());
    for key in keys {
        let mut e = Emitter::new(arena);
        let computed = s.computed.get(&key).cloned().unwrap_or_default();
        let mut slots: HashMap<Id, Operand> = HashMap::new();
        for &id in &computed {
            for c in arena.children(id) {
                if !slots.contains_key(&c) {
                    let o = s.operand(c, key, &slots);
                    e.done.entry(c).or_insert(o);
                }
            }
            let o = match arena.node(id) {
                // A combination of sums that share an accumulator reads it once (the
                // lead's operand, with the lead's coefficient).
                Node::Add(c, terms) if terms.iter().any(|(t, _)| merged.contains_key(t)) => {
                    let kept: Vec<(Operand, f64)> = terms
                        .iter()
                        .filter(|(t, _)| !merged.contains_key(t))
                        .map(|(t, a)| (e.done[t], a.0))
                        .collect();
                    e.sum(c.0, &kept)
                }
                _ => e.node(id),
            };
            e.done.insert(id, o);
            slots.insert(id, o);
        }
        let mut sinks = Vec::new();
        for &(id, sink) in s.sinks.get(&key).map(Vec::as_slice).unwrap_or(&[]) {
            let o = s.operand(id, key, &slots);
            e.tape.push_output(o);
            sinks.push(sink);
        }
        groups.push(Group {
            over: key.1,
            tape: e.tape,
            sinks,
        });
    }
    let entries = kernels
        .iter()
        .map(|(coupling, terms)| EntryLoop {
            coupling: *coupling,
            terms: terms
                .iter()
                .map(|(r, c)| (factor_arrays[r], factor_arrays[c]))
                .collect(),
        })
        .collect();
    let sets = arena.leaf_sets().clone();
    Program::new(s.defs, groups, entries, move |v| {
        matches!(v, VarRef::Elem(_)) || sets.of(v).is_some()
    })
}

/// The programs and construction data of an analysed model (every model has them: a
/// version-1 model's are those of a family model without sets).
pub(crate) fn compile(
    model: &crate::model::Model,
    constraints: &[crate::analysis::ConstraintAnalysis],
    sym: &crate::analysis::SymbolicModel,
) -> super::FamilyModel {
    use super::{ConstraintInfo, Construction, Coupling, FamilyModel};
    use crate::{ConstraintId, StateId};
    let arena = &sym.arena;
    let sets = arena.leaf_sets();
    let rhs: Vec<Root> = sym
        .f
        .iter()
        .enumerate()
        .map(|(k, &f)| {
            let s = StateId::new(k);
            Root::Out(f, Dest::Rhs(s), sets.of(VarRef::State(s)))
        })
        .collect();
    let mut sliding = Vec::new();
    let mut rate = Vec::new();
    let mut factors = Vec::new();
    let mut kernels = Vec::new();
    let mut couplings = Vec::new();
    for (i, c) in sym.constraints.iter().enumerate() {
        let id = ConstraintId::new(i);
        let set = sets.constraint(id);
        for (j, &w) in c.w.iter().enumerate() {
            sliding.push(Root::Out(w, Dest::W(id, j as u32), set));
        }
        sliding.push(Root::Out(c.s, Dest::S(id), set));
        sliding.push(Root::Out(c.alpha_hat, Dest::AlphaHat(id), set));
        rate.push(Root::Out(c.rate, Dest::Rate(id), set));
        for k in &c.kernels {
            for &(r, col) in &k.terms {
                factors.push(Root::Factor(r));
                factors.push(Root::Factor(col));
            }
            kernels.push((couplings.len(), k.terms.clone()));
            couplings.push(Coupling {
                constraint: id,
                alg: k.alg,
                row_map: k.row_map,
                col_map: k.col_map,
            });
        }
    }
    let mut construction = Construction::from_model(model);
    construction.maps = arena.maps().defs().to_vec();
    construction.constraints = model
        .constraints
        .iter()
        .zip(constraints)
        .map(|(d, a)| ConstraintInfo {
            name: d.name.clone(),
            over: d.over,
            index: a.index,
            span: d.span,
        })
        .collect();
    construction.couplings = couplings;
    FamilyModel {
        rhs: program(arena, &rhs, &[]),
        sliding: program(arena, &sliding, &[]),
        jacobian: program(arena, &factors, &kernels),
        rate: program(arena, &rate, &[]),
        construction,
    }
}
