//! The C++ original a step ports: opengl-tutorials/ogl's `tutorial13_normal_mapping/tutorial13.cpp`
//! and `common/*.cpp`, named by function and line range and linked to GitHub. The C++ text is not
//! this project's to copy: the tour names and links it, and shows the Rust.

/// A file of the C++ original, at the commit whose lines the tour counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CppFile {
    Tutorial13,
    TangentSpace,
    VboIndexer,
    Texture,
}

/// The repository the C++ original is in.
pub const REPOSITORY: &str = "https://github.com/opengl-tutorials/ogl";

impl CppFile {
    /// Its path in the repository.
    pub fn path(self) -> &'static str {
        match self {
            CppFile::Tutorial13 => "tutorial13_normal_mapping/tutorial13.cpp",
            CppFile::TangentSpace => "common/tangentspace.cpp",
            CppFile::VboIndexer => "common/vboindexer.cpp",
            CppFile::Texture => "common/texture.cpp",
        }
    }

    /// The commit of the file's last change, whose lines the ranges count (the file is the same at
    /// the repository's head).
    pub fn commit(self) -> &'static str {
        match self {
            CppFile::Tutorial13 | CppFile::Texture => "316cccc5f76f47f09c16089d98be284b689e057d",
            CppFile::TangentSpace => "e7e4990610b442b525dcb68d7edda18551aa3704",
            CppFile::VboIndexer => "b8974c3ad275282f878feb0e32b190f3a4877d8c",
        }
    }

    /// Its file name alone (`tutorial13.cpp`).
    pub fn name(self) -> &'static str {
        self.path().rsplit('/').next().unwrap_or(self.path())
    }
}

/// Lines of the C++ original that a step ports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cpp {
    pub file: CppFile,
    /// The function they are in (`main`, `computeTangentBasis`).
    pub function: &'static str,
    /// First and last line, counted from 1, both included.
    pub lines: (u32, u32),
    /// What these lines do, in a few words of this project's.
    pub what: &'static str,
}

impl Cpp {
    /// The lines on GitHub.
    pub fn url(&self) -> String {
        let (first, last) = self.lines;
        format!(
            "{REPOSITORY}/blob/{}/{}#L{first}-L{last}",
            self.file.commit(),
            self.file.path()
        )
    }

    /// "tutorial13.cpp, main, lines 110–115".
    pub fn label(&self) -> String {
        let (first, last) = self.lines;
        format!(
            "{}, {}, lines {first}–{last}",
            self.file.name(),
            self.function
        )
    }
}
