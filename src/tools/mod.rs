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

/// What a `--size` counts and how it may be written: the bake's map (`N` for a square, or `WxH`) or
/// a rendered frame (`WxH` only, as the window is given).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SizeOf {
    Texels,
    Pixels,
}

/// `--size`: `WxH` (with [`SizeOf::Texels`] also `N`, an N×N map), each side 1 to
/// [`crate::normalmap::MAX_SIDE`]. An error is the line clap shows after the value.
pub fn parse_size(text: &str, of: SizeOf) -> std::result::Result<(u32, u32), String> {
    let unit = match of {
        SizeOf::Texels => "texels",
        SizeOf::Pixels => "pixels",
    };
    let max = crate::normalmap::MAX_SIDE;
    let side = |s: &str| -> std::result::Result<u32, String> {
        let n: u32 = s
            .trim()
            .parse()
            .map_err(|_| format!("'{s}' is not a whole number of {unit}"))?;
        if (1..=max).contains(&n) {
            Ok(n)
        } else {
            Err(format!("{n} {unit}: a side must be 1 to {max}"))
        }
    };
    match (text.split_once(['x', 'X']), of) {
        (Some((w, h)), _) => Ok((side(w)?, side(h)?)),
        (None, SizeOf::Texels) => side(text).map(|n| (n, n)),
        (None, SizeOf::Pixels) => Err(format!("'{text}' is not WxH, e.g. 1024x768")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a map's `N` is refused or a frame's accepted (the window's --size is WxH alone), or
    // if a side of 0 or over 16384 passes either.
    #[test]
    fn a_size_is_read_as_each_flag_takes_it() {
        assert_eq!(parse_size("512", SizeOf::Texels), Ok((512, 512)));
        assert_eq!(parse_size("512x256", SizeOf::Texels), Ok((512, 256)));
        assert_eq!(parse_size("640X480", SizeOf::Pixels), Ok((640, 480)));
        assert_eq!(
            parse_size("512", SizeOf::Pixels),
            Err("'512' is not WxH, e.g. 1024x768".to_string())
        );
        assert_eq!(
            parse_size("16385x8", SizeOf::Texels),
            Err("16385 texels: a side must be 1 to 16384".to_string())
        );
        assert_eq!(
            parse_size("0x8", SizeOf::Pixels),
            Err("0 pixels: a side must be 1 to 16384".to_string())
        );
    }
}
