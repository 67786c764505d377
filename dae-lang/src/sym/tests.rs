//! Tests of the arena: hash-consing, simplifier identities, printing (with a test-only
//! reader of the printed syntax), derivatives against finite differences.

use proptest::prelude::*;

use super::*;

fn names() -> Names {
    Names {
        params: vec!["p".into()],
        states: vec!["x".into(), "y".into()],
        algs: vec!["z".into()],
    }
}

/// Leaves: x, y (states), z (alg), p (param), t, mu1.
fn leaves(a: &mut Arena) -> [Id; 6] {
    [
        a.state(0),
        a.state(1),
        a.alg(0),
        a.param(0),
        a.time(),
        a.mu(0),
    ]
}

fn at<'a>(
    params: &'a [f64],
    states: &'a [f64],
    algs: &'a [f64],
    t: f64,
    mu: &'a [f64],
) -> Point<'a> {
    Point {
        params,
        states,
        algs,
        t,
        mu,
    }
}

// ---------------------------------------------------------------- a test-only reader
// A recursive-descent reader of the printed syntax with the precedence of language.md,
// strict where the grammar might be: an exponent is an atom or a power (never a bare
// unary minus), and a unary minus only starts a sum or a product's first operand.

struct Reader<'s> {
    s: &'s [u8],
    i: usize,
}

impl Reader<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i] == b' ' {
            self.i += 1;
        }
    }
    fn eat(&mut self, c: u8) -> bool {
        self.ws();
        if self.s.get(self.i) == Some(&c) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn sum(&mut self, a: &mut Arena) -> Id {
        let mut acc = self.prod(a);
        loop {
            if self.eat(b'+') {
                let r = self.prod(a);
                acc = a.add(acc, r);
            } else if self.eat(b'-') {
                let r = self.prod(a);
                acc = a.sub(acc, r);
            } else {
                return acc;
            }
        }
    }
    fn prod(&mut self, a: &mut Arena) -> Id {
        let mut acc = self.unary(a);
        loop {
            if self.eat(b'*') {
                let r = self.power(a);
                acc = a.mul(acc, r);
            } else if self.eat(b'/') {
                let r = self.power(a);
                acc = a.div(acc, r);
            } else {
                return acc;
            }
        }
    }
    fn unary(&mut self, a: &mut Arena) -> Id {
        if self.eat(b'-') {
            let x = self.unary(a);
            a.neg(x)
        } else {
            self.power(a)
        }
    }
    fn power(&mut self, a: &mut Arena) -> Id {
        let base = self.atom(a);
        if self.eat(b'^') {
            let e = self.power(a);
            a.pow(base, e)
        } else {
            base
        }
    }
    fn atom(&mut self, a: &mut Arena) -> Id {
        self.ws();
        if self.eat(b'(') {
            let x = self.sum(a);
            assert!(self.eat(b')'), "expected ) at {}", self.i);
            return x;
        }
        let start = self.i;
        let c = self.s[self.i];
        if c.is_ascii_digit() {
            while self.i < self.s.len()
                && (self.s[self.i].is_ascii_alphanumeric()
                    || self.s[self.i] == b'.'
                    || ((self.s[self.i] == b'-' || self.s[self.i] == b'+')
                        && matches!(self.s[self.i - 1], b'e' | b'E')))
            {
                self.i += 1;
            }
            let text = std::str::from_utf8(&self.s[start..self.i]).unwrap();
            return a.num(text.parse().unwrap_or_else(|_| panic!("bad number {text}")));
        }
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_')
        {
            self.i += 1;
        }
        let name = std::str::from_utf8(&self.s[start..self.i]).unwrap();
        assert!(!name.is_empty(), "expected an atom at {start}");
        if self.eat(b'(') {
            let mut args = vec![self.sum(a)];
            while self.eat(b',') {
                args.push(self.sum(a));
            }
            assert!(self.eat(b')'));
            let f =
                crate::model::Func::from_name(name).unwrap_or_else(|| panic!("no function {name}"));
            assert_eq!(args.len(), f.arity());
            return a.call(f, &args);
        }
        match name {
            "x" => a.state(0),
            "y" => a.state(1),
            "z" => a.alg(0),
            "p" => a.param(0),
            "t" => a.time(),
            "mu1" => a.mu(0),
            _ => panic!("unknown name {name}"),
        }
    }
}

fn read(a: &mut Arena, text: &str) -> Id {
    let mut r = Reader {
        s: text.as_bytes(),
        i: 0,
    };
    let id = r.sum(a);
    r.ws();
    assert_eq!(r.i, text.len(), "trailing text in {text}");
    id
}

// ---------------------------------------------------------------- unit tests

#[test]
fn hash_consing_returns_the_same_id_for_the_same_expression() {
    let mut a = Arena::new();
    let [x, y, ..] = leaves(&mut a);
    let e1 = {
        let s = a.add(x, y);
        let si = a.f1(Fun1::Sin, s);
        a.mul(si, x)
    };
    let n = a.len();
    let e2 = {
        let s = a.add(y, x);
        let si = a.f1(Fun1::Sin, s);
        a.mul(x, si)
    };
    assert_eq!(e1, e2);
    assert_eq!(a.len(), n, "rebuilding must not add nodes");
    assert_eq!(a.state(0), x);
    let (two1, two2) = (a.num(2.0), a.num(2.0));
    assert_eq!(two1, two2);
    assert_eq!(a.num(-0.0), a.num(0.0));
    // Also without simplification: identical constructions share.
    let mut r = Arena::unsimplified();
    let (x, y) = (r.state(0), r.state(1));
    let s1 = r.add(x, y);
    let s2 = r.add(x, y);
    assert_eq!(s1, s2);
}

#[test]
fn simplifier_identities() {
    let mut a = Arena::new();
    let [x, y, ..] = leaves(&mut a);
    let (zero, one, two, three) = (a.num(0.0), a.num(1.0), a.num(2.0), a.num(3.0));
    assert_eq!(a.add(x, zero), x, "x + 0");
    assert_eq!(a.mul(x, one), x, "x * 1");
    assert_eq!(a.mul(x, zero), zero, "x * 0");
    assert_eq!(a.pow(x, one), x, "x ^ 1");
    assert_eq!(a.pow(x, zero), one, "x ^ 0");
    assert_eq!(a.sub(x, x), zero, "x - x");
    assert_eq!(a.div(x, x), one, "x / x");
    let nx = a.neg(x);
    assert_eq!(a.neg(nx), x, "--x");
    assert_eq!(a.add(two, three), a.num(5.0), "2 + 3");
    assert_eq!(a.pow(two, three), a.num(8.0), "2 ^ 3");
    let tx = a.mul(three, x);
    assert_eq!(a.mul(two, tx), a.scale(6.0, x), "2 * (3 * x)");
    assert_eq!(a.mul(x, x), a.powf(x, 2.0), "x * x");
    let (x2, x3) = (a.powf(x, 2.0), a.powf(x, 3.0));
    assert_eq!(a.mul(x2, x3), a.powf(x, 5.0), "x^2 * x^3");
    assert_eq!(a.div(x2, x3), a.powf(x, -1.0), "x^2 / x^3");
    let sx = a.sqrt(x);
    assert_eq!(a.mul(sx, sx), x, "sqrt(x) * sqrt(x)");
    let (xy, yx) = (a.add(x, y), a.add(y, x));
    assert_eq!(a.sub(xy, yx), zero, "(x + y) - (y + x)");
    let x_plus = a.add(tx, x2);
    assert_eq!(a.sub(x_plus, tx), x2, "(3x + x^2) - 3x");
    assert_eq!(a.add(tx, x), a.scale(4.0, x), "3x + x");
    let z = a.num(0.0);
    assert_eq!(a.f1(Fun1::Sin, z), zero, "sin 0 folds");
    let m1 = a.num(-1.0);
    let ln = a.f1(Fun1::Ln, m1);
    assert!(a.as_const(ln).is_none(), "ln(-1) is not folded into NaN");
    // (x^2)^0.5 is |x|, not x: must not be merged.
    let r = a.powf(x2, 0.5);
    assert_ne!(r, x);
    assert_eq!(a.eval(r, &at(&[], &[-3.0, 0.0], &[], 0.0, &[])), 3.0);
    // A scaled sum is distributed: -(x - y) = y - x.
    let d = a.sub(x, y);
    assert_eq!(a.neg(d), a.sub(y, x));
}

#[test]
fn unsimplified_arena_keeps_the_structure() {
    let mut a = Arena::unsimplified();
    let x = a.state(0);
    let zero = a.num(0.0);
    assert_ne!(a.add(x, zero), x);
    assert_ne!(a.sub(x, x), zero);
    let e = a.add(x, zero);
    assert_eq!(a.eval(e, &at(&[], &[2.5], &[], 0.0, &[])), 2.5);
}

#[test]
fn op_counts_shared_and_tree() {
    let mut a = Arena::new();
    let [x, y, ..] = leaves(&mut a);
    let s = a.add(x, y); // 1
    let si = a.f1(Fun1::Sin, s); // 1
    let co = a.f1(Fun1::Cos, s); // 1
    let e = a.mul(si, co); // 1
    assert_eq!(a.op_count(&[e]), 4);
    assert_eq!(a.tree_op_count(&[e]), 5, "x + y written twice");
    assert_eq!(a.op_count(&[si, co]), 3);
    assert_eq!(a.tree_op_count(&[si, co]), 4);
    let q = a.div(x, y);
    assert_eq!(a.op_count(&[q]), 1, "x / y is one division");
    let n = a.neg(x);
    assert_eq!(a.op_count(&[n]), 1, "-x is one negation");
    let d = a.sub(x, y);
    assert_eq!(a.op_count(&[d]), 1, "x - y is one subtraction");
}

#[test]
fn printing_uses_the_language_precedence() {
    let mut a = Arena::new();
    let [x, y, _z, p, t, _mu] = leaves(&mut a);
    let nm = names();
    let show = |a: &Arena, id| a.display(id, &nm);
    let x2 = a.powf(x, 2.0);
    let nx2 = a.neg(x2);
    assert_eq!(show(&a, nx2), "-x^2");
    let d = a.sub(x, y);
    assert_eq!(show(&a, d), "x - y");
    let q = a.div(x, y);
    let q2 = a.scale(2.0, q);
    assert_eq!(show(&a, q2), "2*x/y");
    let three = a.num(3.0);
    let x3 = a.div(x, three);
    assert_eq!(show(&a, x3), "x/3");
    let s = a.add(x, p);
    let s2 = a.powf(s, 2.0);
    assert_eq!(show(&a, s2), "(x + p)^2");
    let is = a.powf(s, -1.0);
    assert_eq!(show(&a, is), "1/(x + p)");
    let sq = a.sqrt(s);
    assert_eq!(show(&a, sq), "sqrt(x + p)");
    let yz = a.pow(y, t);
    let right = a.pow(x, yz);
    assert_eq!(show(&a, right), "x^y^t");
    let xy = a.pow(x, y);
    let left = a.pow(xy, t);
    assert_eq!(show(&a, left), "(x^y)^t");
    let mt = a.neg(t);
    let xmt = a.pow(x, mt);
    assert_eq!(show(&a, xmt), "x^(-t)");
    let a2 = a.f2(Fun2::Atan2, y, x);
    assert_eq!(show(&a, a2), "atan2(y, x)");
    let sub_sum = a.sub(p, s);
    assert_eq!(show(&a, sub_sum), "-x");
    let ps = a.mul(p, s);
    let e = a.sub(x, ps);
    assert_eq!(show(&a, e), "x - p*(x + p)");
    for (v, text) in [
        (0.1, "0.1"),
        (1e-7, "1e-7"),
        (2.5e300, "2.5e300"),
        (-4.0, "-4"),
        (1.5, "1.5"),
    ] {
        let c = a.num(v);
        assert_eq!(show(&a, c), text);
    }
    let inf = a.num(f64::INFINITY);
    assert_eq!(show(&a, inf), "(1/0)");
    // Negative operands in the unsimplified arena get parentheses.
    let mut r = Arena::unsimplified();
    let x = r.state(0);
    let m2 = r.num(-2.0);
    let e = r.mul(x, m2);
    assert_eq!(r.display(e, &nm), "x*(-2)");
    let nx = r.neg(x);
    let sq = r.powf(nx, 2.0);
    assert_eq!(r.display(sq, &nm), "(-x)^2");
    let nnx = r.neg(nx);
    assert_eq!(r.display(nnx, &nm), "-(-x)");
    let s = r.add(x, nx);
    let ms = r.sub(x, s);
    assert_eq!(r.display(ms, &nm), "x - (x + (-x))");
}

#[test]
fn printed_text_reads_back_to_the_same_node() {
    let mut a = Arena::new();
    let [x, y, z, p, t, mu] = leaves(&mut a);
    let s = a.lin(-2.0, &[(x, 3.0), (y, -1.0)]);
    let c = a.f1(Fun1::Cos, s);
    let e1 = a.product(-0.25, &[(c, 1.5), (z, -2.0), (p, 1.0)]);
    let e2 = a.f2(Fun2::Max, e1, t);
    let e3 = a.pow(s, mu);
    let e4 = a.lin(0.1, &[(e2, -1.0), (e3, 7.0)]);
    for e in [s, c, e1, e2, e3, e4] {
        let text = a.display(e, &names());
        assert_eq!(read(&mut a, &text), e, "{text}");
    }
}
