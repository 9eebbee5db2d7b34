//! The mesh the scene draws: where its triangle soup comes from (the tutorial's file or a learner's
//! model), the CPU pipeline's switches, the tangent source, and the meshes built from them.

use std::path::PathBuf;
use std::rc::Rc;

use glam::Vec3;

use crate::common::objloader::TriangleSoup;
use crate::mesh::MeshOptions;
use crate::model::Model;
use crate::pipeline::obj_parse::load_obj;
use crate::tangents::{FileTangents, TangentSource};
use crate::Result;

use super::Cylinder;

/// `indexVBO_TBN` merges a corner into an earlier vertex within 0.01 of it (position, UV and normal,
/// in the tutorial's units): on a model much denser than the tutorial's cylinder that moves corners.
/// Says so once, with how many moved, since the model then looks coarser than it is.
pub(super) fn warn_of_merged_corners(model: &Model, mesh: &crate::common::vboindexer::IndexedMesh) {
    let moved = (0..mesh.indices.len())
        .filter(|&i| mesh.vertices[mesh.indices.get(i) as usize] != model.soup.vertices[i])
        .count();
    if moved > 0 {
        log::warn!(
            "{}: indexVBO_TBN's 0.01 tolerance moved {moved} of {} corners onto a neighbour (the \
             tutorial's indexer, on a model denser than its cylinder); F switches to MikkTSpace, \
             which merges only equal corners",
            model.path.display(),
            mesh.indices.len()
        );
    }
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
        matches!(self, SoupSource::Model(model) if crate::model::gltf::is_gltf(&model.path))
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
            SoupSource::Tutorial(path) => std::borrow::Cow::Owned(load_obj(path)?),
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
        if source == TangentSource::Derivative {
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
