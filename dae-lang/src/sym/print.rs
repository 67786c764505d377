//! Printing in the `.dae` language's own expression syntax.
//!
//! Precedence, loosest first: `+ -` (left), `* /` (left), unary `-`, `^` (right
//! associative, tighter than unary minus). Each printed piece carries the [`Kind`] of its
//! outermost operator and a parent wraps it in parentheses only when that kind binds more
//! loosely than the position needs. A leading minus (a negative number or coefficient)
//! has its own kind, so it is parenthesised anywhere but at the start of a sum or at the
//! top: `a*(-2)`, `x^(-1)`, `(-x)^2`. Numbers print with Rust's shortest round-trip form
//! (`{:?}`, integers without `.0`), which the grammar reads back to the same `f64`;
//! non-finite constants (only reachable from non-finite input) print as `(1/0)`,
//! `(-1/0)` and `(0/0)`, which evaluate to the same values.
//!
//! A family model's templates print their leaves at the element bound to their set
//! (`x[b[l]].y`), gathers as the gathered node with its set bound to the image (`b[l]`),
//! sums as `sum(k in L where a[k] == p) z[k]*u[k].x`, and maps and sets by their integer
//! formulas. The text of a node depends on the element name bound to its context (the
//! same `let` prints `u[l].x` and `u[k].x`), so the memo is keyed by the node and that
//! name. A version-1 model is the case without sets: every node is scalar, binds
//! nothing, and is printed once.

use std::collections::HashMap;

use super::names::{Names, split_component};
use super::{Arena, Id, Node, Num};
use crate::ast::{BinOp, LogicOp};
use crate::model::{IntOp, MapKind, RExpr};
use crate::{MapId, SetId, VarRef};

/// Binding strength of the outermost operator of a printed piece.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    Sum,
    Neg,
    Prod,
    Pow,
    Atom,
}

type Piece = (String, Kind);

fn wrap((s, k): Piece, min: Kind) -> String {
    if k < min { format!("({s})") } else { s }
}

/// `base^exp`, each side bracketed as its position needs.
fn power(base: Piece, exp: Piece) -> Piece {
    let (b, e) = (wrap(base, Kind::Atom), wrap(exp, Kind::Pow));
    (format!("{b}^{e}"), Kind::Pow)
}

/// A non-negative finite number as the grammar writes it.
fn unsigned(v: f64) -> String {
    if v.fract() == 0.0 && v < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v:?}")
    }
}

fn number(v: f64) -> Piece {
    if v.is_nan() {
        ("(0/0)".into(), Kind::Atom)
    } else if v.is_infinite() {
        (if v > 0.0 { "(1/0)" } else { "(-1/0)" }.into(), Kind::Atom)
    } else if v < 0.0 {
        (format!("-{}", unsigned(-v)), Kind::Neg)
    } else {
        (unsigned(v), Kind::Atom)
    }
}

/// `1/v` as an integer when that is exact (to print `x/3` instead of `0.333...*x`).
fn exact_reciprocal(v: f64) -> Option<f64> {
    let r = 1.0 / v;
    (r > 1.0 && r < 1e15 && r.fract() == 0.0 && 1.0 / r == v).then_some(r)
}

/// Names written in place of nodes (a model's `let`s), added one at a time.
#[derive(Default)]
struct Abbreviations {
    /// Node -> the name written for it (the latest added for that node).
    names: HashMap<Id, String>,
    /// Abbreviations that are a power of one base, `name = base^e0` (a let `l =
    /// sqrt(x^2 + y^2)`), by base: a factor `base^e` with an integer `e/e0` prints as
    /// `name^(e/e0)` (for a positive integer `e/e0`), so `(x^2 + y^2)^1.5` reads `l^3`.
    /// Needed because a power of a let merges into the surrounding product and the let's
    /// own node disappears. Per base the latest root added, and the latest one before it
    /// with another node (what is used when the latest is the expression being defined).
    roots: HashMap<Id, (Root, Option<Root>)>,
}

/// `name = base^e0`, the abbreviation's own node being `node`.
#[derive(Clone)]
struct Root {
    name: String,
    e0: f64,
    node: Id,
}

#[cfg(test)]
thread_local! {
    /// Entries made by the printer on this thread (abbreviations added, pieces memoised):
    /// the printer's work, for the tests that it is linear.
    pub(crate) static ENTRIES: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Counts one entry made by the printer (tests only).
fn count_entry() {
    #[cfg(test)]
    ENTRIES.with(|e| e.set(e.get() + 1));
}

impl Abbreviations {
    /// Writes `name` for node `id` from now on.
    fn add(&mut self, arena: &Arena, id: Id, name: &str) {
        count_entry();
        self.names.insert(id, name.to_string());
        if let Node::Mul(c, fs) = arena.node(id) {
            if c.0 == 1.0 && fs.len() == 1 {
                let root = Root {
                    name: name.to_string(),
                    e0: fs[0].1.0,
                    node: id,
                };
                match self.roots.get_mut(&fs[0].0) {
                    Some((latest, before)) => {
                        if latest.node != id {
                            *before = Some(latest.clone());
                        }
                        *latest = root;
                    }
                    None => {
                        self.roots.insert(fs[0].0, (root, None));
                    }
                }
            }
        }
    }
}

struct Printer<'a> {
    arena: &'a Arena,
    names: &'a Names,
    /// By node and the element name bound to its context (interned; 0 for a scalar).
    memo: HashMap<(Id, u32), Piece>,
    /// Nodes written by name (a model's `let`s): `d.x` prints `d[l].x` in the context of
    /// `l`.
    abbrev: Abbreviations,
    /// The node being defined: never written as its own abbreviation.
    defining: Option<Id>,
    /// The element name bound to each set (empty for a version-1 model).
    env: Vec<String>,
    /// Interned bindings, for the memo.
    bindings: HashMap<String, u32>,
    /// The element names that enclosing sums hide (their sets now bound to the sums'
    /// elements): a sum's element never takes one, so no name is shadowed.
    hidden: Vec<String>,
}

impl<'a> Printer<'a> {
    fn new(arena: &'a Arena, names: &'a Names) -> Printer<'a> {
        let env = names
            .family
            .as_ref()
            .map_or(Vec::new(), |f| f.elems.clone());
        Printer {
            arena,
            names,
            memo: HashMap::new(),
            abbrev: Abbreviations::default(),
            defining: None,
            env,
            bindings: HashMap::new(),
            hidden: Vec::new(),
        }
    }
}

impl Printer<'_> {
    /// The memo key of a node: its id and the element name bound to its context.
    fn key(&mut self, id: Id) -> (Id, u32) {
        let Some(s) = self.arena.ctx(id) else {
            return (id, 0);
        };
        let b = self.env.get(s.index()).cloned().unwrap_or_default();
        let next = self.bindings.len() as u32 + 1;
        (id, *self.bindings.entry(b).or_insert(next))
    }

    fn pr(&mut self, id: Id) -> Piece {
        if Some(id) != self.defining {
            if let Some(name) = self.abbrev.names.get(&id) {
                return (self.at_element(name, self.arena.ctx(id)), Kind::Atom);
            }
        }
        let key = self.key(id);
        if let Some(p) = self.memo.get(&key) {
            return p.clone();
        }
        let p = match self.arena.node(id) {
            Node::Const(v) => number(v.0),
            Node::Var(v) => (self.leaf(*v), Kind::Atom),
            Node::Gather(m, e) => self.gather(*m, *e),
            Node::Sum(m, b) => self.sum_over(*m, *b),
            Node::Add(c, ts) => self.sum(c.0, ts),
            Node::Mul(c, fs) => self.product(c.0, fs),
            Node::Pow(a, b) => power(self.pr(*a), self.pr(*b)),
            Node::F1(f, a) => (format!("{}({})", f.name(), self.pr(*a).0), Kind::Atom),
            Node::F2(f, a, b) => (
                format!("{}({}, {})", f.name(), self.pr(*a).0, self.pr(*b).0),
                Kind::Atom,
            ),
        };
        count_entry();
        self.memo.insert(key, p.clone());
        p
    }

    fn sum(&mut self, c: f64, ts: &[(Id, Num)]) -> Piece {
        let mut out = String::new();
        // Terms are stored by id; start with a positive term when there is one, so that
        // `b - a` does not print as `-a + b` (both read back to the same node).
        let mut order: Vec<&(Id, Num)> = ts.iter().collect();
        if let Some(p) = order.iter().position(|(_, a)| a.0 > 0.0) {
            let first = order.remove(p);
            order.insert(0, first);
        }
        for (k, (t, a)) in order.into_iter().enumerate() {
            let a = a.0;
            let body = if a.abs() == 1.0 {
                wrap(self.pr(*t), Kind::Prod)
            } else {
                let scaled = match self.arena.node(*t) {
                    Node::Mul(c1, fs) if c1.0 == 1.0 => self.product(a.abs(), fs),
                    _ => self.product(a.abs(), &[(*t, Num(1.0))]),
                };
                wrap(scaled, Kind::Prod)
            };
            let neg = a < 0.0 || (a.is_nan() && a.is_sign_negative());
            // A leading unary minus before a product that starts with a sum would be read as
            // negating (and distributing into) that sum: `-((x + y)/z)`, see `product`.
            let body = if k == 0 && neg && a.abs() == 1.0 && self.starts_with_sum(*t) {
                format!("({body})")
            } else {
                body
            };
            match (k, neg) {
                (0, false) => out.push_str(&body),
                (0, true) => out.push('-'),
                (_, false) => out.push_str(" + "),
                (_, true) => out.push_str(" - "),
            }
            if k > 0 || neg {
                out.push_str(&body);
            }
        }
        if ts.is_empty() {
            return number(c);
        }
        if c != 0.0 {
            let (sign, mag) = if c < 0.0 { (" - ", -c) } else { (" + ", c) };
            out.push_str(sign);
            out.push_str(&wrap(number(mag), Kind::Prod));
        }
        (out, Kind::Sum)
    }

    /// Whether a product prints with a sum (possibly a let's name) as its first factor,
    /// followed by more factors.
    fn starts_with_sum(&self, t: Id) -> bool {
        match self.arena.node(t) {
            Node::Mul(_, fs) if fs.len() > 1 => self
                .numerator(fs)
                .first()
                .is_some_and(|&(b, e)| self.is_sum_factor(b, e)),
            _ => false,
        }
    }

    /// A factor `(a + b)^1`: written first after a number or a minus, it would be read as
    /// scaled by it (see `product`).
    fn is_sum_factor(&self, b: Id, e: f64) -> bool {
        e == 1.0 && matches!(self.arena.node(b), Node::Add(..))
    }

    /// The numerator factors in printing order: by id, except that a factor which is not a
    /// sum goes first when there is one (`2*mu*(a - b)` rather than `2*((a - b)*mu)`,
    /// which needs the brackets to read back to the same node).
    /// (A NaN exponent, from a folded `0/0`, counts as the numerator's.)
    fn numerator(&self, fs: &[(Id, Num)]) -> Vec<(Id, f64)> {
        let mut num: Vec<(Id, f64)> = fs
            .iter()
            .filter(|(_, e)| e.0 >= 0.0 || e.0.is_nan())
            .map(|(b, e)| (*b, e.0))
            .collect();
        if let Some(p) = num.iter().position(|&(b, e)| !self.is_sum_factor(b, e)) {
            let first = num.remove(p);
            num.insert(0, first);
        }
        num
    }

    fn factor(&mut self, b: Id, e: f64) -> Piece {
        let root = self.abbrev.roots.get(&b).and_then(|(latest, before)| {
            if Some(latest.node) != self.defining {
                Some(latest)
            } else {
                before.as_ref()
            }
        });
        if let Some(Root { name, e0, node }) = root.cloned() {
            let k = e / e0;
            if k.fract() == 0.0 && k > 0.0 && k < 1e6 {
                let name = self.at_element(&name, self.arena.ctx(node));
                return if k == 1.0 {
                    (name, Kind::Atom)
                } else {
                    power((name, Kind::Atom), number(k))
                };
            }
        }
        if e == 1.0 {
            (wrap(self.pr(b), Kind::Pow), Kind::Pow)
        } else if e == 0.5 {
            (format!("sqrt({})", self.pr(b).0), Kind::Atom)
        } else {
            power(self.pr(b), number(e))
        }
    }

    fn product(&mut self, c: f64, fs: &[(Id, Num)]) -> Piece {
        let mag = c.abs();
        let has_num = fs.iter().any(|(_, e)| e.0 >= 0.0 || e.0.is_nan());
        let mut coef = None;
        let mut den: Vec<String> = Vec::new();
        // `x/3` for a coefficient 1/3, unless a sum is in the denominator: `x/(3*(a + b))`
        // would read back as `x/(3a + 3b)`, another normal form.
        let sum_below = fs
            .iter()
            .any(|(b, e)| e.0 == -1.0 && matches!(self.arena.node(*b), Node::Add(..)));
        if mag != 1.0 {
            match exact_reciprocal(mag) {
                Some(r) if has_num && !sum_below => den.push(unsigned(r)),
                _ => coef = Some(number(mag).0),
            }
        }
        let order = self.numerator(fs);
        let leading_sum = order
            .first()
            .is_some_and(|&(b, e)| self.is_sum_factor(b, e));
        let mut num: Vec<Piece> = Vec::with_capacity(order.len());
        for (b, e) in order {
            num.push(self.factor(b, e));
        }
        for (b, e) in fs.iter().filter(|(_, e)| e.0 < 0.0) {
            den.push(wrap(self.factor(*b, -e.0), Kind::Pow));
        }
        let more_than_the_sum = num.len() > 1 || !den.is_empty();
        let (mut s, mut kind) = match num.len() {
            0 => (coef.take().unwrap_or_else(|| "1".to_string()), Kind::Atom),
            1 => num.pop().expect("one numerator factor"),
            _ => {
                let parts: Vec<String> = num.into_iter().map(|p| wrap(p, Kind::Pow)).collect();
                (parts.join("*"), Kind::Prod)
            }
        };
        if !den.is_empty() {
            s = wrap((s, kind), Kind::Prod);
            if den.len() == 1 {
                s = format!("{s}/{}", den[0]);
            } else {
                s = format!("{s}/({})", den.join("*"));
            }
            kind = Kind::Prod;
        }
        // A number or a minus directly before a sum would be read as scaling that sum (and
        // distributed into it), a different normal form from scaling the whole product:
        // `-((x + y)/z)`, `2*((x + y)*z)`, not `-(x + y)/z`.
        let scaled = coef.is_some() || c < 0.0;
        if scaled && leading_sum && more_than_the_sum {
            s = format!("({s})");
            kind = Kind::Atom;
        }
        if let Some(cf) = coef {
            s = format!("{cf}*{}", wrap((s, kind), Kind::Prod));
            kind = Kind::Prod;
        }
        if c < 0.0 {
            (format!("-{}", wrap((s, kind), Kind::Prod)), Kind::Neg)
        } else {
            (s, kind)
        }
    }

    /// The element name bound to a set (`0`, the unit's one element, for `None`).
    fn bound(&self, s: Option<SetId>) -> String {
        match s {
            None => "0".into(),
            Some(s) => self
                .env
                .get(s.index())
                .cloned()
                .unwrap_or_else(|| self.names.elem(s)),
        }
    }

    /// A name (a variable's or a `let`'s) at the element bound to `set`: `x.y` ->
    /// `x[b[l]].y`; a scalar's name as it is.
    fn at_element(&self, name: &str, set: Option<SetId>) -> String {
        match set {
            None => name.to_string(),
            Some(s) => {
                let (base, comp) = split_component(name);
                format!("{base}[{}]{comp}", self.bound(Some(s)))
            }
        }
    }

    /// A leaf: an input's derivative `u''.x` at an element is `u''[l].x`, as any other
    /// name with a component.
    fn leaf(&self, v: VarRef) -> String {
        let set = self.arena.leaf_sets().of(v);
        match (v, set) {
            (VarRef::Elem(s), _) => self.bound(Some(s)),
            (VarRef::Mu(_), Some(_)) => format!("{}[{}]", self.names.var(v), self.bound(set)),
            _ => self.at_element(&self.names.var(v), set),
        }
    }

    /// Element `elem` mapped by `m`, as text: `a[l]`, `b[a[l]]`, `l + 1`.
    fn path(&self, m: MapId, elem: &str) -> String {
        let d = self.arena.maps().get(m);
        match &d.kind {
            MapKind::Identity => elem.to_string(),
            MapKind::ToUnit => "0".into(),
            MapKind::Chain(ms) => ms.iter().fold(elem.to_string(), |e, k| self.path(*k, &e)),
            MapKind::Formula(f) if d.name.is_empty() => self.formula(f, elem),
            _ => format!("{}[{elem}]", d.name),
        }
    }

    /// An integer formula (a map's or a set size's) with the element written `elem`.
    fn formula(&self, e: &RExpr, elem: &str) -> String {
        formula(e, elem, &|m, x| self.path(m, x), self.names).0
    }

    /// `Gather(m, e)`: `e` printed with its set bound to the image under `m`.
    fn gather(&mut self, m: MapId, e: Id) -> Piece {
        let maps = self.arena.maps();
        let (dom, cod) = (maps.domain(m), maps.codomain(m));
        let at = self.path(m, &self.bound(dom));
        let Some(c) = cod else { return self.pr(e) };
        let saved = std::mem::replace(&mut self.env[c.index()], at);
        let p = self.pr(e);
        self.env[c.index()] = saved;
        p
    }

    /// `Sum(m, b)`: `sum(k in K where m[k] == q) b`, or `sum(k in K) b`.
    fn sum_over(&mut self, m: MapId, b: Id) -> Piece {
        let maps = self.arena.maps();
        let (k_set, q_set) = (maps.domain(m), maps.codomain(m));
        let Some(ks) = k_set else {
            return self.pr(b);
        };
        let k = self.fresh(ks);
        // The element the condition compares with is bound outside the sum: read it
        // before the sum binds its own set (the same set for a sum over `P` at `p`).
        let q = self.bound(q_set);
        let saved = std::mem::replace(&mut self.env[ks.index()], k.clone());
        self.hidden.push(saved);
        let body = wrap(self.pr(b), Kind::Prod);
        let saved = self.hidden.pop().expect("pushed above");
        let set = self.names.set(k_set);
        let text = match q_set {
            None => format!("sum({k} in {set}) {body}"),
            Some(_) => format!("sum({k} in {set} where {} == {q}) {body}", self.path(m, &k),),
        };
        self.env[ks.index()] = saved;
        // As loose as a sum, so that an operation around it puts it in parentheses.
        (text, Kind::Sum)
    }

    /// A name for the element of a sum over `k`: the set's element name, primed until it
    /// differs from every name bound or hidden by an enclosing sum.
    fn fresh(&self, k: SetId) -> String {
        let mut name = self.names.elem(k);
        while self.env.contains(&name) || self.hidden.contains(&name) {
            name.push('\'');
        }
        name
    }
}

impl Arena {
    /// The expression in the `.dae` language's syntax (shared sub-expressions are written
    /// out in full each time they occur).
    pub fn display(&self, id: Id, names: &Names) -> String {
        self.display_all(&[id], names).swap_remove(0)
    }

    /// Several expressions printed with one memo (faster than repeated [`Arena::display`]).
    pub fn display_all(&self, ids: &[Id], names: &Names) -> Vec<String> {
        self.display_in(ids, names, &[], &[])
    }

    /// Like [`Arena::display_all`], but every occurrence of a node in `abbrev` is written
    /// as the given name (e.g. a model's `let`s, so that the text reads in the model's
    /// scope), and element names are bound to sets: `(set, name)` (e.g. the column
    /// element `k` of a `J_Omega` kernel); the other sets print with their element names.
    pub fn display_in(
        &self,
        ids: &[Id],
        names: &Names,
        abbrev: &[(Id, String)],
        bind: &[(SetId, String)],
    ) -> Vec<String> {
        let mut p = Printer::new(self, names);
        for (id, name) in abbrev {
            p.abbrev.add(self, *id, name);
        }
        for (s, n) in bind {
            if let Some(slot) = p.env.get_mut(s.index()) {
                *slot = n.clone();
            }
        }
        ids.iter().map(|&id| p.pr(id).0).collect()
    }

    /// Definitions `(node, name, abbreviate)` in order, each written in terms of the
    /// earlier ones whose `abbreviate` is true (never in terms of itself). Linear in the
    /// size of the text: the abbreviations grow by one per definition, each definition
    /// is printed with a memo of its own.
    pub fn display_definitions(&self, defs: &[(Id, &str, bool)], names: &Names) -> Vec<String> {
        let mut p = Printer::new(self, names);
        let mut out = Vec::with_capacity(defs.len());
        for &(id, name, abbreviate) in defs {
            p.defining = Some(id);
            p.memo = HashMap::new();
            out.push(p.pr(id).0);
            if abbreviate {
                p.abbrev.add(self, id, name);
            }
        }
        out
    }

    /// A map applied to an element, as text (`a[l]`, `b[a[l]]`, `l + 1`).
    pub fn path_text(&self, m: MapId, elem: &str, names: &Names) -> String {
        Printer::new(self, names).path(m, elem)
    }

    /// An integer formula of the model (a set's size, a map's formula) as text, with its
    /// element written `elem`.
    pub fn formula_text(&self, e: &RExpr, elem: &str, names: &Names) -> String {
        Printer::new(self, names).formula(e, elem)
    }
}

/// An integer (construction-time) formula as text and its binding level (0 `if`,
/// comparisons and logic, 1 sums, 2 products, 3 unary minus, 4 atoms); `path(m, e)`
/// writes a map applied.
fn formula(
    e: &RExpr,
    elem: &str,
    path: &dyn Fn(MapId, &str) -> String,
    names: &Names,
) -> (String, u8) {
    let go = |e: &RExpr, elem: &str| formula(e, elem, path, names);
    let paren = |(s, l): (String, u8), min: u8| if l < min { format!("({s})") } else { s };
    match e {
        RExpr::Num(v) => {
            let t = number(*v).0;
            let level = if t.starts_with('-') { 3 } else { 4 };
            (t, level)
        }
        RExpr::Var(VarRef::Elem(_)) => (elem.to_string(), 4),
        RExpr::Var(v) => (names.var(*v), 4),
        RExpr::Let(l) => (format!("let{}", l.index()), 4),
        RExpr::Gather(m, inner) => match inner.as_ref() {
            RExpr::Var(VarRef::Elem(_)) => (path(*m, elem), 4),
            other => go(other, &path(*m, elem)),
        },
        RExpr::Sum(_, b) => (format!("sum(...) {}", paren(go(b, elem), 2)), 1),
        RExpr::Neg(a) => (format!("-{}", paren(go(a, elem), 3)), 3),
        RExpr::Binary(op, a, b) => {
            let (sym, level) = match op {
                BinOp::Add => (" + ", 1),
                BinOp::Sub => (" - ", 1),
                BinOp::Mul => ("*", 2),
                BinOp::Div => ("/", 2),
                BinOp::Pow => ("^", 4),
            };
            let right_min = if matches!(op, BinOp::Sub | BinOp::Div | BinOp::Pow) {
                level + 1
            } else {
                level
            };
            let (l, r) = (paren(go(a, elem), level), paren(go(b, elem), right_min));
            (format!("{l}{sym}{r}"), level)
        }
        RExpr::Call(f, args) => {
            let a: Vec<String> = args.iter().map(|a| go(a, elem).0).collect();
            (format!("{}({})", f.name(), a.join(", ")), 4)
        }
        RExpr::Int(op, a, b) => {
            let f = if *op == IntOp::Div { "div" } else { "mod" };
            (format!("{f}({}, {})", go(a, elem).0, go(b, elem).0), 4)
        }
        RExpr::Compare(op, a, b) => {
            let (a, b) = (paren(go(a, elem), 1), paren(go(b, elem), 1));
            (format!("{a} {} {b}", op.symbol()), 0)
        }
        RExpr::Logic(op, a, b) => {
            let w = if *op == LogicOp::And { "and" } else { "or" };
            let (a, b) = (paren(go(a, elem), 1), paren(go(b, elem), 1));
            (format!("{a} {w} {b}"), 0)
        }
        RExpr::Not(a) => (format!("not {}", paren(go(a, elem), 1)), 0),
        RExpr::If(c, a, b) => (
            format!(
                "if {} then {} else {}",
                go(c, elem).0,
                go(a, elem).0,
                go(b, elem).0
            ),
            0,
        ),
    }
}
