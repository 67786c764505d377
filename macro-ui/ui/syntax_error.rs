dae_runtime::dae! {
    model Decay {
        state x = 1.0;
        der(x) = -2 * ;
    }
}

fn main() {}
