//! The render uniforms every renderer shares (the mesh, the sky, the ray casters), mirrored by
//! `RenderUniforms` in `wgsl/shade.wgsl`.

use crate::camera::View;
use crate::params::{srgb_to_linear, Shading, TerrainParams};
use crate::sky::SkyLight;

/// Mirrors `RenderUniforms` in `wgsl/shade.wgsl` field by field.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RenderUniforms {
    /// Projection times view.
    pub view_proj: [[f32; 4]; 4],
    /// Camera position (w unused).
    pub camera_pos: [f32; 4],
    /// Unit vector towards the sun (w unused).
    pub sun_dir: [f32; 4],
    /// Linear sun radiance.
    pub sun_color: [f32; 4],
    /// Linear ambient radiance.
    pub ambient_color: [f32; 4],
    /// Linear albedo at the low end of the colour channel.
    pub color_a: [f32; 4],
    /// Linear albedo at the high end of the colour channel.
    pub color_b: [f32; 4],
    /// Linear snow albedo.
    pub snow_color: [f32; 4],
    /// World height of normalised height 1.
    pub height_scale: f32,
    /// Normalised snow height.
    pub snow_height: f32,
    /// Height-AO exponent.
    pub ao_exponent: f32,
    /// Blinn-Phong exponent.
    pub shininess: f32,
    /// Grid vertices per side.
    pub grid: u32,
    /// Texture side.
    pub tex_size: u32,
    /// 1 when the shader must sRGB-encode (the target format is not sRGB).
    pub encode_srgb: u32,
    /// Specular strength.
    pub specular: f32,
    /// Where the tile's textures are read, less where they were baked, in tiles (reduced to
    /// [0, 1)): the scroll animation moves the terrain without baking it again.
    pub shift: [f32; 2],
    /// The grass's draw distance where the frame draws grass (metres; 0: none): the ground
    /// under it is earth near the eye and the field's colour from half the distance on
    /// (`grass_ground` in `wgsl/shade.wgsl`).
    pub grass_distance: f32,
    /// 1 where the frame is the reference's, which draws every blade to `grass_distance`
    /// over bare earth (`src/gpu/grass_reference.rs`).
    pub grass_reference: u32,
    /// Inverse of `view_proj`: what turns a pixel into a view direction for the sky.
    pub inv_view_proj: [[f32; 4]; 4],
    /// Linear sky radiance at the zenith; w: 1 for a flat sky of `sky_horizon`'s colour (no
    /// gradient, no sun), as [`Shading::sky`] off asks.
    pub sky_zenith: [f32; 4],
    /// Linear sky radiance at the horizon (w unused).
    pub sky_horizon: [f32; 4],
    /// A low sun's glow on the horizon towards it (rgb) and its strength (w).
    pub sky_sunset: [f32; 4],
    /// Extinction per world unit of red, green and blue: aerial perspective (0: clear air).
    pub fog: [f32; 4],
    /// The horizontal distance from the eye where terrain begins fading into the sky, metres.
    pub fade_start: f32,
    /// Where the fade into the sky is whole, metres (0: no fade).
    pub fade_end: f32,
    /// The sun's elevation, radians.
    pub sun_elevation: f32,
    /// 1 when the terrain casts shadows (`shade`'s caller passes the horizon).
    pub shadows: u32,
    /// The water's level, normalised height.
    pub water_level: f32,
    /// The water plane's y in the shading's space.
    pub water_plane: f32,
    /// The clock in seconds modulo `CLOCK_PERIOD`: what moves the ripples.
    pub clock: f32,
    /// 1 when there is water.
    pub water_on: u32,
    /// The eye's x and z less the wind's drift, reduced modulo the ripples' period (so ripples
    /// stay put in the world, but for the wind, while positions are camera-relative).
    pub ripple_origin: [f32; 2],
    /// The sand band above the water, normalised height.
    pub sand_band: f32,
    /// The palette ([`crate::palette::Palette::code`]: 0 the blog's, 1 the seed template's
    /// materials and lighting, tone-mapped).
    pub palette: u32,
    /// Where the frame draws grass, the blades a ray crosses in its field per unit of the
    /// cotangent of the ray's elevation above the ground ([`crate::grass::Grass::field_cover`]):
    /// how much of the ground the field hides, seen from the eye (`grass_ground`).
    pub grass_cover: f32,
    /// Where the terrain's shading reads the props' shade map (`src/gpu/props_map.rs`), its
    /// levels (0: it reads none).
    pub props_map_levels: u32,
    /// Padding.
    pub _pad: [f32; 2],
    /// Per level of the props' shade map: the camera-relative x and z of its first texel's
    /// corner, metres, and that texel's column and row in the texture.
    pub props_map: [[f32; 4]; 3],
    /// The clouds (`wgsl/clouds.wgsl`): coverage (0: none), base and top altitudes in metres,
    /// type ([`crate::world::clouds::Clouds`]).
    pub clouds: [f32; 4],
    /// Cloud-space x and z of the eye for the clouds' shapes, then for their detail: the
    /// eye less the wind's drift, reduced modulo `CLOUD_PERIOD`.
    pub cloud_origin: [f32; 4],
    /// The eye's altitude (metres), the view ray's steps through the layer, the frame's step
    /// offset (0 to 1), unused.
    pub cloud_march: [f32; 4],
    /// The sun's linear light at the cloud layer's middle (which sees a sun a little below
    /// the ground's horizon); w unused.
    pub cloud_sun: [f32; 4],
    /// The terrain's shadow-height map for the light shafts (`wgsl/terrain_air_map.wgsl`,
    /// [`crate::gpu::air_shadow`]): the camera-relative x and z of its first corner, its texel
    /// (metres) and its texels a side (0: the frame bakes none, and the air is lit).
    pub air_shadow: [f32; 4],
}

fn linear(c: [f32; 3], k: f32) -> [f32; 4] {
    [
        srgb_to_linear(c[0]) * k,
        srgb_to_linear(c[1]) * k,
        srgb_to_linear(c[2]) * k,
        1.0,
    ]
}

impl RenderUniforms {
    /// The uniforms for one frame: the sky of the shading's sun, clear air.
    pub fn new(p: &TerrainParams, s: &Shading, view: &View, encode_srgb: bool) -> Self {
        let sun = glam::Vec3::from(s.sun_direction).normalize_or(glam::Vec3::Y);
        let sun_color = linear(s.sun_color, s.sun_intensity);
        let light = SkyLight::new(sun, [sun_color[0], sun_color[1], sun_color[2]]);
        let mut u = Self {
            view_proj: view.view_proj.to_cols_array_2d(),
            camera_pos: view.eye.extend(1.0).to_array(),
            sun_dir: sun.extend(0.0).to_array(),
            sun_color: linear(s.sun_color, s.sun_intensity),
            ambient_color: linear(s.ambient_color, s.ambient_intensity),
            color_a: linear(s.color_a, 1.0),
            color_b: linear(s.color_b, 1.0),
            snow_color: linear(s.snow_color, 1.0),
            height_scale: p.height_scale,
            snow_height: p.snow_height,
            ao_exponent: p.ao_exponent,
            shininess: s.shininess,
            grid: p.grid,
            tex_size: p.size,
            encode_srgb: u32::from(encode_srgb),
            specular: s.specular,
            shift: [0.0; 2],
            grass_distance: 0.0,
            grass_reference: 0,
            inv_view_proj: view.view_proj.inverse().to_cols_array_2d(),
            sky_zenith: [0.0; 4],
            sky_horizon: [0.0; 4],
            sky_sunset: [0.0; 4],
            fog: [0.0; 4],
            fade_start: 0.0,
            fade_end: 0.0,
            sun_elevation: sun.y.clamp(-1.0, 1.0).asin(),
            shadows: 0,
            water_level: 0.0,
            water_plane: 0.0,
            clock: 0.0,
            water_on: 0,
            ripple_origin: [0.0; 2],
            sand_band: 0.0,
            palette: 0,
            grass_cover: 0.0,
            props_map_levels: 0,
            _pad: [0.0; 2],
            props_map: [[0.0; 4]; 3],
            clouds: [0.0; 4],
            cloud_origin: [0.0; 4],
            cloud_march: [0.0; 4],
            cloud_sun: [0.0; 4],
            air_shadow: [0.0; 4],
        };
        // The tile's sun keeps the shading's colour: only the sky follows its elevation.
        u.set_sky(
            s,
            &SkyLight {
                sun: [sun_color[0], sun_color[1], sun_color[2]],
                ..light
            },
        );
        u
    }

    /// Sets the sun's direction and light and the sky's colours from `light`, or a flat sky of
    /// the shading's `sky_color` where [`Shading::sky`] is off.
    pub fn set_sky(&mut self, s: &Shading, light: &SkyLight) {
        let w = |c: [f32; 3], w: f32| [c[0], c[1], c[2], w];
        self.sun_dir = w(light.sun_dir.to_array(), 0.0);
        self.sun_elevation = light.sun_dir.y.clamp(-1.0, 1.0).asin();
        self.sun_color = w(light.sun, 1.0);
        if s.sky {
            self.sky_zenith = w(light.zenith, 0.0);
            self.sky_horizon = w(light.horizon, 0.0);
            self.sky_sunset = light.sunset;
        } else {
            let flat = linear(s.sky_color, 1.0);
            self.sky_zenith = w([flat[0], flat[1], flat[2]], 1.0);
            self.sky_horizon = flat;
            self.sky_sunset = [0.0; 4];
        }
    }

    /// What the sky pass and the ray casters' misses twin: the light of this sky.
    pub fn sky_light(&self) -> SkyLight {
        let c = |v: [f32; 4]| [v[0], v[1], v[2]];
        SkyLight {
            sun_dir: glam::Vec4::from(self.sun_dir).truncate(),
            sun: c(self.sun_color),
            zenith: c(self.sky_zenith),
            horizon: c(self.sky_horizon),
            sunset: self.sky_sunset,
            day: 1.0,
        }
    }
}
