//! Integration tests of the DAE compiler live in `tests/tests/`; this library holds what
//! they share: the list of example models, a seeded random source and the comparison
//! used between two evaluations.
#![warn(missing_docs)]

use std::path::PathBuf;

/// The directory of the example models (`examples/models`).
pub fn models_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../examples/models")
}

/// Every example model file, `(file stem, source text)`, sorted by name.
pub fn example_sources() -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = std::fs::read_dir(models_dir())
        .expect("examples/models exists")
        .map(|e| e.expect("readable directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "dae"))
        .map(|p| {
            let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&p).expect("readable model file");
            (stem, text)
        })
        .collect();
    out.sort();
    out
}

/// The example models without families (language version 1 and scalar models), which
/// the Rust code generator compiles today; `(file stem, source text)`, sorted by name.
pub fn scalar_example_sources() -> Vec<(String, String)> {
    example_sources()
        .into_iter()
        .filter(|(_, text)| {
            dae_lang::check_source(text).is_ok_and(|ms| ms.iter().all(|m| !m.is_family()))
        })
        .collect()
}

/// `|a - b| <= tol * max(1, |a|, |b|)`; two NaNs are equal (both evaluations failed
/// the same way), a NaN against a number is not.
pub fn close(a: f64, b: f64, tol: f64) -> bool {
    if a.is_nan() || b.is_nan() {
        return a.is_nan() && b.is_nan();
    }
    if a == b {
        return true; // equal infinities
    }
    (a - b).abs() <= tol * 1f64.max(a.abs()).max(b.abs())
}

/// A small seeded generator (SplitMix64): reproducible random points without a
/// dependency.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let u = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_is_relative_above_one_and_absolute_below() {
        assert!(close(1e6, 1e6 + 1e-7, 1e-12));
        assert!(!close(1e6, 1e6 + 1e-5, 1e-12));
        assert!(close(1e-20, 2e-20, 1e-12));
        assert!(!close(0.0, 1e-11, 1e-12));
        assert!(close(f64::NAN, f64::NAN, 1e-12));
        assert!(!close(f64::NAN, 0.0, 1e-12));
    }

    #[test]
    fn uniform_stays_in_range_and_spreads() {
        let mut r = Rng::new(7);
        let v: Vec<f64> = (0..1000).map(|_| r.uniform(-2.0, 3.0)).collect();
        assert!(v.iter().all(|x| (-2.0..3.0).contains(x)));
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        assert!((mean - 0.5).abs() < 0.2, "mean {mean}");
    }
}
