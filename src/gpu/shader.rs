//! WGSL sources and the one include step that composes them.
//!
//! Each pass has its own file in `wgsl/`; the shared noise functions live in
//! `wgsl/noise.wgsl`. A pass that needs them is composed as `noise.wgsl` followed by the
//! pass's file: plain concatenation, no directives, so every file stays valid WGSL that naga
//! can check on its own (the passes that use noise are checked composed).

/// `wgsl/noise.wgsl`: hash, gradient noise and fBm.
pub const NOISE: &str = include_str!("../../wgsl/noise.wgsl");
/// `wgsl/bake.wgsl`: the bake pass (needs [`NOISE`]).
pub const BAKE: &str = include_str!("../../wgsl/bake.wgsl");
/// `wgsl/normals.wgsl`: the normal pass (needs [`NOISE`]).
pub const NORMALS: &str = include_str!("../../wgsl/normals.wgsl");
/// `wgsl/landscape.wgsl`: the endless world's terrain function (needs [`NOISE`]).
pub const LANDSCAPE: &str = include_str!("../../wgsl/landscape.wgsl");
/// `wgsl/level_texel.wgsl`: the packed level texel (rg32uint), packed and unpacked (stands
/// alone).
pub const LEVEL_TEXEL: &str = include_str!("../../wgsl/level_texel.wgsl");
/// `wgsl/landscape_bake.wgsl`: bakes rectangles of landscape levels (needs [`NOISE`],
/// [`LANDSCAPE`] and [`LEVEL_TEXEL`]).
pub const LANDSCAPE_BAKE: &str = include_str!("../../wgsl/landscape_bake.wgsl");
/// `wgsl/shade.wgsl`: render uniforms and the shading every renderer shares.
pub const SHADE: &str = include_str!("../../wgsl/shade.wgsl");
/// `wgsl/world.wgsl`: the endless world's clipmap render pass (needs [`SHADE`] and
/// [`LEVEL_TEXEL`]).
pub const WORLD: &str = include_str!("../../wgsl/world.wgsl");
/// `wgsl/vis_common.wgsl`: what the visibility method's and the hybrid's compute passes share
/// (after [`WORLD`] or [`WORLD_SURFACE`]).
pub const VIS_COMMON: &str = include_str!("../../wgsl/vis_common.wgsl");
/// `wgsl/visibility.wgsl`: the visibility method's compute shading and composite (needs
/// [`SHADE`], [`LEVEL_TEXEL`], [`WORLD`] and [`VIS_COMMON`]).
pub const VISIBILITY: &str = include_str!("../../wgsl/visibility.wgsl");
/// `wgsl/raster.wgsl`: the visibility method's raster pass in compute (needs [`SHADE`],
/// [`LEVEL_TEXEL`] and [`WORLD`], then [`RASTER_DEPTH`] or [`RASTER_IDS`]).
pub const RASTER: &str = include_str!("../../wgsl/raster.wgsl");
/// `wgsl/raster_depth.wgsl`: what the compute raster keeps on any device (the nearest depth;
/// the attributes by a second dispatch).
pub const RASTER_DEPTH: &str = include_str!("../../wgsl/raster_depth.wgsl");
/// `wgsl/raster_ids.wgsl`: what it keeps with a 64-bit atomic maximum (the nearest depth and
/// its triangle; the attributes by a dispatch a pixel).
pub const RASTER_IDS: &str = include_str!("../../wgsl/raster_ids.wgsl");
/// `wgsl/sky.wgsl`: the sky behind the terrain (needs [`SHADE`]).
pub const SKY: &str = include_str!("../../wgsl/sky.wgsl");
/// `wgsl/raymarch.wgsl`: the tile's ray casters, reference and the seed's march (needs
/// [`NOISE`] and [`SHADE`], then [`RAYS`]).
pub const RAYMARCH: &str = include_str!("../../wgsl/raymarch.wgsl");
/// `wgsl/world_rays.wgsl` and `wgsl/world_rays_io.wgsl`: the endless world's ray casters and
/// their bindings (needs [`NOISE`], [`SHADE`] and [`LANDSCAPE`], then [`RAYS`]).
pub const WORLD_RAYS: &str = concat!(
    include_str!("../../wgsl/world_rays.wgsl"),
    "\n",
    include_str!("../../wgsl/world_rays_io.wgsl")
);
/// `wgsl/world_rays.wgsl` alone: the endless world's continuous surface, its reference ray
/// cast and shading, without the casters' bindings (the hybrid method declares its own).
pub const WORLD_SURFACE: &str = include_str!("../../wgsl/world_rays.wgsl");
/// `wgsl/horizon_probe.wgsl`: the world's ray casters' sun horizon at given points (needs
/// [`WORLD_RAYS`] and [`RAYS`]).
pub const HORIZON_PROBE: &str = include_str!("../../wgsl/horizon_probe.wgsl");
/// `wgsl/world_light.wgsl`: the endless world's light bake (needs [`NOISE`], [`LANDSCAPE`]
/// and [`LEVEL_TEXEL`]).
pub const WORLD_LIGHT: &str = include_str!("../../wgsl/world_light.wgsl");
/// `wgsl/blit.wgsl`: shows a ray-cast image in a window (stands alone).
pub const BLIT: &str = include_str!("../../wgsl/blit.wgsl");
/// `wgsl/blog.wgsl`: the seed blog's pipeline, the benchmark peer `blog` (stands alone).
pub const BLOG: &str = include_str!("../../wgsl/blog.wgsl");
/// `wgsl/march.wgsl`: the ray casters' march and bisection (after a caster's file).
pub const MARCH: &str = include_str!("../../wgsl/march.wgsl");
/// `wgsl/march.wgsl` and `wgsl/rays.wgsl`: the ray casters' march and entry points, composed
/// after a caster's file.
pub const RAYS: &str = concat!(
    include_str!("../../wgsl/march.wgsl"),
    "\n",
    include_str!("../../wgsl/rays.wgsl")
);
/// `wgsl/hybrid.wgsl`: the hybrid method's refinement and shading (needs [`SHADE`],
/// [`NOISE`], [`LANDSCAPE`], [`WORLD_SURFACE`], [`MARCH`] and [`VIS_COMMON`]).
pub const HYBRID: &str = include_str!("../../wgsl/hybrid.wgsl");

/// Joins shared WGSL files and a pass's file into one module source.
pub fn compose(parts: &[&str]) -> String {
    parts.join("\n")
}

/// Every shader module relief builds, by name, fully composed: what the tests validate.
pub fn all_modules() -> Vec<(&'static str, String)> {
    vec![
        ("noise", NOISE.to_owned()),
        ("blit", BLIT.to_owned()),
        ("blog", BLOG.to_owned()),
        (
            "world_light",
            compose(&[NOISE, LANDSCAPE, LEVEL_TEXEL, WORLD_LIGHT]),
        ),
        ("level_texel", LEVEL_TEXEL.to_owned()),
        ("bake", compose(&[NOISE, BAKE])),
        ("normals", compose(&[NOISE, NORMALS])),
        ("shade", SHADE.to_owned()),
        ("world", compose(&[SHADE, LEVEL_TEXEL, WORLD])),
        ("sky", compose(&[SHADE, SKY])),
        (
            "raster",
            compose(&[SHADE, LEVEL_TEXEL, WORLD, RASTER, RASTER_DEPTH]),
        ),
        (
            "raster_ids",
            compose(&[SHADE, LEVEL_TEXEL, WORLD, RASTER, RASTER_IDS]),
        ),
        (
            "visibility",
            compose(&[SHADE, LEVEL_TEXEL, WORLD, VIS_COMMON, VISIBILITY]),
        ),
        (
            "hybrid",
            compose(&[
                SHADE,
                NOISE,
                LANDSCAPE,
                WORLD_SURFACE,
                MARCH,
                VIS_COMMON,
                HYBRID,
            ]),
        ),
        ("raymarch", compose(&[NOISE, SHADE, RAYMARCH, RAYS])),
        (
            "world_rays",
            compose(&[NOISE, SHADE, LANDSCAPE, WORLD_RAYS, RAYS]),
        ),
        (
            "horizon_probe",
            compose(&[NOISE, SHADE, LANDSCAPE, WORLD_RAYS, RAYS, HORIZON_PROBE]),
        ),
        ("landscape", compose(&[NOISE, LANDSCAPE])),
        (
            "landscape_bake",
            compose(&[NOISE, LANDSCAPE, LEVEL_TEXEL, LANDSCAPE_BAKE]),
        ),
    ]
}

pub(crate) fn module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}
