//! The first frame's CPU work at the size of a learner's model: the same results as the tutorial's
//! ports in [`crate::common`], to the bit, in a fraction of the time. The program calls these for a
//! mesh above [`crate::mesh::PORTS_UP_TO_TRIANGLES`] triangles (the tutorial's cylinder runs the
//! ports, so that the code a learner reads is the code that runs); the tests compare the two.
//!
//! | module          | ports                                  | how                                  |
//! |-----------------|----------------------------------------|--------------------------------------|
//! | [`indexer`]     | `indexVBO_TBN`, `indexVBO`             | exact numbering, then a hash grid    |
//! | [`obj_parse`]   | `loadOBJ`                              | the file's lines split over the cores |
//! | [`mikktspace`]  | the `mikktspace` crate (MikkTSpace)    | hashed weld, runs of groups per core  |

pub mod indexer;
pub mod mikktspace;
pub mod obj_parse;

/// `a` on this thread and `b` on a thread of its own, both results returned (rayon's `join`, without
/// a pool); a panic on either is raised here.
pub(crate) fn join<A, B: Send>(a: impl FnOnce() -> A, b: impl FnOnce() -> B + Send) -> (A, B) {
    std::thread::scope(|scope| {
        let other = scope.spawn(b);
        let a = a();
        let b = other
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (a, b)
    })
}

/// `f` on every item, the first on this thread and each other on a thread of its own (with one
/// item no thread is started: the browser has none); a panic on any of them is raised here.
pub(crate) fn on_threads<T: Send, R: Send>(items: Vec<T>, f: impl Fn(T) -> R + Sync) -> Vec<R> {
    let f = &f;
    std::thread::scope(|scope| {
        let mut items = items.into_iter();
        let first = items.next();
        let others: Vec<_> = items.map(|item| scope.spawn(move || f(item))).collect();
        let mut results: Vec<R> = first.into_iter().map(f).collect();
        for other in others {
            results.push(
                other
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
            );
        }
        results
    })
}

/// `f` of runs of the indices below `count`, one run for each of `threads` threads (on
/// [`on_threads`]), the values of all joined in the indices' order.
pub(crate) fn in_runs<R: Send>(
    count: usize,
    threads: usize,
    f: impl Fn(std::ops::Range<usize>) -> Vec<R> + Sync,
) -> Vec<R> {
    let step = count.div_ceil(threads.clamp(1, count.max(1))).max(1);
    let runs = (0..count)
        .step_by(step)
        .map(|start| start..(start + step).min(count));
    let parts = on_threads(runs.collect(), f);
    let mut all = Vec::with_capacity(count);
    for part in parts {
        all.extend(part);
    }
    all
}

/// Arrays at least this long are shared out between the cores by [`each_on_cores`] and
/// [`runs_on_cores`]: a sculpt's millions of corners, not a learner's cube.
const CORES_FROM: usize = 1 << 16;

/// `items` cut into a run per core where it is long (one run where it is short, or where there is
/// one core, as in the browser).
fn runs_of<T>(items: &[T]) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    match items.len() >= CORES_FROM {
        true => items.len().div_ceil(cores).max(1),
        false => items.len().max(1),
    }
}

/// `f` on every element of `items`, a run per core ([`runs_of`]): the values of one pass, as each
/// element's is its own.
pub(crate) fn each_on_cores<T: Send>(items: &mut [T], f: impl Fn(&mut T) + Sync) {
    let run = runs_of(items);
    on_threads(items.chunks_mut(run).collect(), |run| {
        run.iter_mut().for_each(&f)
    });
}

/// `f` of each run of `items` ([`runs_of`]), in order.
pub(crate) fn runs_on_cores<T: Sync, R: Send>(items: &[T], f: impl Fn(&[T]) -> R + Sync) -> Vec<R> {
    on_threads(items.chunks(runs_of(items)).collect(), f)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails if [`each_on_cores`] leaves an element out or does one twice, or if the runs of
    /// [`runs_on_cores`] are not the array's, in order; and if an array long enough is not cut
    /// into a run per core.
    #[test]
    fn the_runs_on_the_cores_cover_the_array_once_in_order() {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        for len in [0, 1, CORES_FROM - 1, CORES_FROM, 3 * CORES_FROM + 7] {
            let mut values: Vec<u64> = (0..len as u64).collect();
            each_on_cores(&mut values, |v| *v = 3 * *v + 1);
            let expected: Vec<u64> = (0..len as u64).map(|v| 3 * v + 1).collect();
            assert_eq!(values, expected, "{len}");
            let runs = runs_on_cores(&values, |run| run.to_vec());
            assert_eq!(runs.concat(), values, "{len}");
            let wanted = match len {
                0 => 0,
                len if len >= CORES_FROM => cores.min(len),
                _ => 1,
            };
            assert_eq!(runs.len(), wanted, "{len}");
        }
    }
}
