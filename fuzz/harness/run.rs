//! Running a target: the pools, the saved failures and the totals.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::time::Duration;

use super::mutate::{mutate, Rng};
use super::{message_kind, read_dir_files, regressions_dir, run_case, seed_dirs, Outcome, Target};

/// A failing input, saved.
#[derive(Debug, Clone)]
pub struct Failure {
    pub target: Target,
    pub message: String,
    pub saved: Option<PathBuf>,
}

/// Totals of one run of one target.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    pub cases: u64,
    pub loaded: u64,
    pub rejected: u64,
    pub failures: Vec<Failure>,
}

/// A file name for `input` that is the same for the same bytes (FNV-1a, 64 bits).
pub fn input_name(input: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in input {
        h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01B3);
    }
    format!("{h:016x}")
}

/// Fuzzes `target` until `stop` says so. Failing inputs go to `save_to` when given (each distinct
/// failure message once per run, so that one bug does not fill the folder).
pub fn fuzz(
    target: Target,
    seed: u64,
    slow: Duration,
    save_to: Option<&Path>,
    mut stop: impl FnMut(&Stats) -> bool,
) -> Stats {
    let mut rng = Rng::new(seed ^ (target as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    // Two pools: inputs that load (mutated further, they reach the deeper code) and inputs
    // rejected in a new way (they explore the error paths). Three bases in four are loading ones.
    let mut loading: Vec<Vec<u8>> = Vec::new();
    let mut rejected: Vec<Vec<u8>> = vec![Vec::new()];
    let seeds = seed_dirs(target)
        .into_iter()
        .map(|dir| read_dir_files(&dir));
    for (_, bytes) in seeds
        .flatten()
        .chain(read_dir_files(&regressions_dir(target)))
    {
        match run_case(target, &bytes, slow) {
            Outcome::Loaded => loading.push(bytes),
            _ => rejected.push(bytes),
        }
    }
    let mut kinds: HashSet<String> = HashSet::new();
    let mut reported: HashSet<String> = HashSet::new();
    let mut stats = Stats::default();
    while !stop(&stats) {
        let pool = if !loading.is_empty() && rng.below(4) != 0 {
            &loading
        } else {
            &rejected
        };
        let base = rng.pick(pool).clone();
        let input = mutate(target, &mut rng, &base, pool);
        stats.cases += 1;
        match run_case(target, &input, slow) {
            Outcome::Loaded => {
                stats.loaded += 1;
                if rng.chance(4) {
                    add_to_pool(&mut loading, &mut rng, input);
                }
            }
            Outcome::Rejected(kind) => {
                stats.rejected += 1;
                if kinds.insert(kind) {
                    add_to_pool(&mut rejected, &mut rng, input);
                }
            }
            Outcome::Failed(message) => {
                let first_line: String = message
                    .lines()
                    .next()
                    .unwrap_or("")
                    .chars()
                    .take(160)
                    .collect();
                if reported.insert(message_kind(&first_line)) {
                    let saved = save_to.and_then(|dir| {
                        std::fs::create_dir_all(dir).ok()?;
                        let path = dir.join(input_name(&input));
                        std::fs::write(&path, &input).ok()?;
                        Some(path)
                    });
                    stats.failures.push(Failure {
                        target,
                        message: first_line,
                        saved,
                    });
                }
            }
        }
    }
    stats
}

fn add_to_pool(pool: &mut Vec<Vec<u8>>, rng: &mut Rng, input: Vec<u8>) {
    const POOL_MAX: usize = 1000;
    if pool.len() < POOL_MAX {
        pool.push(input);
    } else {
        let i = rng.below(pool.len());
        pool[i] = input;
    }
}
