//! Names in expressions: what a bare name stands for (an element, a size, a variable, a
//! `let`), the components it reads at the element at hand, and a declaration's
//! environment.

use super::expr::{Binding, Env, Ty, Val, Via, Where, func_signature};
use super::{Checker, Kind, LET_STRIDE, LetState};
use crate::ast::Span;
use crate::check::names::Suggestions;
use crate::diag::Diagnostic;
use crate::model::RExpr;
use crate::{AlgId, Func, InputId, LetId, ParamId, SetId, StateId, VarRef};

impl Checker<'_> {
    /// A bare name.
    pub(super) fn name(&mut self, n: &str, span: Span, env: &Env) -> Option<Val> {
        if let Some(b) = env.binding(n) {
            let b = b.clone();
            let elem = RExpr::Var(VarRef::Elem(b.set));
            return match b.via {
                Via::Here => Some(Val::scalar(elem, Ty::Int)),
                Via::Map(m) => Some(Val::scalar(RExpr::Gather(m, Box::new(elem)), Ty::Int)),
                Via::Undetermined(sum) => self.undetermined(n, span, sum),
            };
        }
        let Some(entry) = self.names.get(n).copied() else {
            return self.unknown_name(n, span);
        };
        match entry.kind {
            Kind::Size => Some(Val::scalar(RExpr::Var(VarRef::Size(crate::SizeId::new(entry.first))), Ty::Int)),
            Kind::Set => self.err(
                Diagnostic::new(format!("`{n}` is a set, not a number"), span, "a set")
                    .hint("to use the number of elements, declare a size and write the set's size with it"),
            ),
            Kind::Map => {
                let dom = entry.over.map_or(String::new(), |s| self.sets[s.index()].elem.clone());
                self.err(
                    Diagnostic::new(format!("`{n}` is a map: it needs an element"), span, "a map")
                        .hint(format!("write `{n}[{dom}]` for the image of an element")),
                )
            }
            _ => {
                if let Some(set) = entry.over {
                    let s = &self.sets[set.index()];
                    let suggestion = match env.binders.iter().rev().find(|b| b.set == set) {
                        Some(b) => format!("write `{n}[{}]`", b.name),
                        None => format!("write `{n}[...]` with an element of `{}`", s.name),
                    };
                    return self.err(
                        Diagnostic::new(
                            format!("`{n}` is a family over `{}`: it needs an element", s.name),
                            span,
                            format!("one value per element of `{}`", s.name),
                        )
                        .hint(suggestion),
                    );
                }
                self.leaf(n, entry, span, env)
            }
        }
    }

    /// The components of a variable or `let` (read at the element at hand), after the
    /// rules of the place.
    pub(super) fn leaf(
        &mut self,
        n: &str,
        entry: super::Entry,
        span: Span,
        env: &Env,
    ) -> Option<Val> {
        let allowed = match (entry.kind, env.place) {
            (_, Where::Equation) => true,
            (Kind::Param, Where::Init) => true,
            (Kind::Param, Where::Param(i)) => {
                if entry.decl >= i {
                    let d = if self.param_decl.get(entry.first) == Some(&i) {
                        Diagnostic::new(
                            format!("parameter `{}` is defined in terms of itself", env.owner),
                            span,
                            "used in its own default",
                        )
                        .hint(if self.version1 {
                            "give the parameter a value made of numbers and earlier parameters"
                        } else {
                            "give the parameter a value made of numbers, sizes and earlier parameters"
                        })
                    } else {
                        Diagnostic::new(
                            format!(
                                "the default of parameter `{}` uses `{n}`, which is declared after it",
                                env.owner
                            ),
                            span,
                            "declared later",
                        )
                        .related(entry.span, format!("`{n}` is declared here"))
                        .hint(format!("declare `{n}` before `{}`", env.owner))
                    };
                    return self.err(d);
                }
                true
            }
            _ => false,
        };
        if !allowed {
            return self.not_here(&format!("`{n}`, {}", entry.kind.words()), span, env);
        }
        // A `let`'s type is its value's: resolve it first.
        let dim = if entry.kind == Kind::Let {
            self.resolve_let(entry.first)?
        } else {
            entry.dim
        };
        let comps: Vec<RExpr> = (0..dim as usize)
            .map(|c| {
                let i = entry.first + c;
                match entry.kind {
                    Kind::Param => RExpr::Var(VarRef::Param(ParamId::new(i))),
                    Kind::State => RExpr::Var(VarRef::State(StateId::new(i))),
                    Kind::Alg => RExpr::Var(VarRef::Alg(AlgId::new(i))),
                    Kind::Input => RExpr::Var(VarRef::Input(InputId::new(i), 0)),
                    _ => RExpr::Let(LetId::new(entry.first * LET_STRIDE + c)),
                }
            })
            .collect();
        let ty = if dim == 1 { Ty::Real } else { Ty::Vec(dim) };
        Some(Val { comps, ty })
    }

    /// Resolves `let` declaration `d` if not done yet; its dimension.
    pub(super) fn resolve_let(&mut self, d: usize) -> Option<u8> {
        match &self.let_state[d] {
            LetState::Done(Some(c)) => return Some(c.len() as u8),
            LetState::Done(None) => return None,
            // Resolving `d` needs `d`: a cycle through the `let`s. Reported here, since
            // the `let`s on it get no value and so no uses for the ordering to see.
            LetState::InProgress => {
                let from = self.let_stack.iter().position(|&l| l == d).unwrap_or(0);
                let cycle = self.let_stack[from..].to_vec();
                self.diags
                    .push(crate::check::lets::cycle_error(&cycle, &self.lets));
                return None;
            }
            LetState::Todo => {}
        }
        self.let_state[d] = LetState::InProgress;
        self.let_stack.push(d);
        let decl = self.lets[d];
        let set = self.let_sets[d];
        let env = self.decl_env(decl, set, Where::Equation);
        let v = self.expr(&decl.value, &env);
        let v = v.and_then(|v| {
            if v.ty == Ty::Bool {
                self.mismatch(
                    &format!("`let {}`", decl.name.name),
                    &v,
                    decl.value.span,
                    "a number or a vector",
                )
            } else {
                self.check_declared_type(decl, &v)
            }
        });
        self.let_stack.pop();
        let dim = v.as_ref().map(Val::dim);
        self.let_state[d] = LetState::Done(v.map(|v| v.comps));
        dim
    }

    /// A value against the declaration's type annotation (a number without one).
    pub(super) fn check_declared_type(&mut self, decl: &crate::ast::Decl, v: &Val) -> Option<Val> {
        let declared = match decl.ty.as_ref().map(|t| t.name.as_str()) {
            Some("vec2") => Some(2),
            Some("vec3") => Some(3),
            Some(_) => return None, // unknown type: reported at the declaration
            None => None,
        };
        // A `let` without a type takes the type of its value.
        let lets = self
            .names
            .get(decl.name.name.as_str())
            .is_some_and(|e| e.kind == Kind::Let);
        let want = declared.unwrap_or(if lets { v.dim() } else { 1 });
        if v.dim() != want || v.ty == Ty::Bool {
            let what = if want == 1 {
                "a number".to_string()
            } else {
                format!("a vec{want}")
            };
            return self.err(
                Diagnostic::new(
                    format!(
                        "`{}` is {what}, but its value is {}",
                        decl.name.name,
                        v.ty.words()
                    ),
                    decl.value.span,
                    "vector/scalar mismatch",
                )
                .hint(if want == 1 {
                    "declare a vector with its type, e.g. `state x[p in P]: vec3 = vec3(0, 0, 0);`"
                        .to_string()
                } else {
                    format!("give it a vec{want}, e.g. `vec{want}(...)`")
                }),
            );
        }
        Some(v.clone())
    }

    /// The environment of a declaration's value: its set's element is at hand, named by
    /// its binder.
    pub(super) fn decl_env(
        &self,
        decl: &crate::ast::Decl,
        set: Option<SetId>,
        place: Where,
    ) -> Env {
        let mut binders = Vec::new();
        if let (Some(set), Some(b)) = (set, decl.binder.as_ref()) {
            if let Some(e) = &b.elem {
                binders.push(Binding {
                    name: e.name.clone(),
                    set,
                    via: Via::Here,
                });
            }
        }
        Env {
            ctx: set,
            binders,
            place,
            owner: decl.name.name.clone(),
        }
    }

    fn undetermined(&mut self, n: &str, span: Span, sum: Span) -> Option<Val> {
        self.err(
            Diagnostic::new(
                format!("`{n}` is not determined inside this sum"),
                span,
                "which element?",
            )
            .related(sum, "the sum")
            .hint(format!(
                "inside `sum(k in K where m[k] == {n}) ...` the element `{n}` is `m[k]`; a full sum, \
                 or a sum whose condition does not name `{n}` directly, cannot use it"
            )),
        )
    }

    pub(super) fn unknown_name(&mut self, n: &str, span: Span) -> Option<Val> {
        if let Some(f) = Func::from_name(n) {
            return self.err(
                Diagnostic::new(
                    format!("function `{n}` used without arguments"),
                    span,
                    "a function",
                )
                .hint(format!("call it: `{}`", func_signature(f))),
            );
        }
        if super::decl::is_reserved(n, self.version1) {
            let words = if self.version1 {
                "reserved words are `model param state alg let der constraint t` and the function names"
            } else {
                "reserved words are `model param state alg let der constraint t if then else and or not` and the function names"
            };
            return self.err(
                Diagnostic::new(
                    format!("reserved word `{n}` cannot be used in an expression"),
                    span,
                    "reserved word",
                )
                .hint(words),
            );
        }
        let d = Diagnostic::new(
            format!("unknown name `{n}`"),
            span,
            format!("not declared in model `{}`", self.m.name.name),
        );
        let names = self.ordered.len();
        if self
            .suggestions
            .as_ref()
            .is_none_or(|(built, _)| *built != names)
        {
            let all = Suggestions::new(self.ordered.iter().copied());
            self.suggestions = Some((names, all));
        }
        let suggestion = self
            .suggestions
            .as_mut()
            .and_then(|(_, all)| all.suggest(n));
        let d = match suggestion {
            Some(s) => d.hint(format!("did you mean `{s}`?")),
            None if self.version1 => d.hint("declare it with `param`, `state`, `alg` or `let`"),
            None => d.hint(
                "declare it with `param`, `state`, `alg`, `let`, `input`, `size`, `set` or `map`",
            ),
        };
        self.err(d)
    }
}
