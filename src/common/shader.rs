//! `common/shader.cpp`: compile and link the two shader files into a program.
//!
//! A learner edits the `.vertexshader`/`.fragmentshader` files and runs again without recompiling, so
//! the sources are read at run time: from `--shaders DIR` if given, else from the crate's own
//! `shaders/` folder (wherever the binary is started from), else from the copies embedded at build
//! time (a binary moved to another machine still runs).

use std::path::{Path, PathBuf};

use glow::HasContext;

use crate::common::Gl;
use crate::{Error, Result};

/// `(name, text)` of every file in the crate's shaders/ folder, embedded as a fallback (the table is
/// written by build.rs).
const EMBEDDED: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// A shader's text and where it came from (named in every error).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShaderFile {
    pub path: PathBuf,
    pub source: String,
}

/// The crate's `shaders/` folder as it was at build time.
pub fn crate_shader_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders")
}

/// The file [`find_shader`] reads `name` from: in `dir` if given and it is there, else in
/// [`crate_shader_dir`]; `None` when neither has it (the embedded copy is used). The window watches
/// these files to reload a program when one is saved.
pub fn shader_path(name: &str, dir: Option<&Path>) -> Option<PathBuf> {
    dir.map(|dir| dir.join(name))
        .filter(|path| path.exists())
        .or_else(|| Some(crate_shader_dir().join(name)).filter(|path| path.is_file()))
}

/// Finds `name`: in `dir` if given and it is there, else in [`crate_shader_dir`], else embedded. A
/// `--shaders` folder thus only needs the files a learner edits.
pub fn find_shader(name: &str, dir: Option<&Path>) -> Result<ShaderFile> {
    if let Some(path) = shader_path(name, dir) {
        if dir.is_some_and(|dir| !path.starts_with(dir)) {
            log::info!("{name} is not in the --shaders folder: using the crate's own");
        }
        let source = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        return Ok(ShaderFile { path, source });
    }
    let on_disk = crate_shader_dir().join(name);
    let source = embedded_shader(name)
        .ok_or_else(|| Error::io(&on_disk, std::io::ErrorKind::NotFound.into()))?;
    log::debug!("{name}: using the copy embedded at build time");
    Ok(ShaderFile {
        path: PathBuf::from("<embedded>").join(name),
        source: source.to_string(),
    })
}

/// Every file of the crate's `shaders/` as embedded at build time: (name, text).
pub fn embedded_shaders() -> &'static [(&'static str, &'static str)] {
    EMBEDDED
}

/// The copy of the crate's `shaders/{name}` embedded at build time, if there is one.
pub fn embedded_shader(name: &str) -> Option<&'static str> {
    EMBEDDED
        .iter()
        .find(|(embedded, _)| *embedded == name)
        .map(|(_, source)| *source)
}

/// A linked program, deleted with the value.
pub struct Program {
    gl: Gl,
    pub id: glow::Program,
    /// "vertex + fragment": the files it was built from, for errors about it.
    pub files: PathBuf,
    /// Every name the two sources declare `uniform`, used or not (the compiler drops unused ones, so
    /// GL alone cannot tell a misspelt name from one the shader merely does not use).
    pub declared_uniforms: Vec<String>,
}

impl Drop for Program {
    fn drop(&mut self) {
        // SAFETY: the program was made by this context, which outlives it (shared `Gl`).
        unsafe { self.gl.delete_program(self.id) };
    }
}

impl Program {
    pub fn uniform(&self, name: &str) -> Option<glow::UniformLocation> {
        // SAFETY: a valid program of this context.
        unsafe { self.gl.get_uniform_location(self.id, name) }
    }
}

/// `LoadShaders`: compiles both stages and links them. On failure the error names the file (or
/// both, for a link error) and carries the driver's info log. The shader objects are detached and
/// deleted once linked, as the tutorial does.
pub fn load_shaders(gl: &Gl, vertex: &ShaderFile, fragment: &ShaderFile) -> Result<Program> {
    // SAFETY: plain GL calls on the current context with objects created here.
    unsafe {
        let vs = compile(gl, glow::VERTEX_SHADER, vertex)?;
        let fs = match compile(gl, glow::FRAGMENT_SHADER, fragment) {
            Ok(fs) => fs,
            Err(e) => {
                gl.delete_shader(vs);
                return Err(e);
            }
        };
        let id = gl
            .create_program()
            .map_err(|e| Error::gl("shader program", e))?;
        gl.attach_shader(id, vs);
        gl.attach_shader(id, fs);
        gl.link_program(id);
        let linked = gl.get_program_link_status(id);
        let log = gl.get_program_info_log(id);
        gl.detach_shader(id, vs);
        gl.detach_shader(id, fs);
        gl.delete_shader(vs);
        gl.delete_shader(fs);
        let files = PathBuf::from(format!(
            "{} + {}",
            vertex.path.display(),
            fragment.path.display()
        ));
        if !linked {
            gl.delete_program(id);
            return Err(Error::Shader {
                path: files,
                stage: "linking",
                log: log.trim_end().to_string(),
            });
        }
        if !log.trim().is_empty() {
            log::debug!("link log: {}", log.trim_end());
        }
        let mut declared = declared_uniforms(&vertex.source);
        declared.extend(declared_uniforms(&fragment.source));
        Ok(Program {
            gl: gl.clone(),
            id,
            files,
            declared_uniforms: declared,
        })
    }
}

/// What WebGL2 replaces `#version 330 core` with: GLSL ES 3.00, which has no default precision for
/// floats in a fragment shader and a low one for samplers (desktop GL computes both in full), then
/// `#line 2`, so that a compile error names the line of the file as it is.
pub const GLSL_ES_HEADER: &str = "#version 300 es\n\
     precision highp float;\n\
     precision highp int;\n\
     precision highp sampler2D;\n\
     #line 2";

/// A shader file of this repository (`#version 330 core`, GLSL 3.30) as WebGL2 compiles it: the
/// version line becomes [`GLSL_ES_HEADER`], the rest is unchanged (the files use nothing GLSL ES
/// 3.00 lacks). A source without that line is returned as it is, and its compile error says why.
pub fn glsl_es(source: &str) -> String {
    let (first, rest) = source.split_once('\n').unwrap_or((source, ""));
    if first.trim() != "#version 330 core" {
        return source.to_owned();
    }
    format!("{GLSL_ES_HEADER}\n{rest}")
}

unsafe fn compile(gl: &Gl, kind: u32, file: &ShaderFile) -> Result<glow::Shader> {
    let shader = gl.create_shader(kind).map_err(|e| Error::gl("shader", e))?;
    // WebGL2 compiles GLSL ES 3.00: the same files, their first line adapted.
    #[cfg(target_arch = "wasm32")]
    gl.shader_source(shader, &glsl_es(&file.source));
    #[cfg(not(target_arch = "wasm32"))]
    gl.shader_source(shader, &file.source);
    gl.compile_shader(shader);
    if gl.get_shader_compile_status(shader) {
        return Ok(shader);
    }
    let log = gl.get_shader_info_log(shader);
    gl.delete_shader(shader);
    Err(Error::Shader {
        path: file.path.clone(),
        stage: "compilation",
        log: log.trim_end().to_string(),
    })
}

/// The files of `names` that exist on disk (in `dir`, else the crate's shaders/): what a scene's
/// [`Scene::shader_files`](crate::scenes::Scene::shader_files) watches.
pub fn shader_paths<'a>(
    names: impl IntoIterator<Item = &'a str>,
    dir: Option<&Path>,
) -> Vec<PathBuf> {
    names
        .into_iter()
        .filter_map(|name| shader_path(name, dir))
        .collect()
}

/// Vertex and fragment shader of one program, found by [`find_shader`], then linked.
pub fn load_program(gl: &Gl, vertex: &str, fragment: &str, dir: Option<&Path>) -> Result<Program> {
    load_shaders(gl, &find_shader(vertex, dir)?, &find_shader(fragment, dir)?)
}

/// The names a GLSL source declares with `uniform` (`uniform vec3 A;`, `uniform float a, b[2];`,
/// with or without a `layout(...)` before it), comments left out. A plain reading of declarations,
/// not a GLSL parser: uniform blocks (`uniform Block { ... }`) are not listed (the project has none).
pub fn declared_uniforms(source: &str) -> Vec<String> {
    let mut text = String::with_capacity(source.len());
    let mut rest = source;
    // Comments out: `//` to the end of the line, `/* */` anywhere.
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix("//") {
            rest = after.find('\n').map_or("", |i| &after[i..]);
        } else if let Some(after) = rest.strip_prefix("/*") {
            rest = after.find("*/").map_or("", |i| &after[i + 2..]);
            text.push(' ');
        } else {
            let c = rest.chars().next().expect("not empty");
            text.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    let mut names = Vec::new();
    for statement in text.split(';') {
        let mut words = statement.split_whitespace().skip_while(|w| *w != "uniform");
        if words.next().is_none() {
            continue;
        }
        // After `uniform`: optional precision, the type, then the names.
        let declarators: Vec<&str> = words.collect();
        let names_from = declarators
            .iter()
            .position(|w| !matches!(*w, "lowp" | "mediump" | "highp"))
            .map_or(declarators.len(), |type_at| type_at + 1);
        let joined = declarators[names_from.min(declarators.len())..].join(" ");
        for name in joined.split(',') {
            let name = name.split(['[', '=']).next().unwrap_or("").trim();
            if !name.is_empty() && !name.contains('{') {
                names.push(name.to_string());
            }
        }
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a file of shaders/ would reach WebGL2 with its desktop version line, without float
    // precision, or with its lines renumbered (an error's line would not be the file's).
    #[test]
    fn every_shader_file_adapts_to_glsl_es() {
        for (name, source) in EMBEDDED {
            let adapted = glsl_es(source);
            assert!(adapted.starts_with("#version 300 es\n"), "{name}");
            assert!(adapted.contains("\nprecision highp float;\n"), "{name}");
            assert!(!adapted.contains("330"), "{name}");
            let (header, rest) = adapted.split_once("\n#line 2\n").expect("a #line 2");
            assert!(header.lines().count() == 4, "{name}");
            assert_eq!(rest, source.split_once('\n').unwrap().1, "{name}");
        }
        assert_eq!(glsl_es("void main() {}"), "void main() {}");
    }

    // Fails if a shader is not read from the crate's shaders/ folder when no --shaders folder has
    // it (an empty folder path, or the embedded copy, would be taken), or if the embedded copies
    // are not found by name: every file there must be embedded with its text, and nothing else.
    #[test]
    fn shaders_come_from_the_crates_folder_and_its_embedded_copies() {
        let mut names = 0;
        for entry in std::fs::read_dir(crate_shader_dir()).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_str().unwrap();
            let text = std::fs::read_to_string(&path).unwrap();
            let found = find_shader(name, None).unwrap();
            assert_eq!((&found.path, &found.source), (&path, &text), "{name}");
            assert!(found.path.is_absolute(), "{}", found.path.display());
            assert_eq!(embedded_shader(name), Some(text.as_str()), "{name}");
            names += 1;
        }
        assert_eq!(EMBEDDED.len(), names);
        assert_eq!(embedded_shader("NoSuch.fragmentshader"), None);
        let error = find_shader("NoSuch.fragmentshader", None).unwrap_err();
        assert!(
            error.to_string().contains("NoSuch.fragmentshader"),
            "{error}"
        );
    }
}
