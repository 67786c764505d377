//! Evaluation of constant expressions: the parameter defaults and initial values of a
//! model that uses nothing of version 2, which use only numbers and parameters.

use crate::VarRef;
use crate::ast::BinOp;
use crate::model::RExpr;

/// Evaluates `e` given the parameter values; `None` if it uses anything else or a
/// parameter whose value is unknown (because its own default was in error).
pub(crate) fn eval(e: &RExpr, params: &[Option<f64>]) -> Option<f64> {
    Some(match e {
        RExpr::Num(v) => *v,
        RExpr::Var(VarRef::Param(i)) => (*params.get(i.index())?)?,
        // A version-1 value reads only numbers and parameters (a model over sets is
        // evaluated by its construction, `crate::family::ceval`).
        RExpr::Var(_)
        | RExpr::Let(_)
        | RExpr::Gather(..)
        | RExpr::Sum(..)
        | RExpr::Compare(..)
        | RExpr::Logic(..)
        | RExpr::Not(_)
        | RExpr::If(..)
        | RExpr::Int(..) => return None,
        RExpr::Neg(a) => -eval(a, params)?,
        RExpr::Binary(op, a, b) => {
            let (a, b) = (eval(a, params)?, eval(b, params)?);
            match op {
                BinOp::Add => a + b,
                BinOp::Sub => a - b,
                BinOp::Mul => a * b,
                BinOp::Div => a / b,
                BinOp::Pow => a.powf(b),
            }
        }
        RExpr::Call(f, args) => {
            let x = eval(args.first()?, params)?;
            let y = || args.get(1).and_then(|a| eval(a, params));
            if f.arity() == 2 {
                f.apply2(x, y()?)
            } else {
                f.apply1(x)
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Func, ParamId, StateId};

    fn num(v: f64) -> RExpr {
        RExpr::Num(v)
    }

    fn call(f: Func, args: Vec<RExpr>) -> RExpr {
        RExpr::Call(f, args)
    }

    #[test]
    fn functions_match_std() {
        let p = [];
        assert_eq!(eval(&call(Func::Sign, vec![num(-3.0)]), &p), Some(-1.0));
        assert_eq!(eval(&call(Func::Sign, vec![num(0.0)]), &p), Some(0.0));
        assert_eq!(eval(&call(Func::Sign, vec![num(2.0)]), &p), Some(1.0));
        assert_eq!(
            eval(&call(Func::Atan2, vec![num(1.0), num(-1.0)]), &p),
            Some(1f64.atan2(-1.0))
        );
        assert_eq!(
            eval(&call(Func::Pow, vec![num(2.0), num(10.0)]), &p),
            Some(1024.0)
        );
        assert_eq!(
            eval(&call(Func::Min, vec![num(2.0), num(-1.0)]), &p),
            Some(-1.0)
        );
        assert_eq!(
            eval(&call(Func::Max, vec![num(2.0), num(-1.0)]), &p),
            Some(2.0)
        );
        assert_eq!(eval(&call(Func::Ln, vec![num(1.0)]), &p), Some(0.0));
        assert!(eval(&call(Func::Sqrt, vec![num(-1.0)]), &p).is_some_and(f64::is_nan));
    }

    #[test]
    fn operators_and_params() {
        let p = [Some(3.0), None];
        let e = RExpr::Binary(
            BinOp::Pow,
            Box::new(RExpr::Var(VarRef::Param(ParamId::new(0)))),
            Box::new(num(2.0)),
        );
        assert_eq!(eval(&e, &p), Some(9.0));
        let neg = RExpr::Neg(Box::new(RExpr::Binary(
            BinOp::Div,
            Box::new(num(1.0)),
            Box::new(num(4.0)),
        )));
        assert_eq!(eval(&neg, &p), Some(-0.25));
        // An unknown parameter value or a non-constant makes the result unknown.
        assert_eq!(eval(&RExpr::Var(VarRef::Param(ParamId::new(1))), &p), None);
        assert_eq!(eval(&RExpr::Var(VarRef::State(StateId::new(0))), &p), None);
        assert_eq!(eval(&RExpr::Var(VarRef::Time), &p), None);
    }
}
