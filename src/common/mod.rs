//! The tutorial's `common/` folder, one module per file, named after it; functions keep the C++
//! names in snake_case. Nothing here knows of windows or scenes.
//! The tutorial's cylinder is read and indexed by these ports, so that the code a learner reads is
//! the code that runs; a mesh above [`crate::mesh::PORTS_UP_TO_TRIANGLES`] triangles goes through
//! [`crate::pipeline`], which gives what `objloader` and `vboindexer` give, to the bit, in a
//! fraction of the time, and the tests compare the two.
//!
//! | tutorial file             | module           | what it does                                  |
//! |---------------------------|------------------|-----------------------------------------------|
//! | `common/objloader.cpp`    | [`objloader`]    | OBJ → triangle soup, V negated                |
//! | `common/tangentspace.cpp` | [`tangentspace`] | per-triangle tangent and bitangent            |
//! | `common/vboindexer.cpp`   | [`vboindexer`]   | merge near-identical corners, sum their tangents |
//! | `common/texture.cpp`      | [`texture`]      | DDS (DXT1/3/5) and 24-bit BMP files           |
//! | `common/shader.cpp`       | [`shader`]       | compile and link the two shader files         |
//! | `common/controls.cpp`     | [`controls`]     | the first-person camera's matrices            |

pub mod controls;
pub mod objloader;
pub mod shader;
pub mod tangentspace;
pub mod texture;
pub mod vboindexer;

/// The GL function table the loaders take, shared by the objects they make (textures, programs) so
/// that each deletes itself on drop. Defined at the bottom layer so the ports need nothing above
/// them; [`crate::gl::Gl`] is the same type. An `Arc` (not an `Rc`) because egui_glow's painter takes
/// one: the panel draws with the same table.
pub type Gl = std::sync::Arc<glow::Context>;
