//! tutorial13: a Rust port of opengl-tutorial.org's "Tutorial 13: Normal Mapping".
//!
//! The modules are layers, each using only the ones above it in this list:
//!
//! | layer               | module        | what lives there                                              |
//! |---------------------|---------------|---------------------------------------------------------------|
//! | errors and files  | [`error`], [`files`], [`progress`], [`clock`], [`statistics`] | the crate's error type; atomic file writing; a line for a long load; the clock; min and median of timings |
//! | the tutorial's `common/` | [`common`] | objloader, tangentspace, vboindexer, texture, shader, controls |
//! | the fast pipeline   | [`pipeline`]  | the OBJ parse on every core and the linear-time indexers: the `common/` ports' results, to the bit, for a learner's large model |
//! | CPU helpers         | [`mesh`], [`tangent_source`], [`normalmap`], [`photometric`], [`assets`], [`model`], [`bake`], [`combine`] | the CPU pipeline's switches, where a mesh's tangents come from, height map → normal map, photos → normal map (one photo's guess, photometric stereo), the project's own assets and OBJ text made by code, a learner's OBJ with its MTL maps, a detailed model's normals baked into a simple one's UVs, two normal maps combined |
//! | GL helpers          | [`gl`]        | the `Gl` handle, context info, error draining, mesh buffers, read-back and image files, the headless context and offscreen targets |
//! | debugging aids      | [`debug`]     | the TBN lines (immediate mode and line shader), colour views  |
//! | scenes              | [`scenes`]    | `tutorial13.rs` (`tutorial13.cpp`), the cylinder scene, the [`scenes::Scene`] seam |
//! | the tour            | [`tour`]      | the tutorial's sections as steps: each a state set through the scenes' tables, a caption, and its code drawn from the source the binary is built from, beside the C++ lines it ports |
//! | front ends          | [`frontends`] | the window, headless rendering (`--headless`, `--bench`, tests), the browser page (wasm32 only, `web/build.sh`) |
//! | commands            | [`tools`]     | what the binary runs: a scene (window or headless), `make-assets`, `normalmap`, `photometric`, `bake`; `--help`'s layout |
//!
//! `docs/reading-guide.md` maps every block of `tutorial13.cpp` and every `common/*.cpp` function to
//! the Rust that ports it.

pub mod assets;
pub mod bake;
pub mod choices;
pub mod clock;
pub mod combine;
pub mod common;
pub mod debug;
pub mod error;
pub mod files;
pub mod frontends;
pub mod gl;
pub mod mesh;
pub mod model;
pub mod normalmap;
pub mod photometric;
pub mod pipeline;
pub mod progress;
pub mod scenes;
pub mod statistics;
pub mod tangent_source;
pub mod tools;
pub mod tour;

pub use error::{Error, Result};
