//! A test-only reader of the printed syntax, to check that printed text reads back.
//!
//! A recursive-descent reader with the precedence of docs/language.md, strict where the grammar
//! might be: an exponent is an atom or a power (never a bare unary minus), and a unary
//! minus only starts a sum or a product's first operand. Panics on anything else.

use std::collections::HashMap;

use super::{Arena, Id};

struct Reader<'s, 'n> {
    s: &'s [u8],
    i: usize,
    names: &'n HashMap<String, Id>,
}

impl Reader<'_, '_> {
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
            let f = crate::Func::from_name(name).unwrap_or_else(|| panic!("no function {name}"));
            assert_eq!(args.len(), f.arity());
            return a.call(f, &args);
        }
        *self
            .names
            .get(name)
            .unwrap_or_else(|| panic!("unknown name {name}"))
    }
}

/// Read `text` into `a`; `names` maps every name that may occur to its node.
pub(crate) fn read(a: &mut Arena, names: &HashMap<String, Id>, text: &str) -> Id {
    let mut r = Reader {
        s: text.as_bytes(),
        i: 0,
        names,
    };
    let id = r.sum(a);
    r.ws();
    assert_eq!(r.i, text.len(), "trailing text in {text}");
    id
}
