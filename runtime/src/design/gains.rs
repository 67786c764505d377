//! Gains: the sufficient crossing gain (T 4.4, corrected), the robust gain (T 3.17,
//! 3.21) and the design choices of docs/method.md section 5.

use super::{ConstraintSpec, DesignError, check_index, mu_pow, non_negative, positive};

/// The sufficient crossing gain `k*` (T 4.4, corrected as in T 5.7):
///
/// ```text
/// k* = mu^r M / (r - 1) + 2 (2^r - r - 1) eps / ((r - 1) mu)      for r >= 2
/// ```
///
/// (`r = 3`: `mu^3 M / 2 + 4 eps / mu`). The thesis formula is singular at `r = 1`. For
/// `r = 1` we use our own bound, derived from the same crossing requirement: there
/// `s = w` and `mu` plays no role; with exact `alpha` the update sets `s' = -k sgn(s_b)`,
/// and within the interval `|s'(t) - s'(t_b)| <= M (t - t_b)` (T 3.5), so `s` covers at
/// least `k tau - M tau^2 / 2` while its rate keeps its sign (`tau < k / M`). Starting
/// anywhere in the layer it must cover up to `2 eps` to leave it on the far side, which
/// is guaranteed when `k^2 / (2 M) >= 2 eps`:
///
/// ```text
/// k* = 2 sqrt(M eps)                                               for r = 1
/// ```
pub fn sufficient_gain(r: usize, mu: f64, m: f64, eps: f64) -> Result<f64, DesignError> {
    check_index(r)?;
    positive("mu", mu)?;
    non_negative("M", m)?;
    positive("eps", eps)?;
    if r == 1 {
        return Ok(2.0 * (m * eps).sqrt());
    }
    let rm1 = (r - 1) as f64;
    let pow2 = 2f64.powi(r as i32);
    Ok(mu_pow(mu, r) * m / rm1 + 2.0 * (pow2 - r as f64 - 1.0) * eps / (rm1 * mu))
}

/// The robust gain for the cheap `alpha_hat` (T 3.17, 3.21): the crossing gain `k_c`
/// plus the neglected part of `alpha`, `|alpha - alpha_hat| = mu^(r-1) |beta|`:
///
/// ```text
/// k = k_c + mu^(r-1) |beta|
/// ```
pub fn robust_gain(k_c: f64, r: usize, mu: f64, beta_abs: f64) -> Result<f64, DesignError> {
    non_negative("k_c", k_c)?;
    check_index(r)?;
    positive("mu", mu)?;
    non_negative("|beta|", beta_abs)?;
    Ok(k_c + mu_pow(mu, r - 1) * beta_abs)
}

/// How the gain `k_i` of a constraint follows from its `mu_i` during the design.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum GainChoice {
    /// `k = k* + mu^(r-1) |beta|`: [`sufficient_gain`] made robust for the cheap
    /// `alpha_hat` with [`robust_gain`]. For `r = 3`:
    /// `k = mu^3 M / 2 + 4 eps / mu + mu^2 |beta|` (docs/method.md section 5).
    #[default]
    Sufficient,
    /// `k = mu^(r-1) |beta|`: only the part of `alpha` the cheap `alpha_hat` neglects.
    /// Not covered by the crossing guarantee; enough in the thesis example (T section
    /// 4.3, docs/method.md sections 5 and 8).
    Relaxed,
    /// The same given gain `k >= 0` for every `mu`.
    Fixed(f64),
}

impl GainChoice {
    /// The gain for constraint `spec` at surface parameter `mu`.
    pub fn gain(&self, spec: &ConstraintSpec, mu: f64) -> Result<f64, DesignError> {
        spec.validate()?;
        positive("mu", mu)?;
        match *self {
            GainChoice::Sufficient => robust_gain(
                sufficient_gain(spec.r, mu, spec.m, spec.eps)?,
                spec.r,
                mu,
                spec.beta_abs,
            ),
            GainChoice::Relaxed => robust_gain(0.0, spec.r, mu, spec.beta_abs),
            GainChoice::Fixed(k) => non_negative("k", k),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::LayerBound;

    #[test]
    fn sufficient_gain_matches_the_written_out_low_index_forms() {
        let (mu, m, eps) = (0.065f64, 9e4, 0.2);
        // r = 2: mu^2 M + 2 eps / mu; r = 3: mu^3 M / 2 + 4 eps / mu;
        // r = 4: mu^4 M / 3 + 22 eps / (3 mu).
        let expect = [
            (2, mu * mu * m + 2.0 * eps / mu),
            (3, mu.powi(3) * m / 2.0 + 4.0 * eps / mu),
            (4, mu.powi(4) * m / 3.0 + 22.0 * eps / (3.0 * mu)),
        ];
        for (r, e) in expect {
            let k = sufficient_gain(r, mu, m, eps).unwrap();
            assert!((k - e).abs() <= 1e-13 * e, "r = {r}: {k} vs {e}");
        }
    }

    #[test]
    fn index_one_gain_makes_the_worst_case_reach_the_far_side() {
        // Oracle: integrate the worst case s'' = +M (rate decaying from -k) with a fine
        // explicit step and check that s still moves when it has covered 2 eps, and that
        // a 1% smaller gain turns around before.
        let (m, eps) = (50.0, 0.1);
        let k = sufficient_gain(1, 123.0, m, eps).unwrap();
        assert!((k - 2.0 * (m * eps).sqrt()).abs() < 1e-15);
        let travel = |k: f64| {
            let (mut d, mut rate, h) = (0.0, k, 1e-6);
            while rate > 0.0 {
                d += rate * h - 0.5 * m * h * h;
                rate -= m * h;
            }
            d
        };
        assert!(travel(k) >= 2.0 * eps * (1.0 - 1e-5));
        assert!(travel(0.99 * k) < 2.0 * eps);
    }

    #[test]
    fn gain_choices_of_section_five() {
        let spec = ConstraintSpec {
            r: 3,
            eps: 0.2,
            m: 9e4,
            beta_abs: 1.3e3,
            layer: LayerBound::General,
        };
        let mu = 0.065f64;
        let suff = GainChoice::Sufficient.gain(&spec, mu).unwrap();
        let want = mu.powi(3) * 9e4 / 2.0 + 4.0 * 0.2 / mu + mu * mu * 1.3e3;
        assert!((suff - want).abs() <= 1e-13 * want);
        let relaxed = GainChoice::Relaxed.gain(&spec, mu).unwrap();
        assert!((relaxed - mu * mu * 1.3e3).abs() < 1e-12);
        assert_eq!(GainChoice::Fixed(7.5).gain(&spec, mu).unwrap(), 7.5);
        assert!(GainChoice::Fixed(-1.0).gain(&spec, mu).is_err());
    }

    #[test]
    fn robust_gain_adds_the_neglected_beta_term() {
        assert!((robust_gain(10.0, 2, 0.5, 4.0).unwrap() - 12.0).abs() < 1e-15);
        assert_eq!(robust_gain(10.0, 1, 0.5, 4.0).unwrap(), 14.0);
        assert!(robust_gain(f64::NAN, 2, 0.5, 4.0).is_err());
        assert!(robust_gain(1.0, 0, 0.5, 4.0).is_err());
        assert!(robust_gain(1.0, 2, 0.5, -4.0).is_err());
    }

    #[test]
    fn sufficient_gain_rejects_bad_input() {
        assert!(matches!(
            sufficient_gain(0, 0.1, 1.0, 0.1),
            Err(DesignError::BadIndex { .. })
        ));
        assert!(sufficient_gain(3, 0.0, 1.0, 0.1).is_err());
        assert!(sufficient_gain(3, 0.1, f64::NAN, 0.1).is_err());
        assert!(sufficient_gain(3, 0.1, 1.0, 0.0).is_err());
    }
}
