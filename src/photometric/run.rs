//! `tutorial13 photometric`: the command line's job checked before any photo is read, then solved
//! and written.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::capture::{parse_intensities_file, parse_intensity, parse_light, parse_lights_file};
use super::lights::unit_lights;
use super::load::{load_mask, load_photos};
use super::{recover_calibrated, Calibration, PhotometricOptions, Recovered, Solver};
use crate::normalmap::{check_map_output, write_normal_map, write_normal_map16, Green};
use crate::photometric::photo::Encoding;
use crate::{Error, Result};

/// `tutorial13 photometric`, as the command line gives it.
#[derive(Debug, Clone)]
pub struct Job<'a> {
    pub photos: &'a [PathBuf],
    /// The `--light` texts, one per photo (or none, with `lights_file`).
    pub lights: &'a [String],
    /// `--lights FILE`: one `x y z` per photo and line.
    pub lights_file: Option<&'a Path>,
    /// The `--intensity` texts, one per photo (or none).
    pub intensities: &'a [String],
    /// `--intensities FILE`: one `r g b` per photo and line.
    pub intensities_file: Option<&'a Path>,
    /// `--mask FILE`: nonzero inside.
    pub mask: Option<&'a Path>,
    pub output: &'a Path,
    pub albedo: Option<&'a Path>,
    pub solver: Option<Solver>,
    /// Write the normal map with 16 bits per channel (PNG).
    pub sixteen_bit: bool,
    pub encoding: Encoding,
    pub green: Green,
    pub shadow: f32,
}

/// Reads a capture's text file as UTF-8; errors name it.
fn read_text(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    String::from_utf8(bytes)
        .map_err(|_| Error::Photometric(format!("{}: not UTF-8 text", path.display())))
}

/// `values`, one per photo, checked against the photo count; `source` names where they came from
/// and `what` they are.
fn one_per_photo<T>(values: Vec<T>, photos: usize, source: &str, what: &str) -> Result<Vec<T>> {
    if values.len() != photos {
        return Err(Error::Photometric(format!(
            "{source}: {} {what} for {photos} photos: give one per photo, in the photos' order",
            values.len()
        )));
    }
    Ok(values)
}

/// Checks everything that can be checked before reading a photo (counts, lights, intensities,
/// `--shadow`, the outputs' names and folders), reads the photos and the mask and solves on every
/// core, then writes the normal map and the albedo. On any error nothing is written (a normal map
/// already written is removed if the albedo then cannot be).
pub fn run(job: &Job) -> Result<Recovered> {
    let count = job.photos.len();
    let lights = job_lights(job, count)?;
    unit_lights(&lights, count)?;
    let intensities = job_intensities(job, count)?;
    check_shadow_and_outputs(job)?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let photos = load_photos(job.photos, threads)?;
    let mask = job
        .mask
        .map(|path| load_mask(path, &photos[0], &job.photos[0]))
        .transpose()?;
    let options = PhotometricOptions {
        solver: job.solver,
        sixteen_bit: job.sixteen_bit,
        encoding: job.encoding,
        green: job.green,
        shadow: job.shadow,
        albedo: job.albedo.is_some(),
        threads,
    };
    let calibration = Calibration { intensities, mask };
    let recovered = recover_calibrated(&photos, &lights, &calibration, &options)?;
    let (w, h) = (recovered.width, recovered.height);
    match &recovered.normals16 {
        Some(normals) => write_normal_map16(job.output, normals, w, h)?,
        None => write_normal_map(job.output, &recovered.normals, w, h)?,
    }
    if let (Some(path), Some(albedo)) = (job.albedo, &recovered.albedo) {
        if let Err(e) = write_normal_map(path, albedo, w, h) {
            let _ = std::fs::remove_file(job.output);
            return Err(e);
        }
    }
    Ok(recovered)
}

/// The job's light directions, from `--lights FILE` or the `--light` flags, one per photo.
fn job_lights(job: &Job, count: usize) -> Result<Vec<Vec3>> {
    let lights = match job.lights_file {
        Some(path) => one_per_photo(
            parse_lights_file(&read_text(path)?, path)?,
            count,
            &path.display().to_string(),
            "directions",
        )?,
        None => job
            .lights
            .iter()
            .map(|l| parse_light(l))
            .collect::<Result<Vec<_>>>()?,
    };
    Ok(lights)
}

/// The job's light brightnesses, from `--intensities FILE` or the `--intensity` flags, one per
/// photo (`None` without either).
fn job_intensities(job: &Job, count: usize) -> Result<Option<Vec<[f32; 3]>>> {
    let intensities = match job.intensities_file {
        Some(path) => Some(one_per_photo(
            parse_intensities_file(&read_text(path)?, path)?,
            count,
            &path.display().to_string(),
            "intensities",
        )?),
        None if job.intensities.is_empty() => None,
        None => Some(one_per_photo(
            job.intensities
                .iter()
                .map(|i| parse_intensity(i))
                .collect::<Result<Vec<_>>>()?,
            count,
            "--intensity",
            "brightnesses",
        )?),
    };
    Ok(intensities)
}

/// Checks `--shadow`, and the outputs: formats known, folders there, 16 bits only in a PNG, not
/// one file named twice.
fn check_shadow_and_outputs(job: &Job) -> Result<()> {
    if !(0.0..1.0).contains(&job.shadow) {
        return Err(Error::Photometric(format!(
            "--shadow {}: must be a linear luminance from 0 to below 1",
            job.shadow
        )));
    }
    check_map_output("-o", job.output, job.sixteen_bit)?;
    if let Some(albedo) = job.albedo {
        // The albedo is written at 8 bits whatever --depth says.
        check_map_output("--albedo", albedo, false)?;
    }
    if job.albedo == Some(job.output) {
        return Err(Error::Photometric(format!(
            "-o and --albedo name the same file, {}",
            job.output.display()
        )));
    }
    Ok(())
}
