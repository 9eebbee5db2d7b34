//! The program's commands, each a function of plain options returning [`crate::Result`], so that
//! the binary (`src/main.rs`) only parses the command line and prints the error: [`run::run`]
//! draws a scene in the window or headless (none of the tools named), [`make_assets::make_assets`],
//! [`normalmap::normalmap`], [`photometric::photometric`] and [`bake::bake`] are the four tools, and [`help`]
//! lays `--help` out for the terminal. The options derive `clap::Args`: their doc comments are the
//! help texts.

pub mod bake;
// The browser page's bake worker runs `bake` (web/src/bake.rs); the other commands are native only.
#[cfg(not(target_arch = "wasm32"))]
pub mod help;
#[cfg(not(target_arch = "wasm32"))]
pub mod make_assets;
#[cfg(not(target_arch = "wasm32"))]
pub mod normalmap;
#[cfg(not(target_arch = "wasm32"))]
pub mod photometric;
#[cfg(not(target_arch = "wasm32"))]
pub mod run;
#[cfg(not(target_arch = "wasm32"))]
pub mod tour;

/// `--depth`: the bits per channel of a map a tool writes (16 only as PNG).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Depth {
    #[default]
    #[value(name = "8")]
    Eight,
    #[value(name = "16")]
    Sixteen,
}

impl Depth {
    pub fn sixteen_bit(self) -> bool {
        self == Depth::Sixteen
    }

    pub fn bits(self) -> u8 {
        match self {
            Depth::Eight => 8,
            Depth::Sixteen => 16,
        }
    }
}
