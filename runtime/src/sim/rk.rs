//! Explicit Runge-Kutta steps for `x`: the embedded pairs with error control and
//! dense output (Dormand-Prince 5(4), Bogacki-Shampine 3(2)), the Hermite dense output
//! of the fixed-step integrators, and the step-size controller.
//!
//! The right-hand side is a closure `f(dt, y, dy)` evaluated at `t + dt`: the
//! simulator evaluates `z` there on its exact ramp `z(t) + dt v`.

/// Coefficients of an embedded explicit pair with the FSAL property (the last stage is
/// evaluated at the new solution, so it is the next step's first stage).
pub(crate) struct Pair {
    /// Stage nodes.
    c: &'static [f64],
    /// `a[s]` holds the coefficients of stage `s` (`s >= 1`) on the stages before it.
    a: &'static [&'static [f64]],
    /// Error weights `b - b_hat` on all stages.
    e: &'static [f64],
    /// Exponent of the step controller: the order of the error estimate (lower order
    /// plus one).
    q: f64,
    /// Order of the propagated solution (for the initial step).
    order: f64,
    dense: DenseKind,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum DenseKind {
    /// The continuous extension of order 4 of Dormand and Prince (Hairer, Norsett and
    /// Wanner, *Solving ODEs I*, section II.6; the coefficients of their DOPRI5).
    DormandPrince,
    /// Cubic Hermite from the values and derivatives at both ends (order 3).
    Hermite,
}

impl Pair {
    /// Number of stages (the last is the next step's first).
    pub(crate) fn stages(&self) -> usize {
        self.c.len()
    }
}

/// Dormand-Prince 5(4), FSAL: 7 stages, 6 new `f` evaluations per step.
pub(crate) const DORMAND_PRINCE: Pair = Pair {
    c: &[0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0],
    a: &[
        &[],
        &[0.2],
        &[3.0 / 40.0, 9.0 / 40.0],
        &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
        &[
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
        ],
        &[
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
        &[
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ],
    e: &[
        71.0 / 57600.0,
        0.0,
        -71.0 / 16695.0,
        71.0 / 1920.0,
        -17253.0 / 339200.0,
        22.0 / 525.0,
        -1.0 / 40.0,
    ],
    q: 5.0,
    order: 5.0,
    dense: DenseKind::DormandPrince,
};

/// Bogacki-Shampine 3(2), FSAL: 4 stages, 3 new `f` evaluations per step.
pub(crate) const BOGACKI_SHAMPINE: Pair = Pair {
    c: &[0.0, 0.5, 0.75, 1.0],
    a: &[
        &[],
        &[0.5],
        &[0.0, 0.75],
        &[2.0 / 9.0, 1.0 / 3.0, 4.0 / 9.0],
    ],
    e: &[-5.0 / 72.0, 1.0 / 12.0, 1.0 / 9.0, -1.0 / 8.0],
    q: 3.0,
    order: 3.0,
    dense: DenseKind::Hermite,
};

/// Dense-output coefficients `d_j` of the Dormand-Prince continuous extension.
const DP_DENSE: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Stage storage and the dense output of the last step.
pub(crate) struct Rk {
    /// Stage derivatives; `k[0]` is `f` at the step's start.
    pub(crate) k: Vec<Vec<f64>>,
    ys: Vec<f64>,
    /// The new solution of the last step.
    pub(crate) y1: Vec<f64>,
    /// The last embedded step's error estimate `y1 - y_hat`.
    pub(crate) err: Vec<f64>,
    /// Dense output: the step's start `y0` and length `h`, with the coefficients `r`
    /// (Dormand-Prince) or the end derivative `f1` (Hermite).
    y0: Vec<f64>,
    h: f64,
    /// The Dormand-Prince output's coefficients `r2` ... `r5` of Hairer, Norsett and
    /// Wanner's `CONTD5` (`r5 = h sum d_j k_j`).
    r: [Vec<f64>; 4],
    /// Whether `r` is the last step's. It is computed at the step's first output only
    /// (from the stages, which stay until the next step): a located crossing reads the
    /// output several times per step, most steps and every rejected trial never.
    coefficients_known: bool,
    pub(crate) f1: Vec<f64>,
    kind: DenseKind,
    /// Whether the end derivative of a Hermite step is known.
    pub(crate) f1_known: bool,
}

impl Rk {
    pub(crate) fn new(n: usize) -> Self {
        let v = || vec![0.0; n];
        Self {
            k: (0..7).map(|_| v()).collect(),
            ys: v(),
            y1: v(),
            err: v(),
            y0: v(),
            h: 0.0,
            r: [v(), v(), v(), v()],
            coefficients_known: false,
            f1: v(),
            kind: DenseKind::Hermite,
            f1_known: false,
        }
    }

    /// One step of `pair` from `y0` over `h`, with `k[0] = f(t, y0)` already set.
    /// Returns the scaled error norm (accept when `<= 1`) and leaves the new solution in
    /// `y1` and `f(t + h, y1)` in `k[last]`.
    pub(crate) fn embedded<F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        pair: &Pair,
        y0: &[f64],
        h: f64,
        tol: (f64, f64),
        f: &mut F,
    ) -> f64 {
        let stages = pair.c.len();
        for s in 1..stages {
            combine(&mut self.ys, Some(y0), h, pair.a[s], &self.k);
            f(pair.c[s] * h, &self.ys, &mut self.k[s]);
        }
        // FSAL: the last stage's argument is the new solution.
        self.y1.copy_from_slice(&self.ys);
        combine(&mut self.err, None, h, pair.e, &self.k);
        self.y0.copy_from_slice(y0);
        self.h = h;
        self.kind = pair.dense;
        self.coefficients_known = false;
        if pair.dense == DenseKind::Hermite {
            self.f1.copy_from_slice(&self.k[stages - 1]);
            self.f1_known = true;
        }
        error_norm(&self.err, y0, &self.y1, tol)
    }

    /// Remember a fixed-step step from `y0` (with `f0 = k[0]`) to `y1` over `h` for the
    /// Hermite dense output; its end derivative is set later with
    /// [`set_end_derivative`](Self::set_end_derivative).
    pub(crate) fn fixed_done(&mut self, y0: &[f64], h: f64) {
        self.y0.copy_from_slice(y0);
        self.h = h;
        self.kind = DenseKind::Hermite;
        self.f1_known = false;
    }

    /// Length of the last step.
    pub(crate) fn step_length(&self) -> f64 {
        self.h
    }

    /// The dense output at `theta` in `[0, 1]` of the last step, into `out`.
    pub(crate) fn dense(&mut self, theta: f64, out: &mut [f64]) {
        let (y0, y1, h) = (&self.y0, &self.y1, self.h);
        match self.kind {
            DenseKind::DormandPrince => {
                let [r2, r3, r4, r5] = &mut self.r;
                if !self.coefficients_known {
                    combine(r5, None, h, &DP_DENSE, &self.k);
                    let (k1, k7) = (&self.k[0], &self.k[6]);
                    for i in 0..y0.len() {
                        r2[i] = y1[i] - y0[i];
                        r3[i] = h * k1[i] - r2[i];
                        r4[i] = r2[i] - h * k7[i] - r3[i];
                    }
                    self.coefficients_known = true;
                }
                let t1 = 1.0 - theta;
                for i in 0..out.len() {
                    out[i] = y0[i] + theta * (r2[i] + t1 * (r3[i] + theta * (r4[i] + t1 * r5[i])));
                }
            }
            DenseKind::Hermite => {
                debug_assert!(self.f1_known, "Hermite output needs the end derivative");
                let (f0, f1) = (&self.k[0], &self.f1);
                for i in 0..out.len() {
                    let d = y1[i] - y0[i];
                    out[i] = (1.0 - theta) * y0[i]
                        + theta * y1[i]
                        + theta
                            * (theta - 1.0)
                            * ((1.0 - 2.0 * theta) * d
                                + (theta - 1.0) * h * f0[i]
                                + theta * h * f1[i]);
                }
            }
        }
    }
}

/// `out = base + sum_j (h c_j) k_j` (`base` 0 if `None`), over the nonzero `c_j` (the
/// zeros of the tableaus are skipped) and added in the order of `j`: the roundings of one
/// `out += (h c_j) k_j` pass per `j`, in one pass over the states (a stage of
/// Dormand-Prince combines up to six derivatives, and the passes were a seventh of a
/// 10-link chain's step).
fn combine(out: &mut [f64], base: Option<&[f64]>, h: f64, c: &[f64], k: &[Vec<f64>]) {
    let n = out.len();
    let mut coef = [0.0; 7];
    let mut rows: [&[f64]; 7] = [&[]; 7];
    let mut m = 0;
    for (j, &cj) in c.iter().enumerate() {
        if cj != 0.0 {
            coef[m] = h * cj;
            rows[m] = &k[j][..n];
            m += 1;
        }
    }
    // One loop per number of terms, unrolled over them at compile time.
    match m {
        0 => combine_terms::<0>(out, base, &coef, &rows),
        1 => combine_terms::<1>(out, base, &coef, &rows),
        2 => combine_terms::<2>(out, base, &coef, &rows),
        3 => combine_terms::<3>(out, base, &coef, &rows),
        4 => combine_terms::<4>(out, base, &coef, &rows),
        5 => combine_terms::<5>(out, base, &coef, &rows),
        6 => combine_terms::<6>(out, base, &coef, &rows),
        _ => combine_terms::<7>(out, base, &coef, &rows),
    }
}

/// [`combine`] with its first `M` terms.
fn combine_terms<const M: usize>(
    out: &mut [f64],
    base: Option<&[f64]>,
    coef: &[f64; 7],
    rows: &[&[f64]; 7],
) {
    let n = out.len();
    let rows: [&[f64]; M] = std::array::from_fn(|t| &rows[t][..n]);
    match base {
        Some(b) => {
            let b = &b[..n];
            for i in 0..n {
                let mut acc = b[i];
                for t in 0..M {
                    acc += coef[t] * rows[t][i];
                }
                out[i] = acc;
            }
        }
        None => {
            for i in 0..n {
                let mut acc = 0.0;
                for t in 0..M {
                    acc += coef[t] * rows[t][i];
                }
                out[i] = acc;
            }
        }
    }
}

/// RMS of `err_i / (atol + rtol max(|y0_i|, |y1_i|))` (0 for no states).
fn error_norm(err: &[f64], y0: &[f64], y1: &[f64], (rtol, atol): (f64, f64)) -> f64 {
    if err.is_empty() {
        return 0.0;
    }
    let mut sum = 0.0;
    for i in 0..err.len() {
        let sc = atol + rtol * y0[i].abs().max(y1[i].abs());
        let r = err[i] / sc;
        sum += r * r;
    }
    let norm = (sum / err.len() as f64).sqrt();
    if norm.is_nan() { f64::INFINITY } else { norm }
}

/// The factor by which the next step may grow after a step with error norm `err`.
pub(crate) fn step_factor(pair: &Pair, err: f64, after_reject: bool) -> f64 {
    let raw = if err <= 0.0 {
        5.0
    } else {
        0.9 * err.powf(-1.0 / pair.q)
    };
    let hi = if after_reject { 1.0 } else { 5.0 };
    if raw.is_nan() {
        0.2
    } else {
        raw.clamp(0.2, hi)
    }
}

/// A first step for `pair` (Hairer, Norsett and Wanner, section II.4): from the sizes of
/// `y0`, `f0 = f(t, y0)` and one Euler step's change of `f`. Costs one `f` evaluation
/// (into `scratch_f`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<F: FnMut(f64, &[f64], &mut [f64])>(
    pair: &Pair,
    y0: &[f64],
    f0: &[f64],
    tol: (f64, f64),
    h_max: f64,
    scratch_y: &mut [f64],
    scratch_f: &mut [f64],
    f: &mut F,
) -> f64 {
    let (rtol, atol) = tol;
    let n = y0.len().max(1) as f64;
    let norm = |v: &[f64]| {
        let mut s = 0.0;
        for i in 0..v.len() {
            let r = v[i] / (atol + rtol * y0[i].abs());
            s += r * r;
        }
        (s / n).sqrt()
    };
    let d0 = norm(y0);
    let d1 = norm(f0);
    let h0 = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    }
    .min(h_max);
    for i in 0..y0.len() {
        scratch_y[i] = y0[i] + h0 * f0[i];
    }
    f(h0, scratch_y, scratch_f);
    for i in 0..y0.len() {
        scratch_y[i] = scratch_f[i] - f0[i];
    }
    let d2 = norm(scratch_y) / h0;
    let big = d1.max(d2);
    let h1 = if big <= 1e-15 {
        (h0 * 1e-3).max(1e-6)
    } else {
        (0.01 / big).powf(1.0 / pair.order)
    };
    let h = (100.0 * h0).min(h1).min(h_max);
    if h.is_finite() && h > 0.0 { h } else { 1e-6 }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y' = (cos t, -y2), y(0) = (0, 1): exact (sin t, e^-t).
    fn f(t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = t.cos();
        dy[1] = -y[1];
    }

    fn exact(t: f64) -> [f64; 2] {
        [t.sin(), (-t).exp()]
    }

    fn one_step(pair: &Pair, t: f64, h: f64) -> (Rk, f64) {
        let mut rk = Rk::new(2);
        let y0 = exact(t);
        f(t, &y0, &mut rk.k[0]);
        let err = rk.embedded(pair, &y0, h, (1e-6, 1e-6), &mut |dt, y, dy| {
            f(t + dt, y, dy)
        });
        (rk, err)
    }

    /// Local error of the step and of the dense output at theta = 0.37, and the
    /// embedded estimate, for steps h and h/2: their ratios give the orders.
    fn orders(pair: &Pair) -> (f64, f64, f64) {
        let t = 0.3;
        let mut out = [0.0; 2];
        let mut errs = [[0.0; 3]; 2];
        for (k, h) in [0.2, 0.1].into_iter().enumerate() {
            let (mut rk, est) = one_step(pair, t, h);
            let e = exact(t + h);
            errs[k][0] = (rk.y1[0] - e[0]).abs().max((rk.y1[1] - e[1]).abs());
            rk.dense(0.37, &mut out);
            let e = exact(t + 0.37 * h);
            errs[k][1] = (out[0] - e[0]).abs().max((out[1] - e[1]).abs());
            errs[k][2] = est;
        }
        let p = |i: usize| (errs[0][i] / errs[1][i]).log2();
        (p(0), p(1), p(2))
    }

    #[test]
    fn dormand_prince_local_orders_of_step_dense_output_and_estimate() {
        let (step, dense, est) = orders(&DORMAND_PRINCE);
        // Local errors: O(h^6) for the 5th-order step, O(h^5) for the order-4 dense
        // output and the embedded estimate.
        assert!((5.6..6.6).contains(&step), "step {step}");
        assert!((4.6..5.6).contains(&dense), "dense {dense}");
        assert!((4.6..5.6).contains(&est), "estimate {est}");
    }

    #[test]
    fn bogacki_shampine_local_orders_of_step_dense_output_and_estimate() {
        let (step, dense, est) = orders(&BOGACKI_SHAMPINE);
        assert!((3.6..4.6).contains(&step), "step {step}");
        assert!((3.6..4.6).contains(&dense), "dense {dense}");
        assert!((2.6..3.6).contains(&est), "estimate {est}");
    }

    #[test]
    fn dense_output_meets_both_ends() {
        for pair in [&DORMAND_PRINCE, &BOGACKI_SHAMPINE] {
            let (mut rk, _) = one_step(pair, 0.1, 0.3);
            let mut out = [0.0; 2];
            rk.dense(0.0, &mut out);
            assert_eq!(out, exact(0.1));
            rk.dense(1.0, &mut out);
            for (o, y) in out.iter().zip(&rk.y1) {
                assert!((o - y).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn hermite_output_of_a_fixed_step_is_exact_for_cubics() {
        // y = t^3 - t: y' = 3 t^2 - 1, from t = 1 to t = 3.
        let mut rk = Rk::new(1);
        rk.k[0][0] = 2.0;
        rk.y1[0] = 24.0;
        rk.fixed_done(&[0.0], 2.0);
        rk.f1[0] = 26.0;
        rk.f1_known = true;
        let mut out = [0.0];
        for theta in [0.0, 0.25, 0.5, 0.9, 1.0] {
            rk.dense(theta, &mut out);
            let t = 1.0 + 2.0 * theta;
            assert!((out[0] - (t * t * t - t)).abs() < 1e-12, "{theta}");
        }
    }

    #[test]
    fn step_factor_is_clamped_and_nan_safe() {
        assert_eq!(step_factor(&DORMAND_PRINCE, 0.0, false), 5.0);
        assert_eq!(step_factor(&DORMAND_PRINCE, 0.0, true), 1.0);
        assert_eq!(step_factor(&DORMAND_PRINCE, 1e9, false), 0.2);
        assert_eq!(step_factor(&DORMAND_PRINCE, f64::NAN, false), 0.2);
        let f = step_factor(&DORMAND_PRINCE, 1.0, false);
        assert!((f - 0.9).abs() < 1e-12);
    }

    /// `combine` is one pass doing what one `out += (h c_j) k_j` pass per nonzero `c_j`
    /// did: the same sums in the same order, so the same bits (the runs of the
    /// benchmark end alike to the bit across the change).
    #[test]
    fn a_combination_has_the_bits_of_one_pass_per_term() {
        let n = 13;
        // Values of many magnitudes and signs, and a zero coefficient to skip.
        let k: Vec<Vec<f64>> = (0..7)
            .map(|j| {
                (0..n)
                    .map(|i| ((i * 7 + j * 3) as f64).sin() * 10f64.powi(i as i32 % 5 - 2))
                    .collect()
            })
            .collect();
        let base: Vec<f64> = (0..n).map(|i| (i as f64).cos() * 1e3).collect();
        let h = 0.0123;
        for terms in 0..=7 {
            let c: Vec<f64> = (0..terms)
                .map(|j| {
                    if j == 1 {
                        0.0
                    } else {
                        1.0 / (j as f64 + 0.7) - 0.9
                    }
                })
                .collect();
            for start in [Some(&base[..]), None] {
                let mut expect = start.map_or(vec![0.0; n], <[f64]>::to_vec);
                for (j, &cj) in c.iter().enumerate() {
                    if cj != 0.0 {
                        let a = h * cj;
                        for (y, x) in expect.iter_mut().zip(&k[j]) {
                            *y += a * x;
                        }
                    }
                }
                let mut out = vec![f64::NAN; n];
                combine(&mut out, start, h, &c, &k);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&out),
                    bits(&expect),
                    "{terms} terms, base {}",
                    start.is_some()
                );
            }
        }
    }

    /// The Dormand-Prince output computes its coefficients at a step's first output and
    /// reuses them: a second output of the same step, and the first of the next step, are
    /// to the bit what a fresh computation gives (it fails when a new step keeps the last
    /// step's coefficients).
    #[test]
    fn the_dense_output_is_always_the_last_steps() {
        let pair = &DORMAND_PRINCE;
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let mut out = [0.0; 2];
        let mut fresh = [0.0; 2];
        let (mut rk, _) = one_step(pair, 0.3, 0.2);
        rk.dense(0.25, &mut out);
        let (mut rk_fresh, _) = one_step(pair, 0.3, 0.2);
        rk_fresh.dense(0.75, &mut fresh);
        rk.dense(0.75, &mut out);
        assert_eq!(bits(&out), bits(&fresh));
        // The next step, on the same storage.
        let (t, h) = (0.5, 0.1);
        let y0 = exact(t);
        f(t, &y0, &mut rk.k[0]);
        rk.embedded(pair, &y0, h, (1e-6, 1e-6), &mut |dt, y, dy| {
            f(t + dt, y, dy)
        });
        rk.dense(0.4, &mut out);
        let (mut rk_fresh, _) = one_step(pair, t, h);
        rk_fresh.dense(0.4, &mut fresh);
        assert_eq!(bits(&out), bits(&fresh));
    }
}
