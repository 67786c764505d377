//! The scene of the thesis's chapter 5 (docs/method.md section 8) on code generated from
//! `models/double_pendulum_3d.dae`: the design from the published pilot bounds, the
//! settings of the monitored and fixed-rate runs, and an independent tension oracle.
//!
//! Used by `examples/double_pendulum.rs`, `examples/bench_double_pendulum.rs` and the
//! tests in `tests/chapter5.rs`.

use dae_runtime::settings::{Dbsmc, StepEnd, Update};
use dae_runtime::{
    Model, Settings, design::ConstraintSpec, design::Design, design::DesignError,
    design::GainChoice, design::LayerBound, design::MuSearch, design::design,
};

dae_runtime::dae_file!("models/double_pendulum_3d.dae");

/// Layer half-width of both links (docs/method.md section 8).
pub const EPS: f64 = 0.2;
/// RK4 step of the published runs.
pub const STEP: f64 = 1e-4;
/// Duration of the scene.
pub const T_END: f64 = 10.0;
/// The thesis's pilot bounds `|beta_1|`, `|beta_2|`.
pub const THESIS_BETA: [f64; 2] = [1.3e3, 2.3e3];
/// The thesis's pilot bounds `M_1`, `M_2`.
pub const THESIS_M: [f64; 2] = [9e4, 11e4];
/// The published `mu` of the relaxed design, used by the thesis's simulation.
pub const THESIS_MU: [f64; 2] = [0.076, 0.066];
/// The fixed period of the run without monitoring.
pub const FIXED_PERIOD: f64 = 0.005;

/// The design from the thesis's pilot bounds: `Sufficient` gains go with (T 3.14)
/// (`LayerBound::General`), `Relaxed` with (T 4.6) (`LayerBound::TightIndex3`), as in
/// docs/method.md section 8.
pub fn thesis_design(gain: GainChoice) -> Result<Design, DesignError> {
    let layer = match gain {
        GainChoice::Relaxed => LayerBound::TightIndex3,
        _ => LayerBound::General,
    };
    let specs: Vec<ConstraintSpec> = (0..2)
        .map(|i| ConstraintSpec {
            r: 3,
            eps: EPS,
            m: THESIS_M[i],
            beta_abs: THESIS_BETA[i],
            layer,
        })
        .collect();
    design(&specs, gain, &MuSearch::default())
}

/// Relaxed gains `k_i = mu_i^2 |beta_i|` at the published `mu`.
pub fn thesis_gains() -> Vec<f64> {
    (0..2)
        .map(|i| THESIS_MU[i] * THESIS_MU[i] * THESIS_BETA[i])
        .collect()
}

/// The guaranteed period (T 4.6) of the published `mu` with the relaxed gains, per link.
pub fn thesis_t_min() -> Result<[f64; 2], DesignError> {
    let k = thesis_gains();
    let mut out = [0.0; 2];
    for i in 0..2 {
        let spec = ConstraintSpec {
            r: 3,
            eps: EPS,
            m: THESIS_M[i],
            beta_abs: THESIS_BETA[i],
            layer: LayerBound::TightIndex3,
        };
        out[i] = dae_runtime::design::t_min(&spec, THESIS_MU[i], k[i])?;
    }
    Ok(out)
}

/// The monitored run of the thesis: published `mu`, relaxed gains, cheap alpha_hat, RK4
/// with `h = 1e-4` and the thesis's rule of noticing a crossing at the end of the step
/// ([`Law::StepEnd`](dae_runtime::settings::Law::StepEnd): `|s|` overshoots its layer by up to one step of motion, 1 %
/// here), attracting surfaces, `t` in `[0, t_end]`, statistics after `settle`.
pub fn monitored(t_end: f64, settle: f64) -> Settings {
    Settings::new(vec![EPS; 2], THESIS_MU.to_vec(), thesis_gains())
        .step(STEP)
        .law(StepEnd::default())
        .t_end(t_end)
        .settle(settle)
}

/// The same without monitoring: an update every [`FIXED_PERIOD`].
pub fn fixed(t_end: f64, settle: f64) -> Settings {
    monitored(t_end, settle).law(Dbsmc::default().update(Update::Fixed {
        period: FIXED_PERIOD,
    }))
}

/// Tensions from the physics alone, for comparison with the simulator's `z_eq`.
///
/// `f` is affine in the tensions, so the accelerations are `A(z) = A(0) + z1 a1 + z2 a2`
/// with the columns taken from three evaluations of the model's right-hand side (only
/// `f`, none of the generated derivatives). The link lengths `l`, their rates
/// `l' = d.u/l` and `l'' = (u.u + d.A)/l - (d.u)^2/l^3` (`d` the link vector, `u` its
/// rate, `A` its acceleration) are written out here by hand. Returns
/// `(z with l'' = 0, z with s = mu^2 l'' + 2 mu l' + (l - L) = 0)`; the first is the
/// exact tension of the constrained motion (`Omega(x, z) = 0`), the second the `z` that
/// puts the state on the sliding surfaces, which `z_eq` approximates.
pub fn tension_oracle(
    model: &DoublePendulum3D,
    t: f64,
    x: &[f64],
    mu: [f64; 2],
) -> ([f64; 2], [f64; 2]) {
    let mut f = [[0.0; 12]; 3];
    for (k, z) in [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]].iter().enumerate() {
        model.rhs(t, x, z, &mut f[k]);
    }
    let v3 = |s: &[f64], o: usize| [s[o], s[o + 1], s[o + 2]];
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    // Links: (d, u) = (R1, V1) and (R2 - R1, V2 - V1); accelerations likewise.
    let links = [
        (v3(x, 0), v3(x, 6)),
        (sub(v3(x, 3), v3(x, 0)), sub(v3(x, 9), v3(x, 6))),
    ];
    let acc = |fk: &[f64; 12], link: usize| {
        if link == 0 {
            v3(fk, 6)
        } else {
            sub(v3(fk, 9), v3(fk, 6))
        }
    };
    let lengths = [model.L1, model.L2];
    // l_i'' = c0 + c1 z1 + c2 z2, and w, w'.
    let mut rows = [[0.0; 3]; 2];
    let mut w = [0.0; 2];
    let mut wd = [0.0; 2];
    for i in 0..2 {
        let (d, u) = links[i];
        let l = dot(d, d).sqrt();
        let du = dot(d, u);
        let a0 = acc(&f[0], i);
        let base = dot(u, u) / l - du * du / (l * l * l);
        rows[i][0] = base + dot(d, a0) / l;
        for k in 1..3 {
            rows[i][k] = dot(d, sub(acc(&f[k], i), a0)) / l;
        }
        w[i] = l - lengths[i];
        wd[i] = du / l;
    }
    let solve = |rhs: [f64; 2]| {
        let det = rows[0][1] * rows[1][2] - rows[0][2] * rows[1][1];
        [
            (rhs[0] * rows[1][2] - rows[0][2] * rhs[1]) / det,
            (rows[0][1] * rhs[1] - rhs[0] * rows[1][1]) / det,
        ]
    };
    let on_manifold = solve([-rows[0][0], -rows[1][0]]);
    // s = 0: l'' = -(2 mu w' + w) / mu^2.
    let target = |i: usize| -(2.0 * mu[i] * wd[i] + w[i]) / (mu[i] * mu[i]) - rows[i][0];
    let on_surface = solve([target(0), target(1)]);
    (on_manifold, on_surface)
}
