//! tutorial13: a Rust port of opengl-tutorial.org's "Tutorial 13: Normal Mapping".
//!
//! The modules mirror the tutorial's `common/` folder so that the code can be read beside the C++:
//!
//! | tutorial file            | module          | what it does                                             |
//! |--------------------------|-----------------|----------------------------------------------------------|
//! | `common/objloader.cpp`   | [`objloader`]   | OBJ → triangle soup, V negated                           |
//! | `common/tangentspace.cpp`| [`tangentspace`]| per-triangle tangent and bitangent                       |
//! | `common/vboindexer.cpp`  | [`vboindexer`]  | merge near-identical corners, sum their tangents         |
//! | `common/texture.cpp`     | [`texture`]     | DDS (DXT1/3/5) and 24-bit BMP files                      |
//!
//! [`assets`] makes the project's own cylinder, brick textures and normal map (the tutorial's files
//! cannot be redistributed here), and [`mesh`] chains the CPU pipeline the way `tutorial13.cpp` does.

pub mod assets;
pub mod context;
pub mod controls;
pub mod debuglines;
pub mod error;
pub mod headless;
pub mod mesh;
pub mod objloader;
pub mod shader;
pub mod tangentspace;
pub mod texture;
pub mod tutorial13;
pub mod vboindexer;
pub mod window;

pub use error::{Error, Result};
