//! The frame's list of layers: what a layer drawn beside the terrain is given each frame, and
//! the calls [`crate::World`] makes on it. The terrain, its water and its sky are drawn by
//! `World` itself; a [`Layer`] pushed with [`crate::World::push_layer`] is drawn after them
//! into the host's pass, depth-tested against the terrain and the host's own geometry, by every
//! mesh-based method (`mesh`, `visibility`, `hybrid`). docs/architecture.md (section 4) says
//! how each kind of layer joins the frame; [`super::test_box`] is the smallest one.

use super::Targets;
use crate::method::Method;
use glam::DVec3;

/// What a layer is given each frame, after the terrain's uniforms are written.
pub struct LayerFrame<'a> {
    /// The host's device.
    pub device: &'a wgpu::Device,
    /// The host's queue.
    pub queue: &'a wgpu::Queue,
    /// The pass the layer draws into (the host's, or a ray cast's image): colour format, depth
    /// and samples (a layer's pipelines match them).
    pub targets: &'a Targets,
    /// The eye, in world metres: a layer's positions reach the GPU relative to it, as the
    /// terrain's do (f32 far from the origin loses metres, not the eye's offset).
    pub eye: DVec3,
    /// The frame's shading uniforms (`RenderUniforms` in `wgsl/shade.wgsl`): the
    /// camera-relative matrix, the sun, the sky light, whether to encode sRGB. A layer binds
    /// this buffer rather than copying what it holds.
    pub render_uniforms: &'a wgpu::Buffer,
    /// How the terrain is drawn this frame.
    pub method: Method,
}

/// A layer of the frame drawn by [`crate::World`] after the terrain. `Send + Sync` on native
/// targets, as `World` is (on the web, wgpu's types are neither).
pub trait Layer: wgpu::WasmNotSendSync {
    /// Its name, for labels and [`crate::World::layers`].
    fn name(&self) -> &str;
    /// Writes what the layer needs before the host's pass (its uniforms, any bake), into the
    /// host's `encoder` or its queue. Called by every [`crate::World::prepare`], and by the
    /// reference's cast with layers (`headless::render_world_rays_with_layers`), whose targets
    /// are its own (1 sample, `Depth32Float`) and whose render-uniforms buffer is new each
    /// cast: a layer keys what it builds on the [`LayerFrame`] it is given.
    fn prepare(&mut self, frame: &LayerFrame<'_>, encoder: &mut wgpu::CommandEncoder);
    /// Draws into the host's pass, after the terrain, with the depth test on.
    fn render(&self, pass: &mut wgpu::RenderPass<'_>);
}
