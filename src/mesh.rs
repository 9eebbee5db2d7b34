//! The CPU half of `tutorial13.cpp`'s set-up, in its order: `loadOBJ`, `computeTangentBasis`,
//! `indexVBO_TBN`. Its options are the tutorial's experiments, so a switch re-runs only this part.
//!
//! The code that runs is the tutorial's own ports in [`crate::common`] for a mesh of the tutorial's
//! size, so that what a learner reads (and edits, for the first exercise) is what draws; their fast
//! twins in [`crate::pipeline`], which give the same results to the bit, take over above
//! [`PORTS_UP_TO_TRIANGLES`] triangles (an OBJ file above [`PORTS_UP_TO_OBJ_BYTES`]), where the
//! tutorial's quadratic search would keep a learner's model waiting (BENCHMARKS.md, "The ports or
//! their twins").

use std::path::Path;

use crate::common::objloader::{load_obj, TriangleSoup};
use crate::common::tangentspace::{compute_tangent_basis, TangentBasis, TangentOptions};
use crate::common::vboindexer::{index_vbo_tbn, IndexOptions, IndexedMesh};
use crate::pipeline::indexer::index_vbo_tbn_hashed;
use crate::pipeline::obj_parse::load_obj_threaded;
use crate::Result;

/// Every switch of the CPU pipeline.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MeshOptions {
    pub tangents: TangentOptions,
    pub indexing: IndexOptions,
    /// The code that reads and indexes: `None` chooses by size (the ports up to
    /// [`PORTS_UP_TO_TRIANGLES`], the twins above); `Some` runs that one whatever the size (the
    /// exercise check's reference is built by the twins, which a learner's edit of a port leaves as
    /// they are).
    pub code: Option<Code>,
}

/// The most triangles a soup may have for the tutorial's `indexVBO_TBN` port to index it. Its
/// search is quadratic: measured (BENCHMARKS.md), 0.015 ms at the tutorial's 64 triangles, 1.6 ms
/// at 1 024, 28 ms at 4 096, 146 ms at 10 240, against 0.25, 1.25 and 3.3 ms for the hash grid.
/// At 2 048 it costs a few milliseconds once, at load: nothing a learner waits for.
pub const PORTS_UP_TO_TRIANGLES: usize = 2048;

/// The largest OBJ file the tutorial's `loadOBJ` port reads: 128 KiB, about 2 000 triangles as
/// the tools write them (65 bytes a triangle for the benchmarks' cylinders), read in 1.5 ms by
/// tobj on one core where the parse on every core takes 0.6 ms (1 024 triangles, BENCHMARKS.md).
pub const PORTS_UP_TO_OBJ_BYTES: u64 = 128 * 1024;

/// The code that runs a step of the CPU pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Code {
    /// The tutorial's own, ported: [`load_obj`], [`index_vbo_tbn`] (src/common/).
    Ports,
    /// The same results to the bit, fast: [`load_obj_threaded`], [`index_vbo_tbn_hashed`]
    /// (src/pipeline/).
    FastTwins,
}

impl Code {
    /// Where the code is, for the log.
    pub fn place(self) -> &'static str {
        match self {
            Code::Ports => "the ports in src/common/",
            Code::FastTwins => "the fast twins in src/pipeline/",
        }
    }

    /// `choice`, or the code for `size` against `most` (the ports up to it).
    fn by_size(choice: Option<Code>, size: u64, most: u64) -> Code {
        choice.unwrap_or(if size <= most {
            Code::Ports
        } else {
            Code::FastTwins
        })
    }
}

/// Which code built a mesh: its OBJ read (`None` for a soup read another way, a learner's model)
/// and its indexing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BuiltBy {
    pub load_obj: Option<Code>,
    pub index_vbo_tbn: Code,
}

impl std::fmt::Display for BuiltBy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let index = self.index_vbo_tbn.place();
        match self.load_obj {
            Some(load) if load == self.index_vbo_tbn => {
                write!(
                    f,
                    "loadOBJ, computeTangentBasis and indexVBO_TBN ran as {index}"
                )
            }
            Some(load) => write!(
                f,
                "loadOBJ ran as {}, computeTangentBasis as the port, indexVBO_TBN as {index}",
                load.place()
            ),
            None => write!(
                f,
                "computeTangentBasis ran as the port, indexVBO_TBN as {index}"
            ),
        }
    }
}

/// `loadOBJ`: the port ([`load_obj`]) for a file up to [`PORTS_UP_TO_OBJ_BYTES`], else its twin
/// ([`load_obj_threaded`]), unless `choice` names one.
pub fn load_obj_by_size(path: &Path, choice: Option<Code>) -> Result<(TriangleSoup, Code)> {
    // A file that cannot be read is the port's to report (the twin reports it the same way).
    let bytes = std::fs::metadata(path).map_or(0, |m| m.len());
    let code = Code::by_size(choice, bytes, PORTS_UP_TO_OBJ_BYTES);
    let soup = match code {
        Code::Ports => load_obj(path)?,
        Code::FastTwins => load_obj_threaded(path)?,
    };
    Ok((soup, code))
}

/// `indexVBO_TBN`: the port ([`index_vbo_tbn`]) for a soup of up to [`PORTS_UP_TO_TRIANGLES`]
/// triangles, else its twin ([`index_vbo_tbn_hashed`]), unless `options` name one.
pub fn index_vbo_tbn_by_size(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    options: MeshOptions,
) -> (IndexedMesh, Code) {
    let triangles = soup.triangle_count() as u64;
    let code = Code::by_size(options.code, triangles, PORTS_UP_TO_TRIANGLES as u64);
    let mesh = match code {
        Code::Ports => index_vbo_tbn(soup, basis, options.indexing),
        Code::FastTwins => index_vbo_tbn_hashed(soup, basis, options.indexing),
    };
    (mesh, code)
}

/// Soup → tangents → indexed mesh.
pub fn build_mesh(soup: &TriangleSoup, options: MeshOptions) -> IndexedMesh {
    let basis = compute_tangent_basis(soup, options.tangents);
    index_vbo_tbn_by_size(soup, &basis, options).0
}
