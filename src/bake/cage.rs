//! A cage (`--cage`): LOW with its corners moved, read from a file of its own, as Blender's
//! `cage_object` and xNormal's external cage. A texel's ray starts at the cage's point with the
//! texel's barycentrics on the same triangle and goes toward LOW's point and on past it.
//!
//! The cage's triangles are paired with LOW's by their order in the files (each reader groups its
//! soup by material, so the soups' orders may differ where the two files' materials do). What is
//! checked: the same number of triangles, and that corners which are one vertex in the cage are one
//! in LOW too (a cage from another mesh, another triangulation or another face order fails that);
//! a cage may split a vertex LOW shares (a hard edge pushed apart), which leaves a gap there.

use std::collections::HashMap;

use glam::Vec3;

use crate::model::Model;

/// The cage's corners in LOW's soup order and LOW's placed space; or why `cage` is not LOW's.
pub fn cage_corners(cage: &Model, low: &Model) -> Result<Vec<Vec3>, String> {
    let (triangles, low_triangles) = (cage.soup.triangle_count(), low.soup.triangle_count());
    if triangles != low_triangles {
        return Err(format!(
            "{triangles} triangles where LOW ({}) has {low_triangles}: a cage is LOW with its \
             corners moved, the same faces in the same order",
            low.path.display()
        ));
    }
    let file_index = |model: &Model, t: usize| match model.file_order.is_empty() {
        true => t,
        false => model.file_order[t] as usize,
    };
    // The cage's soup triangle for each of the file's triangles.
    let mut cage_of_file = vec![0usize; triangles];
    for t in 0..triangles {
        cage_of_file[file_index(cage, t)] = t;
    }
    let mut corners = Vec::with_capacity(3 * triangles);
    // Each cage vertex's first corner (LOW's soup order), by the vertex's bits.
    let mut first_at: HashMap<[u32; 3], usize> = HashMap::new();
    for t in 0..low_triangles {
        let c = cage_of_file[file_index(low, t)];
        for k in 0..3 {
            let read = cage.soup.vertices[3 * c + k];
            let placed = low.placement.to_world(cage.placement.to_file(read));
            if !placed.is_finite() {
                return Err(format!(
                    "a corner at {read} lies beyond what 32-bit floats hold at LOW's scale \
                     (LOW's bounding radius {})",
                    low.placement.radius
                ));
            }
            let corner = 3 * t + k;
            let first = *first_at.entry(point_key(read)).or_insert(corner);
            if low.soup.vertices[first] != low.soup.vertices[corner] {
                let (ours, theirs) = (file_index(low, t), file_index(low, first / 3));
                let counts = (
                    vertex_count(&cage.soup.vertices),
                    vertex_count(&low.soup.vertices),
                );
                let why = match counts {
                    (cage, low) if cage != low => {
                        format!("the cage has {cage} vertices where LOW has {low}")
                    }
                    _ => "LOW's faces cut or ordered otherwise".to_string(),
                };
                return Err(format!(
                    "its triangles {} and {} (in the file's order, fanned from each face's \
                     first corner) share a vertex that LOW's do not ({why}); a cage is LOW with \
                     its corners moved, the same faces in the same order",
                    theirs + 1,
                    ours + 1,
                ));
            }
            corners.push(placed);
        }
    }
    Ok(corners)
}

/// The distinct points among `corners`.
pub fn vertex_count(corners: &[Vec3]) -> usize {
    let mut seen = std::collections::HashSet::new();
    corners
        .iter()
        .filter(|p| seen.insert(point_key(**p)))
        .count()
}

/// A point's bits, -0 taken as 0: corners at one point have one key.
fn point_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}
