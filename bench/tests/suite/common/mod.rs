//! Test models with closed-form answers, compiled by `dae!` like every model the
//! baselines run on.

dae_runtime::dae! {
    // Index 2: x' = z - x, 0 = x - sin t; exact x = sin t, z = sin t + cos t.
    // Omega = w' = z - x - cos t is affine in z.
    model Tracking {
        state x = 0.0;
        alg z = 0.0;
        der(x) = z - x;
        constraint track: x = sin(t);
    }

    // Index 1 and nonlinear in z: x' = -z, 0 = z^3 + z - x. At x = 10 the algebraic
    // equation has the single real root z = 2.
    model Cubic {
        state x = 10.0;
        alg z = 0.0;
        der(x) = -z;
        constraint cubic: z^3 + z = x;
    }
}
