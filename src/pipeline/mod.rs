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
