//! The CPU half of `tutorial13.cpp`'s set-up, in its order: `loadOBJ`, `computeTangentBasis`,
//! `indexVBO_TBN`. Its options are the tutorial's experiments, so a switch re-runs only this part.

use crate::common::objloader::TriangleSoup;
use crate::common::tangentspace::{compute_tangent_basis, TangentOptions};
use crate::common::vboindexer::{IndexOptions, IndexedMesh};
use crate::pipeline::indexer::index_vbo_tbn_hashed;

/// Every switch of the CPU pipeline.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MeshOptions {
    pub tangents: TangentOptions,
    pub indexing: IndexOptions,
}

/// Soup → tangents → indexed mesh.
pub fn build_mesh(soup: &TriangleSoup, options: MeshOptions) -> IndexedMesh {
    let basis = compute_tangent_basis(soup, options.tangents);
    index_vbo_tbn_hashed(soup, &basis, options.indexing)
}
