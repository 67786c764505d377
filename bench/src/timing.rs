//! The time of one short call, for the examples that print tables of them (`solvers`,
//! `kernels`).

use std::time::Instant;

/// Best time per call of `f` in seconds: the calls per batch are doubled until a batch
/// lasts at least 20 ms, then the best of 5 such batches. On a shared machine the least
/// disturbed batch is the closest to the call's own cost; compare ratios measured in one
/// run, not times across runs.
pub fn best_time(mut f: impl FnMut()) -> f64 {
    let mut calls = 1usize;
    loop {
        let t = Instant::now();
        for _ in 0..calls {
            f();
        }
        if t.elapsed().as_secs_f64() >= 0.02 {
            break;
        }
        calls *= 2;
    }
    (0..5)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..calls {
                f();
            }
            t.elapsed().as_secs_f64() / calls as f64
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_call_that_sleeps_is_timed_at_least_its_sleep() {
        let t = best_time(|| std::thread::sleep(std::time::Duration::from_millis(2)));
        assert!((0.002..0.5).contains(&t), "{t}");
    }
}
