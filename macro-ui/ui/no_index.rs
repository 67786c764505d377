// `z` never reaches the constraint: x' does not depend on it.
dae_runtime::dae! {
    model NoIndex {
        state x = 0.0;
        alg z = 0.0;
        der(x) = 1 + 0 * z;
        constraint c: x = t;
    }
}

fn main() {}
