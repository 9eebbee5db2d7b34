//! The point light a scene's panel moves: [`PointLight`] (its position in the space `--light` uses,
//! its power), the sliders it gives a scene's table ([`light_slider`], [`power_slider`], which
//! `--light` and `--light-power` start), and [`WorldLight`] for a scene whose light is one [`Light`]
//! in world space.

use super::flags::{given, read_slider, Shared, Start};
use super::starts::{Handle, Setting};
use super::table::Control;
use crate::Result;

/// A scene with a point light that the panel moves: its position (in the space `--light` uses) and
/// its power.
pub trait PointLight {
    /// The light's position and power now.
    fn light(&self) -> (glam::Vec3, f32);
    /// Those the scene started with.
    fn light_start(&self) -> (glam::Vec3, f32);
    /// Moves the light and sets its power.
    fn set_light(&mut self, position: glam::Vec3, power: f32) -> Result<()>;
    /// The box the position's sliders move it in (lowest and highest corner): [`LIGHT_RANGE`]
    /// unless the scene says otherwise.
    fn light_range(&self) -> (glam::Vec3, glam::Vec3) {
        LIGHT_RANGE
    }
    /// The power slider's highest value.
    const POWER_MAX: f32;
}

/// The box a light's sliders move it in unless its scene says otherwise: 10 either way of the
/// origin, room around every scene's object (the tutorial's light is 4 away).
pub const LIGHT_RANGE: (glam::Vec3, glam::Vec3) =
    (glam::Vec3::splat(-10.0), glam::Vec3::splat(10.0));

/// A point light in world space as a scene's shader takes it (`LightPosition_worldspace` and a
/// power), so that a scene holds its light as one value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    pub position_worldspace: glam::Vec3,
    /// The light's power or intensity, as the scene's shader reads it.
    pub power: f32,
}

/// A scene whose point light is one [`Light`] field that the panel sets as it is (world space,
/// [`LIGHT_RANGE`]): it says where the light starts and how strong it may get, and has
/// [`PointLight`], and so the light's sliders, without writing its methods.
pub trait WorldLight {
    /// The light without `--light` or `--light-power`, where the panel's reset puts it back.
    const LIGHT_START: Light;
    /// The power slider's highest value ([`PointLight::POWER_MAX`]).
    const LIGHT_POWER_MAX: f32;
    /// The scene's light.
    fn world_light(&self) -> &Light;
    fn world_light_mut(&mut self) -> &mut Light;
}

impl<S: WorldLight> PointLight for S {
    const POWER_MAX: f32 = S::LIGHT_POWER_MAX;

    fn light(&self) -> (glam::Vec3, f32) {
        let light = self.world_light();
        (light.position_worldspace, light.power)
    }
    fn light_start(&self) -> (glam::Vec3, f32) {
        (S::LIGHT_START.position_worldspace, S::LIGHT_START.power)
    }
    fn set_light(&mut self, position: glam::Vec3, power: f32) -> Result<()> {
        *self.world_light_mut() = Light {
            position_worldspace: position,
            power,
        };
        Ok(())
    }
}

/// The labels of the light's three sliders ([`light_slider`]).
pub const LIGHT_AXES: [&str; 3] = ["light x", "light y", "light z"];

/// The label of the light's power slider ([`power_slider`]).
pub const LIGHT_POWER: &str = "light power";

/// The slider of the light's axis `AXIS` (0, 1, 2: x, y, z), within [`PointLight::light_range`],
/// started by that coordinate of `--light`.
pub const fn light_slider<S: PointLight + 'static, const AXIS: usize>() -> Control<S> {
    fn range<S: PointLight, const AXIS: usize>(scene: &S) -> (f32, f32) {
        let (lo, hi) = scene.light_range();
        (lo[AXIS], hi[AXIS])
    }
    fn get<S: PointLight, const AXIS: usize>(scene: &S) -> f32 {
        scene.light().0[AXIS]
    }
    fn start<S: PointLight, const AXIS: usize>(scene: &S) -> f32 {
        scene.light_start().0[AXIS]
    }
    fn set<S: PointLight, const AXIS: usize>(scene: &mut S, value: f32) -> Result<()> {
        let (mut position, power) = scene.light();
        position[AXIS] = value;
        scene.set_light(position, power)
    }
    fn read<const AXIS: usize>(matches: &clap::ArgMatches, id: &str) -> Option<Start> {
        given::<glam::Vec3>(matches, id).map(|light| Start::Slider(light[AXIS]))
    }
    Control::slider(
        LIGHT_AXES[AXIS],
        range::<S, AXIS>,
        start::<S, AXIS>,
        get::<S, AXIS>,
        set::<S, AXIS>,
    )
    .shared_flag(Shared::Light, read::<AXIS>)
}

/// The slider of the light's power, from 0 to [`PointLight::POWER_MAX`], started by
/// `--light-power`.
pub const fn power_slider<S: PointLight + 'static>() -> Control<S> {
    fn range<S: PointLight>(_: &S) -> (f32, f32) {
        (0.0, S::POWER_MAX)
    }
    fn get<S: PointLight>(scene: &S) -> f32 {
        scene.light().1
    }
    fn start<S: PointLight>(scene: &S) -> f32 {
        scene.light_start().1
    }
    fn set<S: PointLight>(scene: &mut S, power: f32) -> Result<()> {
        let (position, _) = scene.light();
        scene.set_light(position, power)
    }
    Control::slider(LIGHT_POWER, range::<S>, start::<S>, get::<S>, set::<S>)
        .shared_flag(Shared::LightPower, read_slider)
}

/// The starts that put the light of a scene whose table is `controls` at `position` (in the space
/// `--light` uses), as `--light` does: its three sliders'.
pub fn light_at<S: 'static>(
    controls: &'static [Control<S>],
    position: glam::Vec3,
) -> [Setting<S>; 3] {
    [0, 1, 2].map(|axis| Handle::new(controls, LIGHT_AXES[axis]).to(position[axis]))
}

/// The handle on the light's power slider of a scene whose table is `controls`.
pub const fn light_power<S: 'static>(controls: &'static [Control<S>]) -> Handle<S, f32> {
    Handle::new(controls, LIGHT_POWER)
}
