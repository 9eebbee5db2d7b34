//! One error type for the library: every variant names the file it is about, so that the binary can
//! print a single line such as `assets/normal.bmp: malformed BMP: 16 bits per pixel, only 24 is supported`.

use std::path::PathBuf;

/// Result alias used across the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The file could not be opened, read or written. The I/O error is part of the message, not a
    /// separate cause, so that printing the chain does not say it twice.
    #[error("{}: {error}", path.display())]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
    /// The OBJ text is not something the tutorial's loader could use.
    #[error("{}: malformed OBJ: {reason}", path.display())]
    Obj { path: PathBuf, reason: String },
    /// The glTF file (or a buffer or image it names) is not something this program can draw.
    #[error("{}: {reason}", path.display())]
    Gltf { path: PathBuf, reason: String },
    /// The DDS file is not a DXT1/DXT3/DXT5 texture the tutorial's loader accepts, or is cut short.
    #[error("{}: malformed DDS: {reason}", path.display())]
    Dds { path: PathBuf, reason: String },
    /// The BMP file is not a 24-bit uncompressed bitmap, or is cut short.
    #[error("{}: malformed BMP: {reason}", path.display())]
    Bmp { path: PathBuf, reason: String },
    /// A shader failed to compile or link; `log` is the driver's info log.
    #[error("{}: {stage} failed: {log}", path.display())]
    Shader {
        path: PathBuf,
        stage: &'static str,
        log: String,
    },
    /// No GL context could be made, or it lacks what the tutorial needs (GL 3.3, a profile).
    #[error("OpenGL context: {0}")]
    Context(String),
    /// The window or its display: none to open a window on, no framebuffer config, a failed swap.
    #[error("window: {0}")]
    Window(String),
    /// A GL object could not be made, or GL raised an error flag; `part` names what was being made
    /// or drawn ("offscreen target", "mesh buffers", "debug lines", "frame").
    #[error("{part}: {reason}")]
    Gl { part: &'static str, reason: String },
    /// A mesh the GL side refuses: arrays of different lengths, or indices past its vertices.
    #[error("mesh: {0}")]
    Mesh(String),
    /// An image the program reads (a height map) could not be decoded.
    #[error("{}: {reason}", path.display())]
    Image { path: PathBuf, reason: String },
    /// Photos and lights that photometric stereo cannot use (too few, a count that differs, lights
    /// nearly coplanar, a `--light` that is not a direction); the message names the option.
    #[error("{0}")]
    Photometric(String),
    /// `make-assets` would replace files that differ from the ones it makes.
    #[error(
        "{}: already there with other contents; nothing was written (pass --force to replace {})",
        list_paths(paths),
        if paths.len() == 1 { "it" } else { "them" }
    )]
    WouldOverwrite { paths: Vec<PathBuf> },
    /// A file given to the program (dropped on the window) that nothing opens.
    #[error("{}: {reason}", path.display())]
    Open { path: PathBuf, reason: String },
    /// Models a bake cannot use (LOW with no UV layout, no frame to bake for); `path` is the model.
    #[error("{}: {reason}", path.display())]
    Bake { path: PathBuf, reason: String },
    /// Writing a generated asset failed for a reason other than I/O (e.g. the encoder refused).
    #[error("{}: cannot write: {reason}", path.display())]
    Write { path: PathBuf, reason: String },
    /// A command-line value that parses but cannot be used (a folder that is not there, a strength
    /// that is not a number), found before anything is drawn or written; the message names the flag.
    #[error("{0}")]
    Argument(String),
    /// `--check-exercise N`: the learner's frame is not the reference; the message says how (not
    /// done yet, or how many pixels differ and where).
    #[error("{0}")]
    Exercise(String),
    /// The frame was drawn but its `--screenshot` could not be written; `error` says why.
    #[error("cannot save the screenshot")]
    Screenshot {
        #[source]
        error: Box<Error>,
    },
}

impl Error {
    /// The file the error is about, if it is about one.
    pub fn path(&self) -> Option<&std::path::Path> {
        match self {
            Error::Io { path, .. }
            | Error::Obj { path, .. }
            | Error::Gltf { path, .. }
            | Error::Dds { path, .. }
            | Error::Bmp { path, .. }
            | Error::Shader { path, .. }
            | Error::Image { path, .. }
            | Error::Open { path, .. }
            | Error::Bake { path, .. }
            | Error::Write { path, .. } => Some(path),
            Error::Screenshot { error } => error.path(),
            Error::WouldOverwrite { paths } => paths.first().map(PathBuf::as_path),
            Error::Context(_)
            | Error::Window(_)
            | Error::Gl { .. }
            | Error::Mesh(_)
            | Error::Photometric(_)
            | Error::Exercise(_)
            | Error::Argument(_) => None,
        }
    }

    pub(crate) fn gl(part: &'static str, reason: impl Into<String>) -> Self {
        Error::Gl {
            part,
            reason: reason.into(),
        }
    }

    pub(crate) fn io(path: impl Into<PathBuf>, error: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            error,
        }
    }
}

fn list_paths(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    names.join(", ")
}
