//! A work queue on local threads for a study's runs: `jobs` threads take the next run from the queue
//! as they become free, and the results are handed on in the queue's order, as a serial loop would
//! hand them on (so the printed lines and the table do not depend on which run finished first).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;

/// The number of runs at once when none is asked for: the cores this process may use.
pub fn default_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// Runs `work(0)`, `work(1)`, … `work(count − 1)` on up to `jobs` threads and calls `done` with each
/// result in the order of the indices. At the first error in that order no further work is started,
/// the work already started is finished (and dropped), and the error is returned: what a serial loop
/// with `?` returns, having handed on the same results before it. `jobs` = 1 is that loop.
pub fn run_in_order<T: Send, E: Send>(
    count: usize,
    jobs: usize,
    work: impl Fn(usize) -> Result<T, E> + Sync,
    mut done: impl FnMut(T),
) -> Result<(), E> {
    let jobs = jobs.clamp(1, count.max(1));
    if jobs == 1 {
        for index in 0..count {
            done(work(index)?);
        }
        return Ok(());
    }
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let (sender, receiver) = mpsc::channel::<(usize, Result<T, E>)>();
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            let sender = sender.clone();
            let (next, stop, work) = (&next, &stop, &work);
            scope.spawn(move || {
                while !stop.load(Ordering::Relaxed) {
                    let index = next.fetch_add(1, Ordering::Relaxed);
                    if index >= count {
                        break;
                    }
                    let result = work(index);
                    // An error ends the queue: the runs after it in the order are never handed on.
                    if result.is_err() {
                        stop.store(true, Ordering::Relaxed);
                    }
                    if sender.send((index, result)).is_err() {
                        break;
                    }
                }
            });
        }
        drop(sender);
        // Results that arrive ahead of their turn wait here until the ones before them are in.
        let mut waiting: Vec<Option<Result<T, E>>> = (0..count).map(|_| None).collect();
        let mut turn = 0;
        for (index, result) in receiver {
            waiting[index] = Some(result);
            while let Some(result) = waiting.get_mut(turn).and_then(Option::take) {
                turn += 1;
                match result {
                    Ok(value) => done(value),
                    Err(e) => {
                        stop.store(true, Ordering::Relaxed);
                        return Err(e);
                    }
                }
            }
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn results_are_handed_on_in_order_whatever_finishes_first() {
        // The early indices take longest, so they finish last.
        let mut seen = Vec::new();
        let result: Result<(), ()> = run_in_order(
            8,
            3,
            |i| {
                std::thread::sleep(Duration::from_millis(5 * (8 - i as u64)));
                Ok(i * i)
            },
            |v| seen.push(v),
        );
        assert_eq!(result, Ok(()));
        assert_eq!(seen, (0..8).map(|i| i * i).collect::<Vec<_>>());
    }

    #[test]
    fn the_first_error_in_order_is_returned_after_the_results_before_it() {
        for jobs in [1, 2, 4] {
            let mut seen = Vec::new();
            let result = run_in_order(10, jobs, |i| if i == 3 || i == 6 { Err(i) } else { Ok(i) }, |v| seen.push(v));
            assert_eq!(result, Err(3), "jobs {jobs}");
            assert_eq!(seen, vec![0, 1, 2], "jobs {jobs}");
        }
    }
}
