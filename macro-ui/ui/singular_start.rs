// dOmega/dz = 2 z vanishes at the initial guess z = 0.
dae_runtime::dae! {
    model Singular {
        state x = 0.0;
        alg z = 0.0;
        der(x) = z^2;
        constraint c: x = t;
    }
}

fn main() {}
