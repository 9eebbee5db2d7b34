//! The fuzz harness inside `cargo test`: every saved failing input and every seed replays cleanly,
//! and a short seeded run of each target finds nothing. Long runs: `fuzz/main.rs`.

#[path = "../../fuzz/harness/mod.rs"]
mod harness;

use std::time::{Duration, Instant};

use harness::{fuzz, read_dir_files, run_case, Outcome, TARGETS};

/// Generous: debug builds, a shared machine. Slowness is the long runs' business.
const SLOW: Duration = Duration::from_secs(60);

// Fails if any input that ever failed (fuzz/regressions/<target>/) or any seed fails again.
#[test]
fn regressions_and_seeds_replay_cleanly() {
    let mut replayed = 0;
    for target in TARGETS {
        let seeds = harness::seed_dirs(target);
        for dir in seeds.into_iter().chain([harness::regressions_dir(target)]) {
            for (path, bytes) in read_dir_files(&dir) {
                if let Outcome::Failed(message) = run_case(target, &bytes, SLOW) {
                    panic!(
                        "{}: {} fails again: {message}",
                        target.name(),
                        path.display()
                    );
                }
                replayed += 1;
            }
        }
    }
    assert!(replayed > 10, "only {replayed} inputs found under fuzz/");
}

// Fails if a short seeded run of any target finds a failure (the same seed every time, so a
// failure here reproduces).
#[test]
fn short_seeded_run_finds_nothing() {
    for target in TARGETS {
        let start = Instant::now();
        // At least 20 cases whatever the clock says: on a machine busy with other builds, the
        // half second could pass before the first case and the target would go untried.
        let stats = fuzz(target, 8, SLOW, None, |s| {
            s.cases >= 1000 || (s.cases >= 20 && start.elapsed() > Duration::from_millis(500))
        });
        assert!(
            stats.cases >= 20,
            "{}: {} cases",
            target.name(),
            stats.cases
        );
        assert!(
            stats.failures.is_empty(),
            "{}: {:?}",
            target.name(),
            stats.failures
        );
    }
}

// Fails if the mutator is not deterministic for a seed (a failing run must be repeatable).
#[test]
fn mutation_is_repeatable() {
    let base = b"v 0 0 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n";
    let run = || {
        let mut rng = harness::Rng::new(42);
        (0..200)
            .map(|_| harness::mutate(harness::Target::Obj, &mut rng, base, &[]))
            .collect::<Vec<_>>()
    };
    assert_eq!(run(), run());
}
