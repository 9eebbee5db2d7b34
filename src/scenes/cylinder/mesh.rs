//! The mesh the scene draws: where its triangle soup comes from (the tutorial's file or a learner's
//! model), the CPU pipeline's switches, the tangent source, and the meshes built from them.

use std::path::PathBuf;
use std::rc::Rc;

use glam::Vec3;

use crate::common::objloader::TriangleSoup;
use crate::mesh::MeshOptions;
use crate::model::Model;
use crate::tangent_source::{FileTangents, TangentSource};
use crate::Result;

use super::Cylinder;

/// `indexVBO_TBN` merges a corner into an earlier vertex within 0.01 of it (position, UV and normal,
/// in the tutorial's units): on a model much denser than the tutorial's cylinder that moves corners.
/// Says so once, with how many moved, since the model then looks coarser than it is.
pub(super) fn say_merged_corners(model: &Model, mesh: &crate::common::vboindexer::IndexedMesh) {
    let moved = (0..mesh.indices.len())
        .filter(|&i| mesh.vertices[mesh.indices.get(i) as usize] != model.soup.vertices[i])
        .count();
    if moved > 0 {
        log::info!(
            "{}: indexVBO_TBN's 0.01 tolerance moved {moved} of {} corners onto a neighbour (the \
             tutorial's indexer, on a model denser than its cylinder); F switches to MikkTSpace, \
             which merges only equal corners",
            model.path.display(),
            mesh.indices.len()
        );
    }
}

/// Above this many triangles the comparison with MikkTSpace is left out of loading (its tangents
/// would add a noticeable part of a large model's first frame); the skew is still measured.
const COMPARE_UP_TO: usize = 300_000;

/// How far the tutorial's frame on a learner's model is from MikkTSpace's, which most maps are baked
/// for: the median and largest angle between their tangents, and the median stretch of the
/// tutorial's T, B, N (σmax/σmin of the matrix; 1 for a frame at right angles with equal lengths).
/// One warning when they are far apart, naming the keys that change frame. With the article's
/// normalized TBN (`normalized`) the shader undoes the stretch, so only the angle counts.
pub(super) fn warn_of_far_frame(
    model: &Model,
    mesh: &crate::common::vboindexer::IndexedMesh,
    normalized: bool,
) {
    let corners = mesh.indices.len();
    if corners == 0 {
        return;
    }
    let mut stretches: Vec<f32> = (0..corners)
        .step_by((corners / 4096).max(1))
        .map(|i| {
            let v = mesh.indices.get(i) as usize;
            crate::tangent_source::frame_stretch(
                mesh.tangents[v],
                mesh.bitangents[v],
                mesh.normals[v],
            ) as f32
        })
        .collect();
    stretches.sort_unstable_by(f32::total_cmp);
    let stretch = if normalized {
        1.0
    } else {
        stretches[stretches.len() / 2]
    };
    let mikktspace = (model.soup.triangle_count() <= COMPARE_UP_TO)
        .then(|| crate::tangent_source::mikktspace_tangents(&model.soup).ok())
        .flatten();
    let angles = mikktspace.map(|tangents| {
        let mut angles: Vec<f32> = (0..corners)
            .map(|i| {
                let t = mesh.tangents[mesh.indices.get(i) as usize];
                let m = Vec3::from_slice(&tangents[i][..3]);
                t.angle_between(m).to_degrees()
            })
            .filter(|a| a.is_finite())
            .collect();
        angles.sort_unstable_by(f32::total_cmp);
        let median = angles.get(angles.len() / 2).copied().unwrap_or(0.0);
        (median, angles.last().copied().unwrap_or(0.0))
    });
    let far_angle = angles.is_some_and(|(median, _)| median > 10.0);
    if stretch < 1.5 && !far_angle {
        return;
    }
    let mut reasons = Vec::new();
    if let Some((median, max)) = angles.filter(|_| far_angle) {
        let mirrored = if max > 90.0 {
            "; mirrored UVs turn its T round"
        } else {
            ""
        };
        reasons.push(format!(
            "its tangents point a median {median:.0}° from MikkTSpace's (at most {max:.0}°{mirrored})"
        ));
    }
    if stretch >= 1.5 {
        reasons.push(format!(
            "its T, B and N are stretched {stretch:.1}× (median), which skews the light whatever \
             the map holds"
        ));
    }
    log::warn!(
        "{}: drawn with the tutorial's frame, far from MikkTSpace's, the frame most normal maps are \
         baked for: {}. F steps to MikkTSpace; T normalizes the tutorial's TBN \
         (docs/tangent-space-sync.md)",
        model.path.display(),
        reasons.join(", and "),
    );
}

/// The mesh the scene draws: the tutorial's `cylinder.obj` (read again by `loadOBJ` whenever the
/// pipeline re-runs, as an edit of the tutorial would), or a learner's model, read once.
pub(super) enum SoupSource {
    Tutorial(PathBuf),
    Model(Rc<Model>),
}

impl SoupSource {
    /// A point of the space `--light` uses (the model's own coordinates, or the tutorial's world
    /// space) where the program draws it.
    pub(super) fn to_world(&self, p: Vec3) -> Vec3 {
        match self {
            SoupSource::Model(model) => model.placement.to_world(p),
            SoupSource::Tutorial(_) => p,
        }
    }

    /// A glTF model's own tangents, if some of its primitives supply them.
    pub(super) fn file_tangents(&self) -> Option<&FileTangents> {
        match self {
            SoupSource::Model(model) => model.file_tangents.as_ref(),
            SoupSource::Tutorial(_) => None,
        }
    }

    /// Whether the `file` tangent source applies: a glTF model (its file can supply tangents).
    pub(super) fn is_gltf(&self) -> bool {
        matches!(self, SoupSource::Model(model) if crate::model::Format::is_gltf(&model.path))
    }

    /// The tangent sources key F steps through: `file` only for a glTF model.
    pub(super) fn tangent_sources(&self) -> Vec<TangentSource> {
        let mut all = <TangentSource as clap::ValueEnum>::value_variants().to_vec();
        if !self.is_gltf() {
            all.retain(|&s| s != TangentSource::File);
        }
        all
    }

    /// The mesh `source` draws with `options`.
    pub(super) fn mesh(
        &self,
        source: TangentSource,
        options: MeshOptions,
    ) -> Result<crate::common::vboindexer::IndexedMesh> {
        source.mesh_with(&*self.soup()?, self.file_tangents(), options)
    }

    pub(super) fn soup(&self) -> Result<std::borrow::Cow<'_, TriangleSoup>> {
        Ok(match self {
            SoupSource::Tutorial(path) => {
                std::borrow::Cow::Owned(crate::mesh::load_obj_by_size(path, None)?.0)
            }
            SoupSource::Model(model) => std::borrow::Cow::Borrowed(&model.soup),
        })
    }
}

/// What the scene's mesh is made from, in one place (the mesh itself, built and uploaded, is the
/// tutorial's: `Tutorial13::mesh`).
pub(super) struct MeshState {
    /// Where the CPU pipeline's soup comes from when a switch re-runs it.
    pub(super) soup: SoupSource,
    /// The CPU pipeline's switches.
    pub(super) options: MeshOptions,
    /// Where the tangent frame comes from.
    pub(super) source: TangentSource,
    /// The tangent source of every mesh the CPU pipeline built since the scene was loaded.
    pub(super) built: Vec<TangentSource>,
}

impl Cylinder {
    /// Where the tangent frame comes from.
    pub fn tangent_source(&self) -> TangentSource {
        self.mesh.source
    }

    /// The CPU pipeline's current switches.
    pub fn mesh_options(&self) -> MeshOptions {
        self.mesh.options
    }

    /// The tangent source of every mesh the CPU pipeline built since the scene was loaded (the
    /// first one aside), in order.
    pub fn meshes_built(&self) -> &[TangentSource] {
        &self.mesh.built
    }

    /// Draws with another tangent source: the mesh is rebuilt (with the tutorial's tangents,
    /// MikkTSpace's, or none for the per-pixel frame) and the lines with it.
    pub fn set_tangent_source(&mut self, source: TangentSource) -> Result<()> {
        if source == self.mesh.source {
            return Ok(());
        }
        self.rebuild_mesh(source, self.mesh.options)?;
        self.mesh.source = source;
        // Lines shown with the per-pixel frame were dropped: built again from the new mesh.
        if self.show_lines && self.lines.built().is_none() {
            self.set_show_lines(true)?;
        }
        Ok(())
    }

    /// Runs the CPU pipeline of `source` with `options` and uploads the result; lines already built
    /// follow (the per-pixel frame has no vertex tangents to show, so they are dropped; the caller
    /// builds them again for another source). The tangent source is the caller's to set.
    pub(super) fn rebuild_mesh(
        &mut self,
        source: TangentSource,
        options: MeshOptions,
    ) -> Result<()> {
        self.mesh.built.push(source);
        match (&self.mesh.soup, source) {
            (SoupSource::Tutorial(path), TangentSource::Tutorial) => {
                self.tutorial.reload_mesh(path, options)?
            }
            (soup_source, _) => self.tutorial.set_mesh(soup_source.mesh(source, options)?)?,
        }
        if !source.has_vertex_tangents() {
            self.lines.drop_built();
        } else if let Some(lines) = self.lines.built_mut() {
            lines.rebuild(&self.tutorial.mesh)?;
        }
        Ok(())
    }

    /// Runs the CPU pipeline again with `mesh` (the compare view's meshes too), if it changed.
    pub fn set_mesh_options(&mut self, mesh: MeshOptions) -> Result<()> {
        if mesh != self.mesh.options {
            self.rebuild_mesh(self.mesh.source, mesh)?;
            self.mesh.options = mesh;
            if let Some((sources, _)) = self.comparison {
                self.start_comparison(sources)?;
            }
        }
        Ok(())
    }
}
