//! # relief: procedural terrain on the GPU with wgpu
//!
//! relief bakes periodic gradient-noise (Perlin) fBm into textures with compute shaders,
//! derives a wrap-around normal map, and draws a mesh displaced by the heights, with levels of
//! detail from the screen-space error, with Blinn-Phong shading, a noise-jittered snow line and
//! height ambient occlusion. One renderer ([`World`]) draws both the seed blog's tile
//! ([`Terrain`], a bounded square of a periodic landscape) and the endless world.
//!
//! ## Shape
//!
//! ```text
//! TerrainParams ──► noise (CPU twin, f64) ──► GPU: bake ─► normals ─► render
//!                                                  ▲                   ▲
//!   front ends: window (native + web) · CLI (render, bake) · your app (embedding)
//! ```
//!
//! The core, [`Terrain`], owns no window, surface or event loop. It takes the host's
//! `&wgpu::Device`, `&wgpu::Queue` and [`Targets`] (colour format, depth format, sample
//! count), records everything a frame needs before the host's pass into the host's encoder
//! ([`Terrain::prepare`]: the bake owed, nothing when nothing changed; the frame's uniforms;
//! the compute passes of the methods shaded in compute), and draws into the host's render pass
//! ([`Terrain::render`]) or writes the frame without one ([`Terrain::present`]). It never
//! submits. The window app, the headless `relief render`, and the tests all go through these
//! same calls; only the target differs.
//!
//! The endless world ([`World`], [`WorldParams`], [`WorldView`]) is the same middleware shape
//! for a landscape in metres seen from inside: geometry clipmap levels ([`clipmap`]) baked by
//! strips as the camera moves ([`World::prepare`] takes the view, and bakes within a
//! per-frame budget, [`World::set_bake_budget`]), drawn as patch rings morphing into each other
//! without cracks, sized by a screen-space error knob. Its look is one shading path for every
//! method: an analytic sky, sun and aerial perspective ([`sky`]), soft sun shadows and valley
//! occlusion from a light bake beside the levels ([`light`]), water, and the palettes
//! ([`palette`]).
//!
//! Every way of drawing a frame is a [`Method`] value from one list: the mesh, the seed's
//! heightfield ray march (compute or fragment, optionally band-limited), and the reference ray
//! cast of the continuous surface that every method is measured against (for the tile,
//! [`gpu::raymarch`]; for the endless world, [`gpu::world_rays`]).
//! `relief render` draws with the fastest mesh-based method on its GPU, measured before the
//! frame ([`choice`]); the library draws with the mesh until told otherwise.
//!
//! ## Conventions
//!
//! - World space is y-up. One tile spans x, z in [-[`WORLD_SIZE`]/2, [`WORLD_SIZE`]/2]; the
//!   terrain is periodic and tiles without a seam.
//! - Heights are normalised to [0, 1] and scaled by [`TerrainParams::height_scale`].
//! - The same seed gives the same terrain on every GPU, in the browser and on the CPU twin
//!   ([`noise`]): the hash is an integer PCG hash of integer lattice coordinates.
//!
//! ## Crates
//!
//! This crate is the core alone (wgpu, glam, bytemuck, thiserror, log, and half natively): it
//! has no features and names no front end. A device without a window, an offscreen target and
//! readback are [`gpu::headless`] (native only). The front ends are their own crates in the
//! repository's workspace: `relief-app` (the winit window, native and the web page),
//! `relief-cli` (the `relief` program) and `relief-eval` (metrics, the CPU ray caster, the
//! benchmarks and the stability map).
//!
//! ## Embedding
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, encoder: &mut wgpu::CommandEncoder,
//! #          pass: &mut wgpu::RenderPass<'_>) -> relief::Result<()> {
//! let targets = relief::Targets {
//!     color_format: wgpu::TextureFormat::Bgra8UnormSrgb,
//!     depth_format: Some(wgpu::TextureFormat::Depth32Float),
//!     sample_count: 1,
//! };
//! let mut terrain = relief::Terrain::new(device, queue, targets, relief::TerrainParams::default())?;
//! terrain.set_viewport((1280, 720)); // the target's pixels (the mesh's screen-error bound)
//! // Each frame:
//! let view = relief::OrbitCamera::default().view(1280.0 / 720.0);
//! terrain.prepare(device, queue, encoder, &view)?; // bakes, uniforms, compute passes
//! terrain.render(pass); // inside the host's render pass
//! # Ok(()) }
//! ```

#![deny(missing_docs)]

pub mod camera;
pub mod choice;
pub mod clipmap;
pub mod error;
pub mod gpu;
pub mod grass;
pub mod landscape;
pub mod light;
pub mod method;
pub mod noise;
pub mod palette;
pub mod params;
pub mod props;
pub mod sky;
pub mod table;
pub mod temporal;
pub(crate) mod tile;
pub mod world;
pub use world::day;

pub use camera::WorldView;
pub use camera::{FlyCamera, OrbitCamera, PathCamera, View};
pub use error::{Error, Result};
pub use gpu::world::World;
pub use gpu::world_stats::WorldStats;
pub use gpu::{height_at, Targets, Terrain, Textures};
pub use method::{Method, MethodConfig, Raster};
pub use params::{Dirty, NormalMethod, Redo, Shading, TerrainParams, PARAMS};
pub use temporal::Temporal;
pub use wgpu;
pub use world::{Wind, WorldKind, WorldParams};

/// The README's Rust snippets, compiled as doctests so that they stay true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

/// World width of one terrain tile: x and z span [-WORLD_SIZE/2, WORLD_SIZE/2].
pub const WORLD_SIZE: f64 = 2.0;

// A host may keep relief's renderers in a `Send + Sync` place (a render thread, an ECS
// resource): checked at compile time, natively (on the web WebGPU's handles stay on their
// thread).
#[cfg(not(target_arch = "wasm32"))]
const _: () = {
    const fn send_sync<T: Send + Sync>() {}
    send_sync::<Terrain>();
    send_sync::<World>();
    send_sync::<Targets>();
};
