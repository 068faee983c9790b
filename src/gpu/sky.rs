//! The sky pass: `wgsl/sky.wgsl`, one full-screen triangle at the far plane that fills the
//! pixels the terrain left, drawn by [`crate::Terrain::render`] and [`crate::World::render`]
//! from their own render uniforms (so the sky is the one their shading fogs towards).

use super::render::RenderUniforms;
use super::Targets;

pub(crate) struct SkyPass {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    /// Whether the host's pass has depth: the sky then goes after the terrain, tested against
    /// it; without depth it goes first, and the terrain covers it.
    after: bool,
}

impl SkyPass {
    /// A sky pass reading the render uniforms in `uniforms` and the light shafts' `air_shadow`
    /// map.
    pub fn new(
        device: &wgpu::Device,
        targets: &Targets,
        (uniforms, air_shadow): (&wgpu::Buffer, &super::air_shadow::AirShadow),
    ) -> Self {
        let module =
            super::shader::module(device, "relief:sky:shader", &super::shader::source("sky"));
        let air = super::air_shadow::AirShadow::entries(wgpu::ShaderStages::FRAGMENT);
        let [map, map_sampler] = air_shadow.bindings();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:sky:bind-group-layout"),
            entries: &[
                super::uniform_entry::<RenderUniforms>(0, wgpu::ShaderStages::FRAGMENT),
                air[0],
                air[1],
            ],
        });
        // Depth 1 passes only where the depth buffer still holds its clear value.
        let pipeline = super::render_pipeline(
            device,
            ("relief:sky", &layout, &module, ("vs_main", "fs_main")),
            targets,
            wgpu::PrimitiveTopology::TriangleList,
            &[],
            (false, wgpu::CompareFunction::LessEqual),
        );
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:sky:bind-group"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniforms.as_entire_binding(),
                },
                map,
                map_sampler,
            ],
        });
        Self {
            pipeline,
            bind_group,
            after: targets.depth_format.is_some(),
        }
    }

    /// Draws the terrain with `terrain`, and the sky behind it (when `sky` is on).
    pub fn around(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        sky: bool,
        terrain: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) {
        if sky && !self.after {
            self.draw(pass);
        }
        terrain(pass);
        if sky && self.after {
            self.draw(pass);
        }
    }

    fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.push_debug_group("relief:sky");
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.draw(0..3, 0..1);
        pass.pop_debug_group();
    }
}
