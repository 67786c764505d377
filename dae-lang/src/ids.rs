//! Typed indices of a model's declarations, and the one reference to a variable.
//!
//! Every kind of declaration has its own index type (cranelift-entity style: a `u32`
//! newtype per kind), so that a state index cannot be used where a parameter is meant.
//! [`VarRef`] is the leaf every stage reads: the checked model's expressions, the
//! symbolic arena's leaves and the tapes' inputs are the same type, so a new kind of
//! variable is added in one place.
//!
//! In a family model (language version 2) a parameter, state, algebraic unknown, input or
//! constraint may stand for a family: one value per element of a set. Its reference is
//! then read "at the element at hand" of the expression it occurs in; reading it at
//! another element goes through a map (`RExpr::Gather`, the arena's `Gather` node, the
//! tapes' `Operand::Gather`). Vectors are expanded by the checker: each component of a
//! vector declaration is a declaration of its own (`x.x`, `x.y`, `x.z`).

macro_rules! entity {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(u32);

        impl $name {
            /// The id of declaration number `i` (in declaration order, from 0).
            ///
            /// # Panics
            /// If `i` does not fit in 32 bits (no model comes near).
            pub fn new(i: usize) -> Self {
                Self(u32::try_from(i).expect("fewer than 2^32 declarations of a kind"))
            }

            /// The position in declaration order (`0..count`).
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }
    };
}

entity!(
    /// A parameter of the model (position in `Model::params`).
    ParamId
);
entity!(
    /// A differential state (position in `Model::states`).
    StateId
);
entity!(
    /// An algebraic unknown (position in `Model::algs`).
    AlgId
);
entity!(
    /// A `let` definition (position in `Model::lets`).
    LetId
);
entity!(
    /// A constraint (position in `Model::constraints`); also names its realization
    /// parameter `mu`. In a family model, a constraint family (one constraint per element
    /// of its set).
    ConstraintId
);
entity!(
    /// A size declaration `size N = 10;` (position in `Model::sizes`): an integer set at
    /// construction.
    SizeId
);
entity!(
    /// An index set `set P = N + 1;` (position in `Model::sets`): the elements
    /// `0 .. |P|`, its size fixed at construction.
    SetId
);
entity!(
    /// A map between sets (position in `Model::maps`): a named `map`, or one the checker
    /// or the analysis made (a formula written inside an index, a composition, the map of
    /// a set to the scalar context, an identity).
    MapId
);
entity!(
    /// An input component family (position in `Model::inputs`): a value the caller sets
    /// during a run, with its first time derivatives.
    InputId
);

entity!(
    /// A scratch array of a compiled family program (one value per element of its set,
    /// or one value): a materialised intermediate, the accumulator of a sum, or a factor
    /// of a `J_Omega` kernel.
    ArrayId
);

/// A variable an expression reads: what the checked model's names resolve to (besides
/// `let`s, which are definitions, not variables), the leaves of the symbolic arena and
/// the inputs of a tape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum VarRef {
    /// A model parameter.
    Param(ParamId),
    /// A differential state.
    State(StateId),
    /// An algebraic unknown.
    Alg(AlgId),
    /// The rate `z'` of an algebraic unknown along a motion: the direction in which
    /// `Omega' = beta + J_Omega z'` is taken. Never written in a model: the analysis
    /// introduces it (in `Omega'` only).
    AlgRate(AlgId),
    /// Time `t`.
    Time,
    /// The realization parameter `mu` of a constraint (printed `mu1`, `mu2`, ... from
    /// the first constraint). Never written in a model: the analysis introduces it. For a
    /// constraint family, the `mu` of the element at hand.
    Mu(ConstraintId),
    /// Time derivative number `order` (0 = the value) of an input, at the element at hand
    /// for an input family. Set by the caller during a run.
    Input(InputId, u8),
    /// The element at hand of a set, as a number (`p` in `p * L0`).
    Elem(SetId),
    /// The value of a `size` declaration (a number, fixed at construction).
    Size(SizeId),
}
