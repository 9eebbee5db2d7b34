//! Least squares by mask, up to [`MASKED_PHOTOS`](super::MASKED_PHOTOS) photos: each set of kept
//! photos' solve, computed the first time a band of rows meets it.

use glam::DVec3;
use rustc_hash::FxHashMap;

use super::lights::{light_spread_degrees, nearly_coplanar, scatter};

/// Each mask's solve, computed the first time it is met: for every photo k, the column
/// (Σ l lᵀ)⁻¹ l_k of the photos in the mask (zero for the others), or `None` for fewer than three
/// photos or lights within [`MIN_SPREAD_DEGREES`](super::MIN_SPREAD_DEGREES) of one plane.
pub(super) struct Solves<'a> {
    lights: &'a [DVec3],
    index: FxHashMap<u64, usize>,
    solves: Vec<Option<Vec<[f32; 3]>>>,
    /// Neighbouring texels mostly keep the same photos.
    last: Option<(u64, usize)>,
}

impl<'a> Solves<'a> {
    pub(super) fn new(lights: &'a [DVec3]) -> Self {
        Solves {
            lights,
            index: FxHashMap::default(),
            solves: Vec::new(),
            last: None,
        }
    }

    pub(super) fn get(&mut self, mask: u64) -> Option<&[[f32; 3]]> {
        let slot = match self.last {
            Some((last, slot)) if last == mask => slot,
            _ => {
                let slot = match self.index.get(&mask) {
                    Some(&slot) => slot,
                    None => {
                        self.solves.push(solve(self.lights, mask));
                        self.index.insert(mask, self.solves.len() - 1);
                        self.solves.len() - 1
                    }
                };
                self.last = Some((mask, slot));
                slot
            }
        };
        self.solves[slot].as_deref()
    }
}

fn solve(lights: &[DVec3], mask: u64) -> Option<Vec<[f32; 3]>> {
    let kept: Vec<DVec3> = (0..lights.len())
        .filter(|k| mask & (1 << k) != 0)
        .map(|k| lights[k])
        .collect();
    if kept.len() < 3 || nearly_coplanar(light_spread_degrees(&kept)) {
        return None;
    }
    let inverse = scatter(kept.iter()).inverse();
    let columns = (0..lights.len()).map(|k| {
        if mask & (1 << k) != 0 {
            (inverse * lights[k]).as_vec3().to_array()
        } else {
            [0.0; 3]
        }
    });
    Some(columns.collect())
}
