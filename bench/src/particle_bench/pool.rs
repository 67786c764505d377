//! Running the benchmark's independent runs on several cores. Each run is one thread's
//! work from start to end (its timing is of one core); the runs are handed out in
//! their order, so the longest wait at the end is one run's.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// `f(0), ..., f(n - 1)` on `workers` threads (at least one), in the order of the
/// indices as far as the threads allow; the results in index order.
///
/// A panic in `f` is a bug of the benchmark, not an outcome of a run (a run's failure is
/// a record), so it is propagated when the threads are joined.
pub fn parallel_map<T: Send>(n: usize, workers: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let workers = workers.clamp(1, n.max(1));
    if workers == 1 {
        return (0..n).map(f).collect();
    }
    let next = AtomicUsize::new(0);
    let out: Mutex<Vec<Option<T>>> = Mutex::new((0..n).map(|_| None).collect());
    // The workers are joined here, not by the scope, so that a panic is raised again
    // with its own message (the scope's would only say that a thread panicked).
    let panicked = std::thread::scope(|s| {
        let workers: Vec<_> = (0..workers)
            .map(|_| {
                s.spawn(|| {
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= n {
                            break;
                        }
                        let r = f(i);
                        // The lock is held only to store a result (`f` runs outside it),
                        // so it is never poisoned by a run's panic.
                        out.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(r);
                    }
                })
            })
            .collect();
        // Every worker is joined (one left to the scope would make it panic itself).
        let mut first = None;
        for w in workers {
            if let Err(payload) = w.join() {
                first.get_or_insert(payload);
            }
        }
        first
    });
    if let Some(payload) = panicked {
        std::panic::resume_unwind(payload);
    }
    out.into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .map(|r| r.expect("every index was run: the scope joined every worker"))
        .collect()
}

/// The workers the benchmark uses unless told: one per core the system offers.
pub fn default_workers() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The value of a `--jobs N` option: a positive whole number of runs at a time.
pub fn parse_workers(value: Option<&str>) -> Result<usize, String> {
    let v = value.ok_or("--jobs needs a number of runs at a time")?;
    match v.parse::<usize>() {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(format!("--jobs {v}: not a positive whole number")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;
    use std::thread::ThreadId;

    #[test]
    fn results_come_back_in_index_order_whatever_the_workers() {
        for workers in [0, 1, 2, 3, 8, 100] {
            let v = parallel_map(37, workers, |i| {
                // Uneven work, so that the threads finish out of order.
                std::thread::sleep(std::time::Duration::from_micros(((i * 7) % 5) as u64 * 50));
                i * i
            });
            assert_eq!(v, (0..37).map(|i| i * i).collect::<Vec<_>>(), "{workers}");
        }
        assert!(parallel_map(0, 2, |i| i).is_empty());
    }

    #[test]
    fn two_workers_run_on_two_threads() {
        let ids: Mutex<HashSet<ThreadId>> = Mutex::new(HashSet::new());
        parallel_map(8, 2, |_| {
            ids.lock().unwrap().insert(std::thread::current().id());
            std::thread::sleep(std::time::Duration::from_millis(20));
        });
        assert_eq!(ids.into_inner().unwrap().len(), 2);
    }

    #[test]
    fn jobs_are_a_positive_whole_number() {
        assert_eq!(parse_workers(Some("3")), Ok(3));
        for bad in ["0", "-1", "two", "1.5", ""] {
            let e = parse_workers(Some(bad)).unwrap_err();
            assert!(e.contains("not a positive whole number"), "{bad}: {e}");
        }
        assert!(parse_workers(None).unwrap_err().contains("needs a number"));
    }

    #[test]
    #[should_panic(expected = "run 3 failed")]
    fn a_panicking_run_is_not_swallowed() {
        parallel_map(6, 2, |i| {
            if i == 3 {
                panic!("run 3 failed");
            }
            i
        });
    }
}
