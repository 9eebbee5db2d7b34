//! Parts matched by name (`--match-names`): LOW's and HIGH's parts ([`crate::model::parts`]) paired
//! by their names without the usual suffixes, so that a LOW part's rays meet only its HIGH part's
//! triangles and a gun's grip never takes the barrel beside it (Substance's "match by mesh name").
//!
//! A name's key is its text, case ignored, up to the first suffix (`_low` or `_lp` on LOW's side,
//! `_high` or `_hp` on HIGH's) that ends the name or is followed by something other than a letter:
//! `Barrel_low`, `barrel_LP` and `barrel_low_Cube.001` (Blender's object and mesh names) all pair
//! with `barrel_high`. A name without a suffix is its own key. The unnamed part and a name that
//! is only a suffix pair with nothing.

use glam::Vec3;

use super::bvh::{Bvh, Hit, Ray, PACKET};
use crate::common::objloader::TriangleSoup;
use crate::model::parts::PartNames;

/// The suffixes of LOW's part names.
pub const LOW_SUFFIXES: [&str; 2] = ["_low", "_lp"];
/// The suffixes of HIGH's part names.
pub const HIGH_SUFFIXES: [&str; 2] = ["_high", "_hp"];
/// A triangle in no pair.
const NO_PAIR: u32 = u32::MAX;

/// `name`'s key: lower case, up to its first suffix (see the module's note).
pub fn base_name(name: &str, suffixes: &[&str]) -> String {
    let lower = name.to_lowercase();
    for (at, _) in lower.char_indices() {
        for suffix in suffixes {
            let Some(after) = lower[at..].strip_prefix(suffix) else {
                continue;
            };
            if !after.starts_with(char::is_alphabetic) {
                return lower[..at].to_string();
            }
        }
    }
    lower
}

/// One side's part names in a pair, and their triangles.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Side {
    pub names: Vec<String>,
    pub triangles: usize,
}

/// One key's parts on both sides.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pair {
    pub key: String,
    pub low: Side,
    pub high: Side,
}

/// LOW's and HIGH's parts paired by key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pairing {
    pub pairs: Vec<Pair>,
    /// Each LOW triangle's pair (an index into `pairs`), or [`NO_PAIR`].
    low: Vec<u32>,
    /// Each HIGH triangle's pair, likewise.
    high: Vec<u32>,
    /// Part names with no partner, each with its triangles.
    pub unpaired_low: Vec<(String, usize)>,
    pub unpaired_high: Vec<(String, usize)>,
}

impl Pairing {
    /// Pairs `low`'s parts with `high`'s by key, in the order LOW names them.
    pub fn new(low: &PartNames, high: &PartNames) -> Pairing {
        let keys = |names: &PartNames, suffixes: &[&str]| -> Vec<String> {
            names.names.iter().map(|n| base_name(n, suffixes)).collect()
        };
        let (low_keys, high_keys) = (keys(low, &LOW_SUFFIXES), keys(high, &HIGH_SUFFIXES));
        let mut pairs: Vec<Pair> = Vec::new();
        for key in &low_keys {
            let paired = !key.is_empty() && high_keys.contains(key);
            if paired && !pairs.iter().any(|p| p.key == *key) {
                pairs.push(Pair {
                    key: key.clone(),
                    low: Side::default(),
                    high: Side::default(),
                });
            }
        }
        let (low_pairs, unpaired_low) = assign(low, &low_keys, &mut pairs, |p| &mut p.low);
        let (high_pairs, unpaired_high) = assign(high, &high_keys, &mut pairs, |p| &mut p.high);
        Pairing {
            pairs,
            low: low_pairs,
            high: high_pairs,
            unpaired_low,
            unpaired_high,
        }
    }
}

/// Each of `names`' triangles' pair by its name's key, each name added to its pair's `side`; and
/// the names in no pair, with their triangles.
fn assign(
    names: &PartNames,
    keys: &[String],
    pairs: &mut [Pair],
    side: fn(&mut Pair) -> &mut Side,
) -> (Vec<u32>, Vec<(String, usize)>) {
    let mut counts = vec![0usize; names.names.len()];
    names
        .of_triangle
        .iter()
        .for_each(|&n| counts[n as usize] += 1);
    let name_pairs: Vec<u32> = keys
        .iter()
        .map(|key| {
            let found = pairs.iter().position(|p| p.key == *key);
            found.map_or(NO_PAIR, |p| p as u32)
        })
        .collect();
    let mut unpaired = Vec::new();
    for (n, name) in names.names.iter().enumerate() {
        match name_pairs[n] {
            NO_PAIR => unpaired.push((name.clone(), counts[n])),
            p => {
                let side = side(&mut pairs[p as usize]);
                side.names.push(name.clone());
                side.triangles += counts[n];
            }
        }
    }
    let triangles = names
        .of_triangle
        .iter()
        .map(|&n| name_pairs[n as usize])
        .collect();
    (triangles, unpaired)
}

/// What a ray from a LOW triangle may meet: all of HIGH, or its pair's HIGH triangles.
pub(crate) enum Targets<'a> {
    Whole(Bvh),
    Pairs {
        /// Each pair's hierarchy, with the HIGH index of each of its triangles.
        pairs: Vec<(Bvh, Vec<u32>)>,
        /// Each LOW triangle's pair.
        low: &'a [u32],
    },
}

impl<'a> Targets<'a> {
    /// The hierarchies over `high`: one, or one per pair of `pairing`; each triangle keeps `data`
    /// of its HIGH index (its normals).
    pub fn build(
        high: &TriangleSoup,
        pairing: Option<&'a Pairing>,
        threads: usize,
        data: impl Fn(usize) -> [Vec3; 3] + Sync,
    ) -> Self {
        let Some(pairing) = pairing else {
            return Targets::Whole(Bvh::build_with(&high.vertices, data, threads));
        };
        let mut members = vec![Vec::new(); pairing.pairs.len()];
        for (t, &p) in pairing.high.iter().enumerate() {
            if p != NO_PAIR {
                members[p as usize].push(t as u32);
            }
        }
        let pairs = members
            .into_iter()
            .map(|triangles| {
                let mut corners: Vec<Vec3> = Vec::with_capacity(3 * triangles.len());
                for &t in &triangles {
                    corners.extend_from_slice(&high.vertices[3 * t as usize..3 * t as usize + 3]);
                }
                let bvh = Bvh::build_with(&corners, |i| data(triangles[i] as usize), threads);
                (bvh, triangles)
            })
            .collect();
        Targets::Pairs {
            pairs,
            low: &pairing.low,
        }
    }

    /// The hierarchies' nodes, for the log.
    pub fn node_count(&self) -> usize {
        match self {
            Targets::Whole(bvh) => bvh.node_count(),
            Targets::Pairs { pairs, .. } => pairs.iter().map(|(bvh, _)| bvh.node_count()).sum(),
        }
    }

    /// Whether rays from `low_triangle` have anything to meet (a LOW part without a partner has not).
    pub fn paired(&self, low_triangle: usize) -> bool {
        match self {
            Targets::Whole(_) => true,
            Targets::Pairs { low, .. } => low[low_triangle] != NO_PAIR,
        }
    }

    /// [`Bvh::first_hits`] of `rays`, each among what rays from its LOW triangle in `low_triangles`
    /// may meet; a hit's triangle is HIGH's index. The rays of one pair are traced together (a
    /// packet's rays are nearly always one part's), [`PACKET`] at a time, with nothing allocated.
    pub fn first_hits(&self, low_triangles: &[usize], rays: &[Ray], hits: &mut [Option<Hit>]) {
        let (pairs, low) = match self {
            Targets::Whole(bvh) => return bvh.first_hits(rays, hits),
            Targets::Pairs { pairs, low } => (pairs, low),
        };
        let packets = (low_triangles.chunks(PACKET))
            .zip(rays.chunks(PACKET))
            .zip(hits.chunks_mut(PACKET));
        for ((low_triangles, rays), hits) in packets {
            let mut done = [false; PACKET];
            for k in 0..rays.len() {
                if done[k] {
                    continue;
                }
                let pair = low[low_triangles[k]];
                // This pair's rays of the packet, and where each came from.
                let (mut ours, mut our_rays, mut n) = ([0usize; PACKET], [Ray::IDLE; PACKET], 0);
                for j in k..rays.len() {
                    if !done[j] && low[low_triangles[j]] == pair {
                        done[j] = true;
                        hits[j] = None;
                        (ours[n], our_rays[n]) = (j, rays[j]);
                        n += 1;
                    }
                }
                let Some((bvh, triangles)) = pairs.get(pair as usize) else {
                    continue;
                };
                let mut our_hits = [None; PACKET];
                bvh.first_hits(&our_rays[..n], &mut our_hits[..n]);
                for (&j, hit) in ours[..n].iter().zip(&our_hits[..n]) {
                    hits[j] = hit.map(|hit| Hit {
                        triangle: triangles[hit.triangle as usize],
                        ..hit
                    });
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails if a suffix is not found in any case, if one inside a word ends the key, or if the
    /// text after a suffix is kept.
    #[test]
    fn a_key_is_the_name_up_to_its_suffix() {
        let low = |n| base_name(n, &LOW_SUFFIXES);
        let high = |n| base_name(n, &HIGH_SUFFIXES);
        assert_eq!(low("Barrel_low"), "barrel");
        assert_eq!(low("barrel_LP"), "barrel");
        assert_eq!(low("Barrel_low_Cube.001"), "barrel");
        assert_eq!(low("barrel_low2"), "barrel");
        assert_eq!(low("slow_lowpoly"), "slow_lowpoly");
        assert_eq!(low("grip"), "grip");
        assert_eq!(high("GRIP_High"), "grip");
        assert_eq!(high("grip_hp.001"), "grip");
        assert_eq!(high("grip_highres"), "grip_highres");
        assert_eq!(high("_high"), "");
    }

    /// Fails if triangles are given to the wrong pair, if a key with parts on one side only is
    /// paired, or if the unnamed parts pair.
    #[test]
    fn parts_pair_by_key_and_the_rest_is_said() {
        let names = |names: &[&str], of_triangle: &[u32]| PartNames {
            names: names.iter().map(|n| n.to_string()).collect(),
            of_triangle: of_triangle.to_vec(),
        };
        let low = names(
            &["", "Grip_low", "barrel_lp", "stock_low"],
            &[1, 2, 2, 0, 3, 1],
        );
        let high = names(
            &["barrel_high", "", "grip_HP", "scope_high", "grip_high.001"],
            &[0, 0, 1, 2, 3, 4, 0],
        );
        let pairing = Pairing::new(&low, &high);
        let keys: Vec<&str> = pairing.pairs.iter().map(|p| p.key.as_str()).collect();
        assert_eq!(keys, ["grip", "barrel"]);
        assert_eq!(pairing.pairs[0].high.names, ["grip_HP", "grip_high.001"]);
        assert_eq!(pairing.pairs[0].high.triangles, 2);
        assert_eq!(pairing.low, [0, 1, 1, NO_PAIR, NO_PAIR, 0]);
        assert_eq!(pairing.high, [1, 1, NO_PAIR, 0, NO_PAIR, 0, 1]);
        assert_eq!(
            pairing.unpaired_low,
            [("".to_string(), 1), ("stock_low".to_string(), 1)]
        );
        assert_eq!(
            pairing.unpaired_high,
            [("".to_string(), 1), ("scope_high".to_string(), 1)]
        );
    }
}
