//! Evaluation of constant expressions: parameter defaults and initial values, which use
//! only numbers and parameters.

use crate::ast::BinOp;
use crate::model::{Func, RExpr, Var};

/// Evaluates `e` given the parameter values; `None` if it uses anything else or a
/// parameter whose value is unknown (because its own default was in error).
pub(super) fn eval(e: &RExpr, params: &[Option<f64>]) -> Option<f64> {
    Some(match e {
        RExpr::Num(v) => *v,
        RExpr::Var(Var::Param(i)) => (*params.get(*i)?)?,
        RExpr::Var(_) => return None,
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
            match f {
                Func::Sin => x.sin(),
                Func::Cos => x.cos(),
                Func::Tan => x.tan(),
                Func::Asin => x.asin(),
                Func::Acos => x.acos(),
                Func::Atan => x.atan(),
                Func::Sinh => x.sinh(),
                Func::Cosh => x.cosh(),
                Func::Tanh => x.tanh(),
                Func::Exp => x.exp(),
                Func::Ln => x.ln(),
                Func::Sqrt => x.sqrt(),
                Func::Abs => x.abs(),
                // `sign(0) = 0`, unlike `f64::signum`.
                Func::Sign => {
                    if x > 0.0 {
                        1.0
                    } else if x < 0.0 {
                        -1.0
                    } else {
                        x * 0.0
                    }
                }
                Func::Atan2 => x.atan2(y()?),
                Func::Pow => x.powf(y()?),
                Func::Min => x.min(y()?),
                Func::Max => x.max(y()?),
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
            Box::new(RExpr::Var(Var::Param(0))),
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
        assert_eq!(eval(&RExpr::Var(Var::Param(1)), &p), None);
        assert_eq!(eval(&RExpr::Var(Var::State(0)), &p), None);
        assert_eq!(eval(&RExpr::Var(Var::Time), &p), None);
    }
}
