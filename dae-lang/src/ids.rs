//! Typed indices of a model's declarations, and the one reference to a variable.
//!
//! Every kind of declaration has its own index type (cranelift-entity style: a `u32`
//! newtype per kind), so that a state index cannot be used where a parameter is meant.
//! [`VarRef`] is the leaf every stage reads: the checked model's expressions, the
//! symbolic arena's leaves and the tapes' inputs are the same type, so a new kind of
//! variable is added in one place.

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
    /// parameter `mu`.
    ConstraintId
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
    /// Time `t`.
    Time,
    /// The realization parameter `mu` of a constraint (printed `mu1`, `mu2`, ... from
    /// the first constraint). Never written in a model: the analysis introduces it.
    Mu(ConstraintId),
}
