//! The symbolic core: a hash-consed expression arena.
//!
//! The shape is egg's: a flat `Vec` of nodes where every child id is smaller than its
//! parent's, and a `HashMap` from node to id so that building the same expression twice
//! returns the same id. A DAG built this way shares every common sub-expression, which is
//! what keeps the repeated time derivatives of the index analysis small.
//!
//! # Sums and products are n-ary, with numeric coefficients and exponents
//!
//! We store `c + a1*t1 + a2*t2 + ...` as one [`Node::Add`] and `c * b1^e1 * b2^e2 * ...`
//! as one [`Node::Mul`] (numeric `a_k`, `e_k`), with the terms sorted by id. Subtraction,
//! unary minus, division and numeric powers (including `sqrt`, as `^0.5`) are coefficients
//! and exponents of these nodes, not node kinds. Why: with binary nodes, `x - x`, `2*x + 3*x`,
//! `x*x` or `x^a * x^-b` only cancel when the two operands happen to sit next to each other;
//! in this normal form collecting like terms and powers is a merge of two sorted lists, so it
//! always happens, and `a - b` and `-b + a` are the same node (better hash-consing). The
//! price is that a sum nested in a scaled sum is flattened (a numeric factor is distributed
//! over a sum), which can duplicate a long sum; it is linear, never a swell.
//!
//! # Simplification contract
//!
//! The simplifying constructors (in `build.rs`) return an expression that equals the
//! requested one (up to rounding) wherever every sub-expression of the requested one
//! evaluates to a finite number. Elsewhere they may differ: `x*0 = 0`, `x/x = 1` and
//! `x^0.5 * x^0.5 = x` turn a NaN into a number, and `1/(x*0)` is `+inf` where the
//! unsimplified `1/(-0)` is `-inf`. Signed zeros are not kept (`-0.0` is stored as `0.0`); the only finite
//! function that tells them apart is `atan2` on its branch cut (`y = -0`, `x < 0`).
//!
//! Constants are the exception: an expression without leaves is folded as IEEE 754
//! evaluates it (`0/0`, `0 * (1/0)`, `(1/0) - (1/0)` and `(1/0)/(1/0)` are NaN), and a rule
//! that would drop, cancel or regroup a constant sub-expression that is not finite is not
//! applied (the arena keeps the value of every constant node). Two representation
//! choices remain visible at infinities only: signed zeros (above), and `x^0.5`, which
//! is evaluated as `sqrt(x)` (NaN at `x = -inf`, where IEEE's `pow` gives `inf`). The
//! checker makes the contract hold where the compiler looks: every operation of a model's
//! equations must have a finite value at the initial point (`check/domain.rs`).
//! [`Arena::unsimplified`] builds an arena with all of this switched off
//! (hash-consing stays), for measuring what the simplifier buys.
//!
//! # Families (language version 2)
//!
//! Every node has a *context* ([`Arena::ctx`]): the set whose element it is evaluated at,
//! or `None` for a scalar. A leaf of a family is in the context of its set and means
//! "the variable at the element at hand"; the children of an arithmetic node are in its
//! context or scalar (a scalar is the same for every element). [`Node::Gather`] reads a
//! node of another context through a map (its context is the map's domain), and
//! [`Node::Sum`] adds a node over the elements a map sends to the element at hand (its
//! context is the map's codomain). The maps live in the arena's [`MapTable`], so that
//! composing gathers makes canonical maps. An arena of a version-1 model has no maps and
//! every node is scalar.

mod build;
mod diff;
mod kernels;
mod names;
// The compiler evaluates tapes, never the arena: this evaluator serves the tests.
#[cfg(any(test, feature = "internals"))]
mod eval;
#[cfg(test)]
mod parse_back;
mod print;
#[cfg(test)]
pub(crate) mod reader;
#[cfg(test)]
mod tests;

use std::collections::HashMap;
use std::hash::{Hash, Hasher};

use crate::maps::MapTable;
use crate::{AlgId, ConstraintId, Func, MapId, SetId, VarRef};

pub use diff::DiffContext;
#[cfg(any(test, feature = "internals"))]
pub use eval::Point;
pub use kernels::jacobian_terms;
#[cfg(any(test, feature = "internals"))]
pub use kernels::{Term, TwoHop};
#[cfg(any(test, feature = "internals"))]
pub use names::FamilyNames;
pub use names::Names;
pub(crate) use names::primes;

/// The id of a node in an [`Arena`]; children always have smaller ids than parents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Id(u32);

impl Id {
    /// The position of the node in the arena (`0..arena.len()`).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A finite or non-finite `f64` compared and hashed by its bits (`-0.0` is stored as
/// `0.0`, every NaN as `f64::NAN`).
#[derive(Clone, Copy, Debug)]
pub struct Num(pub f64);

impl Num {
    /// `-0.0` as `0.0`, and every NaN as the one `f64::NAN` (NaNs computed at run time
    /// may carry other bits), so that equal values are one node.
    fn norm(v: f64) -> Num {
        Num(if v == 0.0 {
            0.0
        } else if v.is_nan() {
            f64::NAN
        } else {
            v
        })
    }
}

impl PartialEq for Num {
    fn eq(&self, o: &Num) -> bool {
        self.0.to_bits() == o.0.to_bits()
    }
}
impl Eq for Num {}
impl Hash for Num {
    fn hash<H: Hasher>(&self, h: &mut H) {
        self.0.to_bits().hash(h)
    }
}

/// A node of the arena.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// A number.
    Const(Num),
    /// A variable: parameter, state, algebraic unknown, time or realization parameter.
    Var(VarRef),
    /// `c + sum a_k * t_k`, terms sorted by id.
    Add(Num, Box<[(Id, Num)]>),
    /// `c * prod b_k ^ e_k`, factors sorted by id.
    Mul(Num, Box<[(Id, Num)]>),
    /// `a ^ b` with a non-numeric exponent.
    Pow(Id, Id),
    /// A one-argument function other than `sqrt` (a power, see the module docs).
    F1(Func, Id),
    /// `atan2`, `min` or `max` (`pow` is [`Node::Pow`] or a numeric exponent).
    F2(Func, Id, Id),
    /// The node (in the context of the map's codomain) at the image of the element at
    /// hand (of the map's domain).
    Gather(MapId, Id),
    /// The sum of the node (in the context of the map's domain) over the elements the map
    /// sends to the element at hand (of the map's codomain; the unit for a full sum).
    Sum(MapId, Id),
}

/// The sets of the leaves of a family model (`None`: a scalar). Empty lists (a version-1
/// model) make every leaf scalar.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LeafSets {
    /// By parameter component.
    pub params: Vec<Option<SetId>>,
    /// By state component.
    pub states: Vec<Option<SetId>>,
    /// By algebraic component.
    pub algs: Vec<Option<SetId>>,
    /// By input component.
    pub inputs: Vec<Option<SetId>>,
    /// By constraint (the set of the realization parameter `mu`).
    pub constraints: Vec<Option<SetId>>,
}

impl LeafSets {
    /// The set of a leaf.
    pub fn of(&self, v: VarRef) -> Option<SetId> {
        let get = |l: &[Option<SetId>], i: usize| l.get(i).copied().flatten();
        match v {
            VarRef::Param(i) => get(&self.params, i.index()),
            VarRef::State(i) => get(&self.states, i.index()),
            VarRef::Alg(i) | VarRef::AlgRate(i) => get(&self.algs, i.index()),
            VarRef::Input(i, _) => get(&self.inputs, i.index()),
            VarRef::Mu(c) => get(&self.constraints, c.index()),
            VarRef::Elem(s) => Some(s),
            VarRef::Time | VarRef::Size(_) => None,
        }
    }

    /// The set of a constraint.
    pub fn constraint(&self, c: ConstraintId) -> Option<SetId> {
        self.constraints.get(c.index()).copied().flatten()
    }
}

/// Which kinds of leaves a node depends on (bit set), kept per node for O(1) pruning.
pub(crate) mod dep {
    use crate::VarRef;

    pub const PARAM: u8 = 1;
    pub const STATE: u8 = 2;
    pub const ALG: u8 = 4;
    pub const TIME: u8 = 8;
    pub const MU: u8 = 16;
    /// An input of a family model (it changes with time: its derivative is the next
    /// input derivative).
    pub const INPUT: u8 = 32;
    /// The rate of an algebraic unknown (only in `Omega'`).
    pub const ALG_RATE: u8 = 64;

    /// The bit of a leaf (elements and sizes are constants, like parameters).
    pub fn of(v: VarRef) -> u8 {
        match v {
            VarRef::Param(_) | VarRef::Elem(_) | VarRef::Size(_) => PARAM,
            VarRef::State(_) => STATE,
            VarRef::Alg(_) => ALG,
            VarRef::Time => TIME,
            VarRef::Mu(_) => MU,
            VarRef::Input(..) => INPUT,
            VarRef::AlgRate(_) => ALG_RATE,
        }
    }
}

/// The hash-consed expression arena. See the module documentation.
#[derive(Clone, Debug)]
pub struct Arena {
    nodes: Vec<Node>,
    deps: Vec<u8>,
    ctx: Vec<Option<SetId>>,
    /// The value of each node without leaves (a constant expression), as IEEE 754
    /// evaluates it; unused for the others. What the simplifier asks before it drops a
    /// constant sub-expression (see `build.rs`).
    values: Vec<f64>,
    memo: HashMap<Node, Id>,
    simplify: bool,
    leaf_sets: LeafSets,
    maps: MapTable,
}

impl Default for Arena {
    fn default() -> Self {
        Arena::new()
    }
}

impl Arena {
    /// An empty arena whose constructors simplify.
    pub fn new() -> Arena {
        Arena {
            nodes: Vec::new(),
            deps: Vec::new(),
            ctx: Vec::new(),
            values: Vec::new(),
            memo: HashMap::new(),
            simplify: true,
            leaf_sets: LeafSets::default(),
            maps: MapTable::default(),
        }
    }

    /// An arena for a family model: the sets of its leaves and its maps.
    pub fn with_families(simplify: bool, leaf_sets: LeafSets, maps: MapTable) -> Arena {
        Arena {
            simplify,
            leaf_sets,
            maps,
            ..Arena::new()
        }
    }

    /// The context of a node: the set whose element it is evaluated at (`None`: scalar).
    pub fn ctx(&self, id: Id) -> Option<SetId> {
        self.ctx[id.index()]
    }

    /// The maps of the arena.
    pub fn maps(&self) -> &MapTable {
        &self.maps
    }

    /// The maps of the arena, to make new ones.
    pub fn maps_mut(&mut self) -> &mut MapTable {
        &mut self.maps
    }

    /// The sets of the leaves.
    pub fn leaf_sets(&self) -> &LeafSets {
        &self.leaf_sets
    }

    /// An empty arena whose constructors do not simplify (only hash-consing), for measuring.
    pub fn unsimplified() -> Arena {
        Arena {
            simplify: false,
            ..Arena::new()
        }
    }

    /// Whether the constructors simplify.
    pub fn simplifies(&self) -> bool {
        self.simplify
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the arena has no nodes.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node behind an id.
    pub fn node(&self, id: Id) -> &Node {
        &self.nodes[id.index()]
    }

    /// The numeric value if the node is a constant.
    pub fn as_const(&self, id: Id) -> Option<f64> {
        match self.node(id) {
            Node::Const(v) => Some(v.0),
            _ => None,
        }
    }

    pub(crate) fn deps(&self, id: Id) -> u8 {
        self.deps[id.index()]
    }

    /// Whether the expression contains any algebraic unknown.
    pub fn has_alg(&self, id: Id) -> bool {
        self.deps(id) & dep::ALG != 0
    }

    /// Whether the expression contains any state, input or `t` (so its time derivative
    /// may be non-zero).
    pub fn has_state_or_time(&self, id: Id) -> bool {
        self.deps(id) & (dep::STATE | dep::TIME | dep::INPUT) != 0
    }

    /// Insert a node as is (hash-consed), returning its id.
    fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.memo.get(&node) {
            return id;
        }
        let d = match &node {
            Node::Const(_) => 0,
            Node::Var(v) => dep::of(*v),
            Node::Add(_, ts) | Node::Mul(_, ts) => ts.iter().fold(0, |d, (t, _)| d | self.deps(*t)),
            Node::Pow(a, b) | Node::F2(_, a, b) => self.deps(*a) | self.deps(*b),
            Node::F1(_, a) | Node::Gather(_, a) => self.deps(*a),
            // A sum of a constant depends on the instance (how many elements meet the
            // element at hand), like a size: never a constant expression to fold.
            Node::Sum(_, a) => match self.deps(*a) {
                0 => dep::PARAM,
                d => d,
            },
        };
        let ctx = match &node {
            Node::Const(_) => None,
            Node::Var(v) => self.leaf_sets.of(*v),
            Node::Gather(m, _) => self.maps.domain(*m),
            Node::Sum(m, _) => self.maps.codomain(*m),
            _ => {
                let mut c = None;
                self.for_each_child_of(&node, |k| c = c.or(self.ctx[k.index()]));
                c
            }
        };
        let value = if d == 0 {
            self.constant_value(&node)
        } else {
            f64::NAN
        };
        let id = Id(u32::try_from(self.nodes.len()).expect("arena holds fewer than 2^32 nodes"));
        self.nodes.push(node.clone());
        self.deps.push(d);
        self.ctx.push(ctx);
        self.values.push(value);
        self.memo.insert(node, id);
        id
    }

    /// The value of a node whose children are all constants (given their values).
    fn constant_value(&self, node: &Node) -> f64 {
        let v = |id: &Id| self.values[id.index()];
        match node {
            Node::Const(c) => c.0,
            Node::Var(_) => f64::NAN,
            Node::Add(c, ts) => ts.iter().fold(c.0, |s, (t, a)| s + a.0 * v(t)),
            Node::Mul(c, fs) => fs
                .iter()
                .fold(c.0, |p, (b, e)| p * build::pow_num(v(b), e.0)),
            Node::Pow(a, b) => v(a).powf(v(b)),
            Node::F1(f, a) => f.apply1(v(a)),
            Node::F2(f, a, b) => f.apply2(v(a), v(b)),
            // A gather of a constant is the constant (`Arena::gather` never makes one); a
            // sum is never constant (see `intern`).
            Node::Gather(_, a) => v(a),
            Node::Sum(..) => f64::NAN,
        }
    }

    /// Whether the node is a constant expression whose value is not finite (`1/0`,
    /// `ln(-1)`): a sub-expression the simplifier must not drop.
    pub(crate) fn is_non_finite_constant(&self, id: Id) -> bool {
        self.deps(id) == 0 && !self.values[id.index()].is_finite()
    }

    /// The value of a constant expression (a node without leaves), `None` for others.
    pub(crate) fn constant(&self, id: Id) -> Option<f64> {
        (self.deps(id) == 0).then(|| self.values[id.index()])
    }

    /// The children of a node, in order.
    pub fn children(&self, id: Id) -> Vec<Id> {
        let mut out = Vec::new();
        self.for_each_child(id, |c| out.push(c));
        out
    }

    fn for_each_child(&self, id: Id, f: impl FnMut(Id)) {
        self.for_each_child_of(self.node(id), f)
    }

    fn for_each_child_of(&self, node: &Node, mut f: impl FnMut(Id)) {
        match node {
            Node::Add(_, ts) | Node::Mul(_, ts) => ts.iter().for_each(|(t, _)| f(*t)),
            Node::Pow(a, b) | Node::F2(_, a, b) => {
                f(*a);
                f(*b)
            }
            Node::F1(_, a) | Node::Gather(_, a) | Node::Sum(_, a) => f(*a),
            Node::Const(_) | Node::Var(_) => {}
        }
    }

    /// Every node reachable from `roots` (each once), in increasing id order.
    pub fn reachable(&self, roots: &[Id]) -> Vec<Id> {
        let mut seen = vec![false; self.len()];
        let mut stack: Vec<Id> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if std::mem::replace(&mut seen[id.index()], true) {
                continue;
            }
            self.for_each_child(id, |c| {
                if !seen[c.index()] {
                    stack.push(c)
                }
            });
        }
        seen.iter()
            .enumerate()
            .filter(|(_, s)| **s)
            .map(|(i, _)| Id(i as u32))
            .collect()
    }

    /// The algebraic unknowns an expression contains, sorted.
    pub fn algs_in(&self, id: Id) -> Vec<AlgId> {
        // Sorted by index, not by node id: leaves are interned in order of first use.
        let mut out: Vec<AlgId> = self
            .leaves_in(id, dep::ALG)
            .into_iter()
            .filter_map(|l| match self.node(l) {
                Node::Var(VarRef::Alg(k)) => Some(*k),
                _ => None,
            })
            .collect();
        out.sort_unstable();
        out
    }

    /// The leaves (of the kinds in `mask`) reachable from `id`, sorted by id.
    pub(crate) fn leaves_in(&self, id: Id, mask: u8) -> Vec<Id> {
        let mut seen = std::collections::HashSet::new();
        let mut out = Vec::new();
        let mut stack = vec![id];
        while let Some(n) = stack.pop() {
            if self.deps(n) & mask == 0 || !seen.insert(n) {
                continue;
            }
            match self.node(n) {
                Node::Var(_) => out.push(n),
                _ => self.for_each_child(n, |c| stack.push(c)),
            }
        }
        out.sort();
        out
    }

    /// Arithmetic operations to evaluate one node given its children (a cost model:
    /// every `+ - * /`, power, and function call is one operation; a coefficient of
    /// `-1` is a subtraction or negation, not a multiplication).
    fn node_ops(&self, id: Id) -> u64 {
        match self.node(id) {
            Node::Add(c, ts) => {
                let parts = ts.len() as u64 + u64::from(c.0 != 0.0);
                let scaled = ts.iter().filter(|(_, a)| a.0.abs() != 1.0).count() as u64;
                let lone_neg =
                    u64::from(c.0 == 0.0 && ts.first().is_some_and(|(_, a)| a.0 == -1.0));
                parts.saturating_sub(1) + scaled + lone_neg
            }
            Node::Mul(c, fs) => {
                let unit = c.0.abs() == 1.0;
                let parts = fs.len() as u64 + u64::from(!unit);
                let powers = fs.iter().filter(|(_, e)| e.0.abs() != 1.0).count() as u64;
                let no_numerator = fs.iter().all(|(_, e)| e.0 < 0.0);
                let recip = u64::from(unit && no_numerator && !fs.is_empty());
                let neg = u64::from(c.0 == -1.0);
                parts.saturating_sub(1) + powers + recip + neg
            }
            Node::Pow(..) | Node::F1(..) | Node::F2(..) | Node::Sum(..) => 1,
            _ => 0,
        }
    }

    /// Operation count of a set of roots with every shared sub-expression counted once
    /// (what straight-line code after common sub-expression elimination costs).
    pub fn op_count(&self, roots: &[Id]) -> u64 {
        self.reachable(roots)
            .into_iter()
            .map(|id| self.node_ops(id))
            .sum()
    }

    /// Operation count of the roots written out as trees (nothing shared, saturating).
    pub fn tree_op_count(&self, roots: &[Id]) -> u64 {
        let reach = self.reachable(roots);
        let mut cost: HashMap<Id, u64> = HashMap::with_capacity(reach.len());
        // Increasing id order visits children before parents.
        for id in reach {
            let mut c = self.node_ops(id);
            self.for_each_child(id, |ch| c = c.saturating_add(cost[&ch]));
            cost.insert(id, c);
        }
        roots.iter().fold(0u64, |s, r| s.saturating_add(cost[r]))
    }
}
