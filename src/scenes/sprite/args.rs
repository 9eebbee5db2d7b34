//! The sprite scene's command-line arguments.

use glam::Vec3;

use crate::normalmap::Green;
use crate::scenes::scene::{SceneArgs, SharedArgs};

use super::SpriteOptions;

#[derive(clap::Args, Debug, Clone)]
#[command(next_help_heading = "Scene sprite")]
pub struct SpriteArgs {
    /// The light at X,Y (0 to 1 across the window, y up as in the article) and height Z > 0
    /// [default: 0.4,0.6,0.075]; in the window the mouse takes over once it moves
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_light, allow_hyphen_values = true)]
    pub light: Option<Vec3>,

    /// Measure the light's distance in the sprite's own pixels, not in window heights (key I)
    #[arg(long)]
    pub independent_falloff: bool,
}

impl SceneArgs for SpriteArgs {
    type Options = SpriteOptions;

    fn options(&self, shared: &SharedArgs) -> SpriteOptions {
        SpriteOptions {
            light: self.light.unwrap_or(SpriteOptions::default().light),
            flip_green: shared.green == Green::Down,
            independent_falloff: self.independent_falloff,
        }
    }
}

fn parse_light(s: &str) -> std::result::Result<Vec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [x, y, z] = parts[..] else {
        return Err(format!("'{s}' is not X,Y,Z, e.g. 0.5,0.5,0.075"));
    };
    let parse = |v: &str| {
        v.parse::<f32>()
            .ok()
            .filter(|n| n.is_finite())
            .ok_or_else(|| format!("'{v}' is not a finite number"))
    };
    let light = Vec3::new(parse(x)?, parse(y)?, parse(z)?);
    if light.z <= 0.0 {
        return Err(format!(
            "Z = {} must be above 0 (the light's height over the sprite)",
            light.z
        ));
    }
    Ok(light)
}
