//! The guaranteed update period (T 3.14) and the reachable bound for a given period
//! (T 3.13).
//!
//! Both come from one inequality. Within a control interval of length `T` that starts
//! at an update, `s` cannot move farther than
//!
//! ```text
//! |Delta s| <= a T^2 + b T,   a = mu^(r-1) M,   b = k + lambda eps
//! ```
//!
//! where `lambda eps` bounds the drift of the sliding terms of `alpha` while `|s| <= eps`
//! ([`LayerBound`]). Setting `|Delta s| = eps` gives `T_min` (T 3.14); solving the same
//! relation for `eps` at a given `T` gives the reachable bound (T 3.13).

use super::{ConstraintSpec, DesignError, check_index, mu_pow, non_negative, positive};

/// Which bound on the sliding terms of `alpha` enters `b = k + lambda eps` of (T 3.14).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum LayerBound {
    /// `lambda = c_r / mu` with `c_r = 4 (2^(r-1) - 1)` (T 3.12, 3.14). Any index.
    #[default]
    General,
    /// `lambda = c_3 / mu` with the tighter `c_3 = 4 (2 + e^-3)` (T 4.6, from T lemma
    /// 4.2). Index 3 only.
    TightIndex3,
    /// The spectrum of `w` is limited to `omega_m` (rad/s), so `|w^(j)| <= omega_m^j eps`
    /// and `|2 mu w'' + w'| <= (2 mu omega_m^2 + omega_m) eps` (T 4.7):
    /// `lambda = 2 mu omega_m^2 + omega_m`. Index 3 only: the thesis states it for
    /// `r = 3`, and the factor that relates this bound to `c_r` for other indices is
    /// not given there, so we do not extrapolate it.
    Spectrum {
        /// The frequency bound `omega_m > 0`.
        omega_m: f64,
    },
}

impl LayerBound {
    /// Checks that the bound applies to index `r` and that its parameter is valid.
    pub fn validate(&self, r: usize) -> Result<(), DesignError> {
        check_index(r)?;
        match *self {
            LayerBound::General => Ok(()),
            LayerBound::TightIndex3 if r == 3 => Ok(()),
            LayerBound::TightIndex3 => Err(DesignError::IndexNotSupported {
                formula: "(T 4.6)",
                r,
            }),
            LayerBound::Spectrum { omega_m } => {
                positive("omega_m", omega_m)?;
                if r == 3 {
                    Ok(())
                } else {
                    Err(DesignError::IndexNotSupported {
                        formula: "(T 4.7)",
                        r,
                    })
                }
            }
        }
    }

    /// The coefficient `lambda` in `b = k + lambda eps` for index `r` and surface
    /// parameter `mu` (see the variants).
    pub fn lambda(&self, r: usize, mu: f64) -> Result<f64, DesignError> {
        self.validate(r)?;
        positive("mu", mu)?;
        Ok(match *self {
            LayerBound::General => c_r(r)? / mu,
            LayerBound::TightIndex3 => 4.0 * (2.0 + (-3.0f64).exp()) / mu,
            LayerBound::Spectrum { omega_m } => 2.0 * mu * omega_m * omega_m + omega_m,
        })
    }
}

/// `c_r = 4 (2^(r-1) - 1)` of (T 3.12): 0, 4, 12, 28, ... for r = 1, 2, 3, 4.
pub fn c_r(r: usize) -> Result<f64, DesignError> {
    check_index(r)?;
    Ok(4.0 * (2f64.powi(r as i32 - 1) - 1.0))
}

/// The guaranteed minimum update period of one constraint (T 3.14):
///
/// ```text
/// T_min = (-b + sqrt(b^2 + 4 a eps)) / (2 a),  a = mu^(r-1) M,  b = k + lambda eps
/// ```
///
/// with `lambda` from `spec.layer` ([`LayerBound`]; `General` is (T 3.14) itself,
/// `TightIndex3` is (T 4.6), `Spectrum` is (T 4.7)). It is evaluated in the equivalent
/// form `T = 2 eps / (b + sqrt(b^2 + 4 a eps))`, which has no cancellation when
/// `4 a eps << b^2` and stays valid for `M = 0` (`T = eps / b`). The square root is
/// taken with `hypot` so that large `b` does not overflow. `spec.beta_abs` is not used
/// (it enters through the gain `k`). Returns `+inf` when `a = b = 0` (nothing limits
/// the period).
pub fn t_min(spec: &ConstraintSpec, mu: f64, k: f64) -> Result<f64, DesignError> {
    spec.validate()?;
    positive("mu", mu)?;
    non_negative("k", k)?;
    let a = mu_pow(mu, spec.r - 1) * spec.m;
    let b = k + spec.layer.lambda(spec.r, mu)? * spec.eps;
    let root = b.hypot(2.0 * (a * spec.eps).sqrt());
    Ok(2.0 * spec.eps / (b + root))
}

/// The bound on `|s|` reachable with a fixed update period `T` (T 3.13):
///
/// ```text
/// |s| <= (mu^(r-1) M T + k) / (1/T - lambda)
/// ```
///
/// (`lambda = c_r / mu` for [`LayerBound::General`]). It inverts [`t_min`]: at
/// `T = t_min(spec, mu, k)` it returns `spec.eps`. Errors with
/// [`DesignError::PeriodTooLong`] when `T >= 1 / lambda` (i.e. `T >= mu / c_r`), where the
/// bound does not exist. `spec.eps` is only validated, not used.
pub fn reachable_bound(
    spec: &ConstraintSpec,
    mu: f64,
    k: f64,
    period: f64,
) -> Result<f64, DesignError> {
    spec.validate()?;
    positive("mu", mu)?;
    non_negative("k", k)?;
    positive("period", period)?;
    let lambda = spec.layer.lambda(spec.r, mu)?;
    let a = mu_pow(mu, spec.r - 1) * spec.m;
    if lambda * period >= 1.0 {
        return Err(DesignError::PeriodTooLong {
            period,
            limit: 1.0 / lambda,
        });
    }
    // (aT + k) / (1/T - lambda) multiplied through by T: no division by a tiny 1/T.
    Ok((a * period + k) * period / (1.0 - lambda * period))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(r: usize, eps: f64, m: f64) -> ConstraintSpec {
        ConstraintSpec {
            r,
            eps,
            m,
            beta_abs: 0.0,
            layer: LayerBound::General,
        }
    }

    #[test]
    fn c_r_matches_closed_form_values() {
        let expected = [0.0, 4.0, 12.0, 28.0, 60.0];
        for (i, e) in expected.iter().enumerate() {
            assert_eq!(c_r(i + 1).unwrap(), *e);
        }
        assert!(matches!(c_r(0), Err(DesignError::BadIndex { r: 0, .. })));
    }

    #[test]
    fn t_min_is_the_positive_root_of_the_quadratic() {
        // Oracle: the textbook root (-b + sqrt(b^2 + 4 a eps)) / (2a), well conditioned
        // for these numbers, and the residual of a T^2 + b T - eps = 0.
        let sp = spec(3, 0.2, 9e4);
        let (mu, k) = (0.07, 50.0);
        let t = t_min(&sp, mu, k).unwrap();
        let a = mu * mu * 9e4;
        let b = k + 12.0 * 0.2 / mu;
        let textbook = (-b + (b * b + 4.0 * a * 0.2).sqrt()) / (2.0 * a);
        assert!(
            (t - textbook).abs() <= 1e-12 * textbook,
            "{t} vs {textbook}"
        );
        assert!((a * t * t + b * t - 0.2).abs() < 1e-14);
    }

    #[test]
    fn t_min_is_stable_when_four_a_eps_is_tiny() {
        // 4 a eps / b^2 ~ 1e-20: the textbook form loses every digit; the series
        // T = eps/b - a eps^2/b^3 + ... is the oracle.
        let sp = spec(2, 1e-3, 1e-9);
        let (mu, k) = (1e-3, 1e3);
        let t = t_min(&sp, mu, k).unwrap();
        let a = mu * 1e-9;
        let b = k + 4.0 * 1e-3 / mu;
        let series = 1e-3 / b - a * 1e-6 / (b * b * b);
        assert!((t - series).abs() <= 1e-15 * series, "{t} vs {series}");
        let textbook = (-b + (b * b + 4.0 * a * 1e-3).sqrt()) / (2.0 * a);
        assert!(
            (textbook - series).abs() > 0.5 * series,
            "textbook form should fail"
        );
    }

    #[test]
    fn t_min_without_drift_is_eps_over_b_and_infinite_without_anything() {
        let t = t_min(&spec(2, 0.1, 0.0), 0.5, 3.0).unwrap();
        assert!((t - 0.1 / (3.0 + 4.0 * 0.1 / 0.5)).abs() < 1e-15);
        assert_eq!(t_min(&spec(1, 0.1, 0.0), 0.5, 0.0).unwrap(), f64::INFINITY);
        // r = 1, k = 0: T = sqrt(eps / M).
        let t1 = t_min(&spec(1, 0.1, 40.0), 7.0, 0.0).unwrap();
        assert!((t1 - 0.05).abs() < 1e-15);
    }

    #[test]
    fn variants_use_their_constants() {
        let (mu, k, eps, m) = (0.07, 10.0, 0.2, 9e4);
        let a = mu * mu * m;
        let root = |b: f64| (-b + (b * b + 4.0 * a * eps).sqrt()) / (2.0 * a);
        let mut sp = spec(3, eps, m);
        sp.layer = LayerBound::TightIndex3;
        let c3 = 4.0 * (2.0 + (-3.0f64).exp());
        let t = t_min(&sp, mu, k).unwrap();
        assert!((t - root(k + c3 * eps / mu)).abs() < 1e-12 * t);
        let w = 30.0;
        sp.layer = LayerBound::Spectrum { omega_m: w };
        let t = t_min(&sp, mu, k).unwrap();
        assert!((t - root(k + (2.0 * mu * w * w + w) * eps)).abs() < 1e-12 * t);
    }

    #[test]
    fn index_restricted_variants_reject_other_indices() {
        let mut sp = spec(2, 0.2, 1.0);
        sp.layer = LayerBound::TightIndex3;
        assert_eq!(
            t_min(&sp, 0.1, 1.0),
            Err(DesignError::IndexNotSupported {
                formula: "(T 4.6)",
                r: 2
            })
        );
        sp.layer = LayerBound::Spectrum { omega_m: 3.0 };
        assert!(matches!(
            t_min(&sp, 0.1, 1.0),
            Err(DesignError::IndexNotSupported { r: 2, .. })
        ));
        sp.r = 3;
        sp.layer = LayerBound::Spectrum { omega_m: f64::NAN };
        assert!(matches!(
            t_min(&sp, 0.1, 1.0),
            Err(DesignError::NotPositive {
                name: "omega_m",
                ..
            })
        ));
    }

    #[test]
    fn bad_inputs_are_errors() {
        let ok = spec(3, 0.2, 1.0);
        let cases = [
            (spec(3, 0.0, 1.0), 0.1, 1.0, "eps"),
            (spec(3, -1.0, 1.0), 0.1, 1.0, "eps"),
            (spec(3, f64::NAN, 1.0), 0.1, 1.0, "eps"),
            (ok, 0.0, 1.0, "mu"),
            (ok, f64::NAN, 1.0, "mu"),
            (ok, 0.1, -1.0, "k"),
            (ok, 0.1, f64::INFINITY, "k"),
            (spec(3, 0.2, -1.0), 0.1, 1.0, "M"),
        ];
        for (sp, mu, k, name) in cases {
            match t_min(&sp, mu, k) {
                Err(DesignError::NotPositive { name: n, .. })
                | Err(DesignError::Negative { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{name}: expected an error, got {other:?}"),
            }
        }
        assert!(matches!(
            t_min(&spec(0, 0.2, 1.0), 0.1, 1.0),
            Err(DesignError::BadIndex { r: 0, .. })
        ));
        assert!(matches!(
            t_min(&spec(65, 0.2, 1.0), 0.1, 1.0),
            Err(DesignError::BadIndex { r: 65, .. })
        ));
    }

    #[test]
    fn reachable_bound_inverts_t_min() {
        for (r, layer) in [
            (1, LayerBound::General),
            (2, LayerBound::General),
            (3, LayerBound::General),
            (3, LayerBound::TightIndex3),
            (3, LayerBound::Spectrum { omega_m: 12.0 }),
            (4, LayerBound::General),
        ] {
            let sp = ConstraintSpec {
                r,
                eps: 0.2,
                m: 9e4,
                beta_abs: 0.0,
                layer,
            };
            let (mu, k) = (0.06, 25.0);
            let t = t_min(&sp, mu, k).unwrap();
            let s = reachable_bound(&sp, mu, k, t).unwrap();
            assert!((s - 0.2).abs() < 1e-12, "r = {r} {layer:?}: {s}");
            // Monotone: a shorter period reaches less far.
            assert!(reachable_bound(&sp, mu, k, 0.5 * t).unwrap() < s);
        }
    }

    #[test]
    fn reachable_bound_rejects_periods_at_or_beyond_mu_over_c_r() {
        let sp = spec(3, 0.2, 9e4);
        let mu = 0.06;
        let limit = mu / 12.0;
        assert!(matches!(
            reachable_bound(&sp, mu, 1.0, limit),
            Err(DesignError::PeriodTooLong { .. })
        ));
        match reachable_bound(&sp, mu, 1.0, 2.0 * limit) {
            Err(DesignError::PeriodTooLong { limit: l, .. }) => {
                assert!((l - limit).abs() < 1e-15)
            }
            other => panic!("expected PeriodTooLong, got {other:?}"),
        }
        assert!(reachable_bound(&sp, mu, 1.0, 0.99 * limit).unwrap() > 0.0);
        assert!(reachable_bound(&sp, mu, 1.0, f64::NAN).is_err());
    }
}
