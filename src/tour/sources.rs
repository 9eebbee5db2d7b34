//! The files the tour shows, as the binary was built from them: the Rust files by `include_str!`
//! (listed here; an item in a file not listed is an error of the excerpts' test, which names this
//! file), the shaders through the copies `build.rs` embeds for `find_shader`.

use crate::common::shader::embedded_shader;

/// `(path in the repository, text)` for each Rust file of `$path`.
macro_rules! rust_sources {
    ($($path:literal),* $(,)?) => {
        const RUST: &[(&str, &str)] = &[$(
            ($path, include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/", $path))),
        )*];
    };
}

rust_sources![
    "src/common/objloader.rs",
    "src/common/tangentspace.rs",
    "src/common/vboindexer.rs",
    "src/common/texture.rs",
    "src/common/controls.rs",
    "src/mesh.rs",
    "src/gl/buffers.rs",
    "src/debug/lines.rs",
    "src/debug/views.rs",
    "src/normalmap.rs",
    "src/combine.rs",
    "src/photometric/photo.rs",
    "src/scenes/cylinder/tutorial13.rs",
    "src/scenes/cylinder/programs.rs",
];

/// The text of `path` (`src/….rs`, or `shaders/NAME`) as the binary holds it.
pub fn text(path: &str) -> Option<&'static str> {
    match path.strip_prefix("shaders/") {
        Some(name) => embedded_shader(name),
        None => RUST.iter().find(|(p, _)| *p == path).map(|(_, text)| *text),
    }
}
