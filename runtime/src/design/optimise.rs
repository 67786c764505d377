//! The choice of `mu_i` (T corollary 4.1, section 4.3): maximise `T_i^min(mu_i)` with the
//! gain `k_i(mu_i)` substituted, per constraint; the design's period is the smallest
//! `T_i^min` (T 3.15).

use super::{ConstraintSpec, DesignError, GainChoice, t_min};

/// Where and how finely [`optimise_mu`] searches.
///
/// Method: `T_min(mu)` is sampled at `scan_points` values of `mu` spaced evenly in
/// `ln mu` over `[lo, hi]`; the best sample must be interior (otherwise
/// [`DesignError::NoInteriorMaximum`]); then golden-section search on `ln mu` over the
/// two scan cells around it until the bracket is narrower than `ln_tol`. The scan makes
/// the result robust against several local maxima (it finds the best one to within a
/// scan cell); the golden-section step then converges to that maximum. Near a smooth
/// maximum `T_min` changes only to second order, so `mu` is located to about
/// `sqrt(f64::EPSILON) ~ 1.5e-8` relative at best, whatever `ln_tol`; `T_min` itself is
/// found to within a few units in the last place.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MuSearch {
    /// Smallest `mu` considered (`> 0`).
    pub lo: f64,
    /// Largest `mu` considered (`> lo`).
    pub hi: f64,
    /// Number of scan points, at least 3.
    pub scan_points: usize,
    /// Width of the final bracket in `ln mu`.
    pub ln_tol: f64,
}

impl Default for MuSearch {
    /// `mu` in `[1e-6, 1e3]`, 40 scan points per decade (361), `ln_tol = 1e-10`.
    fn default() -> Self {
        MuSearch {
            lo: 1e-6,
            hi: 1e3,
            scan_points: 361,
            ln_tol: 1e-10,
        }
    }
}

impl MuSearch {
    /// `ln mu` of scan point `i` of `scan_points`, evenly spaced over `[ln lo, ln hi]`.
    fn ln_mu_at(&self, i: usize) -> f64 {
        let (x_lo, x_hi) = (self.lo.ln(), self.hi.ln());
        x_lo + (x_hi - x_lo) * i as f64 / (self.scan_points - 1) as f64
    }
}

/// The outcome of [`optimise_mu`] for one constraint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstraintDesign {
    /// The chosen surface parameter. For `r = 1`, `s = w` does not depend on `mu` and
    /// neither do the gains or `T_min`; `mu` is then reported as 1.
    pub mu: f64,
    /// The gain at that `mu`.
    pub k: f64,
    /// The guaranteed period `T_i^min` at that `mu` and gain (T 3.14 or a variant).
    pub t_min: f64,
}

/// A design for all constraints.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    /// One entry per constraint, in input order.
    pub constraints: Vec<ConstraintDesign>,
    /// `T_min = min_i T_i^min` (T 3.15): the period that a fixed-period DBSMC may use.
    pub t_min: f64,
    /// The constraint that attains `t_min` (the first one on ties).
    pub limiting: usize,
    /// The quiet constraints (see [`design`]): their `T_i^min(mu)` had no maximum in the
    /// search range, and they were given the smallest `mu` that keeps `t_min`. Empty
    /// for [`design_at`].
    pub quiet: Vec<usize>,
}

/// Maximises `T_min(mu)` of one constraint with `k = gain.gain(spec, mu)` substituted
/// (method in [`MuSearch`]).
pub fn optimise_mu(
    spec: &ConstraintSpec,
    gain: GainChoice,
    search: &MuSearch,
) -> Result<ConstraintDesign, DesignError> {
    spec.validate()?;
    let eval = |mu: f64| at_mu(spec, gain, mu);
    if spec.r == 1 {
        // s = w: mu enters neither s, nor the gains, nor (T 3.14) (c_1 = 0).
        return eval(1.0);
    }
    let bad = DesignError::BadSearch {
        lo: search.lo,
        hi: search.hi,
        points: search.scan_points,
    };
    let tol_ok = search.ln_tol.is_finite() && search.ln_tol > 0.0;
    if !(search.lo.is_finite() && search.hi.is_finite() && search.lo > 0.0)
        || search.hi <= search.lo
        || search.scan_points < 3
        || !tol_ok
    {
        return Err(bad);
    }
    let n = search.scan_points;
    let x_at = |i: usize| search.ln_mu_at(i);
    let f = |x: f64| eval(x.exp()).map(|d| d.t_min);

    let mut best = (0, f64::NEG_INFINITY);
    for i in 0..n {
        let t = f(x_at(i))?;
        if t > best.1 {
            best = (i, t);
        }
    }
    let i = best.0;
    if i == 0 || i == n - 1 {
        return Err(DesignError::NoInteriorMaximum {
            mu: x_at(i).exp(),
            lo: search.lo,
            hi: search.hi,
        });
    }

    // Golden-section search for the maximum in [x_{i-1}, x_{i+1}].
    let inv_phi = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (x_at(i - 1), x_at(i + 1));
    let mut c = b - inv_phi * (b - a);
    let mut d = a + inv_phi * (b - a);
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    while b - a > search.ln_tol {
        if fc >= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - inv_phi * (b - a);
            fc = f(c)?;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + inv_phi * (b - a);
            fd = f(d)?;
        }
    }
    let found = eval((0.5 * (a + b)).exp())?;
    // Never return worse than the scan's best point (guards a flat top).
    if found.t_min >= best.1 {
        Ok(found)
    } else {
        eval(x_at(i).exp())
    }
}

/// Optimises every constraint with [`optimise_mu`] and takes `T_min = min_i T_i^min`
/// (T 3.15). Errors name the constraint ([`DesignError::Constraint`]).
///
/// **Quiet constraints.** A constraint whose pilot showed little or no drift has a
/// `T_i^min(mu)` that keeps growing up to the top of the search range (with `M = 0` and
/// `beta = 0` it is `mu / c_r`): it has no best `mu`, but it does not need one, because
/// it does not limit the period. Such a constraint gets the smallest `mu` at which
/// `T_i^min(mu)` reaches the period of the others (the fastest surface that keeps the
/// design's period; found on the scan and refined by bisection) and is listed in
/// [`Design::quiet`]. If every constraint is quiet, or a quiet one cannot reach the
/// others' period inside the range, the error names it
/// ([`DesignError::NoInteriorMaximum`]). In a long chain only the links near its ends
/// move in a short pilot; the middle ones are quiet.
///
/// The double pendulum of the thesis (docs/method.md section 8), relaxed gains with (T 4.6):
///
/// ```
/// use dae_runtime::{design::ConstraintSpec, design::GainChoice, design::LayerBound, design::MuSearch, design::design};
///
/// let link = |beta_abs, m| ConstraintSpec {
///     r: 3,
///     eps: 0.2,
///     m,
///     beta_abs,
///     layer: LayerBound::TightIndex3,
/// };
/// let d = design(&[link(1.3e3, 9e4), link(2.3e3, 11e4)], GainChoice::Relaxed, &MuSearch::default())?;
/// assert!((d.constraints[0].mu - 0.076).abs() < 0.001);
/// assert!((d.t_min - 0.0053).abs() < 1e-4);
/// assert!(d.quiet.is_empty());
/// # Ok::<(), dae_runtime::design::DesignError>(())
/// ```
pub fn design(
    specs: &[ConstraintSpec],
    gain: GainChoice,
    search: &MuSearch,
) -> Result<Design, DesignError> {
    if specs.is_empty() {
        return Err(DesignError::NoConstraints);
    }
    let named = |index: usize| {
        move |e: DesignError| DesignError::Constraint {
            index,
            source: Box::new(e),
        }
    };
    // Pass 1: every constraint on its own; the quiet ones are set aside.
    let mut found: Vec<Option<ConstraintDesign>> = Vec::with_capacity(specs.len());
    let mut quiet = Vec::new();
    let mut first_quiet_error = None;
    for (i, spec) in specs.iter().enumerate() {
        match optimise_mu(spec, gain, search) {
            Ok(d) => found.push(Some(d)),
            // At the top end of the range (not the bottom): T_min still growing.
            Err(e @ DesignError::NoInteriorMaximum { mu, .. })
                if mu * mu > search.lo * search.hi =>
            {
                first_quiet_error.get_or_insert((i, e));
                quiet.push(i);
                found.push(None);
            }
            Err(e) => return Err(named(i)(e)),
        }
    }
    // Pass 2: the quiet ones take the smallest mu that keeps the others' period.
    if !quiet.is_empty() {
        let target = found
            .iter()
            .flatten()
            .map(|d| d.t_min)
            .fold(f64::INFINITY, f64::min);
        if !target.is_finite() {
            let (i, e) = first_quiet_error.expect("a quiet constraint was recorded");
            return Err(named(i)(e));
        }
        for &i in &quiet {
            let d = smallest_mu_reaching(&specs[i], gain, search, target)
                .map_err(named(i))?
                .ok_or_else(|| {
                    named(i)(DesignError::NoInteriorMaximum {
                        mu: search.hi,
                        lo: search.lo,
                        hi: search.hi,
                    })
                })?;
            found[i] = Some(d);
        }
    }
    let constraints: Vec<ConstraintDesign> = found.into_iter().flatten().collect();
    Ok(finish(constraints, quiet))
}

/// The smallest `mu` on the scan of `search` (refined by bisection in `ln mu` between
/// it and the scan point below) at which `T_min(mu) >= target`, with its gain; `None`
/// if no scan point reaches `target`.
fn smallest_mu_reaching(
    spec: &ConstraintSpec,
    gain: GainChoice,
    search: &MuSearch,
    target: f64,
) -> Result<Option<ConstraintDesign>, DesignError> {
    let eval = |x: f64| at_mu(spec, gain, x.exp());
    let x_at = |i: usize| search.ln_mu_at(i);
    for i in 0..search.scan_points {
        let d = eval(x_at(i))?;
        if d.t_min < target {
            continue;
        }
        if i == 0 {
            return Ok(Some(d));
        }
        // T(a) < target <= T(b): bisect, keeping the reaching end.
        let (mut a, mut b, mut best) = (x_at(i - 1), x_at(i), d);
        while b - a > search.ln_tol {
            let c = 0.5 * (a + b);
            let dc = eval(c)?;
            if dc.t_min >= target {
                b = c;
                best = dc;
            } else {
                a = c;
            }
        }
        return Ok(Some(best));
    }
    Ok(None)
}

/// The design at given surface parameters: `k_i = gain.gain(spec_i, mu_i)` and
/// `T_i^min` (T 3.14 or a variant) at that `mu_i` and gain, without searching; `T_min`
/// is the smallest (T 3.15). For a model whose `mu` are fixed beforehand (e.g. the
/// published ones of an example). `mu` has one entry per spec.
pub fn design_at(
    specs: &[ConstraintSpec],
    mu: &[f64],
    gain: GainChoice,
) -> Result<Design, DesignError> {
    if mu.len() != specs.len() {
        return Err(DesignError::CountMismatch {
            what: "mu",
            got: mu.len(),
            expected: specs.len(),
        });
    }
    per_constraint(specs, |i, spec| at_mu(spec, gain, mu[i]))
}

/// The design of one constraint at a given `mu`: `k = gain.gain(spec, mu)` and
/// `T_min(mu, k)`.
fn at_mu(
    spec: &ConstraintSpec,
    gain: GainChoice,
    mu: f64,
) -> Result<ConstraintDesign, DesignError> {
    let k = gain.gain(spec, mu)?;
    Ok(ConstraintDesign {
        mu,
        k,
        t_min: t_min(spec, mu, k)?,
    })
}

/// Designs every constraint with `one` (errors name the constraint) and takes
/// `T_min = min_i T_i^min` (T 3.15).
fn per_constraint(
    specs: &[ConstraintSpec],
    one: impl Fn(usize, &ConstraintSpec) -> Result<ConstraintDesign, DesignError>,
) -> Result<Design, DesignError> {
    if specs.is_empty() {
        return Err(DesignError::NoConstraints);
    }
    let constraints = specs
        .iter()
        .enumerate()
        .map(|(index, spec)| {
            one(index, spec).map_err(|e| DesignError::Constraint {
                index,
                source: Box::new(e),
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(finish(constraints, Vec::new()))
}

/// The design of `constraints` (not empty): the smallest `T_i^min` and where it is.
fn finish(constraints: Vec<ConstraintDesign>, quiet: Vec<usize>) -> Design {
    let mut limiting = 0;
    for (i, c) in constraints.iter().enumerate() {
        if c.t_min < constraints[limiting].t_min {
            limiting = i;
        }
    }
    Design {
        t_min: constraints[limiting].t_min,
        limiting,
        constraints,
        quiet,
    }
}

#[cfg(test)]
mod tests;
