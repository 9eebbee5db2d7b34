//! The capture's lights as given: a direction and a brightness per photo, from the command line's
//! flags or from a capture's text files.

use std::path::Path;

use glam::Vec3;

use crate::{Error, Result};

/// One `--light X,Y,Z`: three finite numbers, not all zero (any length: only the direction counts).
pub fn parse_light(text: &str) -> Result<Vec3> {
    direction(text.split(',')).map_err(|not| {
        let why = match not {
            NotALight::Numbers => "not three numbers X,Y,Z (e.g. --light -1,0,1)",
            NotALight::Direction => "not a direction (all zero, or not finite)",
        };
        Error::Photometric(format!("--light {text}: {why}"))
    })
}

/// Why a light's text is not a direction.
enum NotALight {
    Numbers,
    Direction,
}

/// Three finite numbers, not all zero, as a direction.
fn direction<'a>(numbers: impl Iterator<Item = &'a str>) -> std::result::Result<Vec3, NotALight> {
    let numbers: Vec<f32> = numbers
        .map(|n| n.trim().parse::<f32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| NotALight::Numbers)?;
    let [x, y, z] = numbers[..] else {
        return Err(NotALight::Numbers);
    };
    let light = Vec3::new(x, y, z);
    if !light.is_finite() || light == Vec3::ZERO {
        return Err(NotALight::Direction);
    }
    Ok(light)
}

/// One `--intensity R,G,B` (or one value for all three): finite numbers above zero.
pub fn parse_intensity(text: &str) -> Result<[f32; 3]> {
    intensity(text.split(','))
        .map_err(|why| Error::Photometric(format!("--intensity {text}: {why}")))
}

/// Three numbers, or one for all three, each finite and above zero; else why not.
fn intensity<'a>(numbers: impl Iterator<Item = &'a str>) -> std::result::Result<[f32; 3], String> {
    let numbers: Vec<f32> = numbers
        .map(|n| n.trim().parse::<f32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| "not three numbers R G B (or one for all three)".to_string())?;
    let rgb = match numbers[..] {
        [v] => [v; 3],
        [r, g, b] => [r, g, b],
        _ => return Err("not three numbers R G B (or one for all three)".into()),
    };
    if rgb.iter().any(|c| !c.is_finite() || *c <= 0.0) {
        return Err("each brightness must be a finite number above zero".into());
    }
    Ok(rgb)
}

/// The lines of a capture's text file that hold values: blank lines and `#` comments left out,
/// with their line numbers (from 1).
fn value_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, line)| (i + 1, line.split('#').next().unwrap_or("").trim()))
        .filter(|(_, line)| !line.is_empty())
}

/// A light-directions file (`--lights`): one `x y z` per photo and line, in the photos' order.
pub fn parse_lights_file(text: &str, path: &Path) -> Result<Vec<Vec3>> {
    value_lines(text)
        .map(|(n, line)| {
            direction(line.split_whitespace()).map_err(|not| {
                let why = match not {
                    NotALight::Numbers => "not three numbers x y z",
                    NotALight::Direction => "not a direction (all zero, or not finite)",
                };
                Error::Photometric(format!("{}: line {n}: {why}", path.display()))
            })
        })
        .collect()
}

/// A light-intensities file (`--intensities`): one `r g b` (or one value) per photo and line.
pub fn parse_intensities_file(text: &str, path: &Path) -> Result<Vec<[f32; 3]>> {
    value_lines(text)
        .map(|(n, line)| {
            intensity(line.split_whitespace())
                .map_err(|why| Error::Photometric(format!("{}: line {n}: {why}", path.display())))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if the capture files' parsers do not skip blank lines and comments, take one value as
    // all three channels, or do not name the file and line of a bad value.
    #[test]
    fn capture_files_parse_as_sets_ship_them() {
        let path = Path::new("l.txt");
        let lights = parse_lights_file("# x y z\n\n0 0 1\n1 0 1 # right\n", path).unwrap();
        assert_eq!(lights, [Vec3::Z, Vec3::new(1.0, 0.0, 1.0)]);
        let rgb = parse_intensities_file("0.5 1 2\n\n3\n", path).unwrap();
        assert_eq!(rgb, [[0.5, 1.0, 2.0], [3.0; 3]]);
        let error = parse_intensities_file("1\n1 nan 1\n", path).unwrap_err();
        assert!(error.to_string().starts_with("l.txt: line 2: "), "{error}");
        let error = parse_lights_file("0 0 0\n", path).unwrap_err();
        assert!(
            error
                .to_string()
                .starts_with("l.txt: line 1: not a direction"),
            "{error}"
        );
    }
}
