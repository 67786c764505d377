dae_runtime::dae! {
    model Decay {
        state x = 1.0;
        der(x) = -k * x;
    }
}

fn main() {}
