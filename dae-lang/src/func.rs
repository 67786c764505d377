//! The built-in functions of the language: one table of names, arities and values,
//! shared by the checker, the symbolic arena, the tapes and the code generator.

/// Built-in functions of the language.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Func {
    /// `sin`
    Sin,
    /// `cos`
    Cos,
    /// `tan`
    Tan,
    /// `asin`
    Asin,
    /// `acos`
    Acos,
    /// `atan`
    Atan,
    /// `sinh`
    Sinh,
    /// `cosh`
    Cosh,
    /// `tanh`
    Tanh,
    /// `exp`
    Exp,
    /// `ln` (natural logarithm)
    Ln,
    /// `sqrt`
    Sqrt,
    /// `abs`
    Abs,
    /// `sign` (-1, 0 or 1)
    Sign,
    /// `atan2(y, x)`
    Atan2,
    /// `pow(a, b)` = `a^b`
    Pow,
    /// `min(a, b)`
    Min,
    /// `max(a, b)`
    Max,
}

impl Func {
    /// Every function, in the order of the language reference.
    pub const ALL: [Func; 18] = [
        Func::Sin,
        Func::Cos,
        Func::Tan,
        Func::Asin,
        Func::Acos,
        Func::Atan,
        Func::Sinh,
        Func::Cosh,
        Func::Tanh,
        Func::Exp,
        Func::Ln,
        Func::Sqrt,
        Func::Abs,
        Func::Sign,
        Func::Atan2,
        Func::Pow,
        Func::Min,
        Func::Max,
    ];

    /// The name as written in the language.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Atan => "atan",
            Func::Sinh => "sinh",
            Func::Cosh => "cosh",
            Func::Tanh => "tanh",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Sqrt => "sqrt",
            Func::Abs => "abs",
            Func::Sign => "sign",
            Func::Atan2 => "atan2",
            Func::Pow => "pow",
            Func::Min => "min",
            Func::Max => "max",
        }
    }

    /// Look a function up by its name.
    pub fn from_name(name: &str) -> Option<Func> {
        Func::ALL.into_iter().find(|f| f.name() == name)
    }

    /// Number of arguments.
    pub fn arity(self) -> usize {
        match self {
            Func::Atan2 | Func::Pow | Func::Min | Func::Max => 2,
            _ => 1,
        }
    }

    /// The value of a one-argument function: the one definition of the language's
    /// semantics, shared by the checker, the symbolic evaluator and the interpreter (the
    /// code generator emits the same operations). `sign` is -1, 0 or 1 (`f64::signum`
    /// gives 1 at 0) and NaN for NaN. A two-argument function gives NaN.
    pub fn apply1(self, x: f64) -> f64 {
        match self {
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
            Func::Sign => {
                if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    x * 0.0
                }
            }
            Func::Atan2 | Func::Pow | Func::Min | Func::Max => f64::NAN,
        }
    }

    /// The value of a two-argument function (see [`Func::apply1`]). `min` and `max`
    /// propagate a NaN operand (`f64::min` would drop it and hide the error). A
    /// one-argument function gives NaN.
    pub fn apply2(self, a: f64, b: f64) -> f64 {
        match self {
            Func::Atan2 => a.atan2(b),
            Func::Pow => a.powf(b),
            Func::Min | Func::Max if a.is_nan() || b.is_nan() => f64::NAN,
            Func::Min => a.min(b),
            Func::Max => a.max(b),
            _ => f64::NAN,
        }
    }
}
