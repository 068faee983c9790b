//! The test layer: a box standing on the terrain (`wgsl/test_box.wgsl`). It proves the list
//! of layers ([`super::layer`]): it touches nothing but its own module and the list, and every
//! mesh-based method draws it, depth-tested against the terrain and the host's geometry.
//! Tests and examples use it; it is no scenery.

use super::layer::{Layer, LayerFrame};
use super::render::RenderUniforms;
use super::Targets;
use glam::DVec3;

/// Mirrors `BoxUniforms` in `wgsl/test_box.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct BoxUniforms {
    center: [f32; 4],
    half_size: [f32; 4],
    albedo: [f32; 4],
}

/// An axis-aligned box in world metres, drawn flat-lit in one colour.
pub struct TestBox {
    /// Its centre, world metres.
    pub center: DVec3,
    /// Half its size along x, y and z, metres.
    pub half_size: DVec3,
    /// Its linear albedo.
    pub albedo: [f32; 3],
    uniforms: Option<wgpu::Buffer>,
    drawn: Option<(Targets, wgpu::RenderPipeline, wgpu::BindGroupLayout)>,
    /// The bind group, with the render-uniforms buffer it binds.
    bind_group: Option<(wgpu::Buffer, wgpu::BindGroup)>,
}

impl TestBox {
    /// A box standing on the ground at `foot` (its bottom face's centre), `size` metres along
    /// x, y and z.
    pub fn standing(foot: DVec3, size: DVec3, albedo: [f32; 3]) -> Self {
        Self {
            center: foot + DVec3::new(0.0, size.y / 2.0, 0.0),
            half_size: size / 2.0,
            albedo,
            uniforms: None,
            drawn: None,
            bind_group: None,
        }
    }
}

impl Layer for TestBox {
    fn name(&self) -> &str {
        "test box"
    }

    fn prepare(&mut self, frame: &LayerFrame<'_>, _encoder: &mut wgpu::CommandEncoder) {
        let device = frame.device;
        if self.drawn.as_ref().is_none_or(|(t, ..)| t != frame.targets) {
            let module = super::shader::module(
                device,
                "relief:test-box:shader",
                &super::shader::source("test_box"),
            );
            let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("relief:test-box:bind-group-layout"),
                entries: &[
                    super::uniform_entry::<RenderUniforms>(0, stages),
                    super::uniform_entry::<BoxUniforms>(1, stages),
                ],
            });
            let pipeline = super::render_pipeline(
                device,
                ("relief:test-box", &layout, &module, ("vs_main", "fs_main")),
                frame.targets,
                wgpu::PrimitiveTopology::TriangleList,
                &[],
                (true, wgpu::CompareFunction::Less),
            );
            self.drawn = Some((*frame.targets, pipeline, layout));
            self.bind_group = None;
        }
        let uniforms = self.uniforms.get_or_insert_with(|| {
            super::uniform_buffer::<BoxUniforms>(device, "relief:test-box:uniforms")
        });
        let center = (self.center - frame.eye).as_vec3();
        let half = self.half_size.as_vec3();
        let u = BoxUniforms {
            center: center.extend(1.0).to_array(),
            half_size: half.extend(0.0).to_array(),
            albedo: [self.albedo[0], self.albedo[1], self.albedo[2], 1.0],
        };
        frame
            .queue
            .write_buffer(uniforms, 0, bytemuck::bytes_of(&u));
        // Made again only when the world's render uniforms are a new buffer (it rebuilt them)
        // or the pipeline is new.
        if self
            .bind_group
            .as_ref()
            .is_none_or(|(bound, _)| bound != frame.render_uniforms)
        {
            let (_, _, layout) = self.drawn.as_ref().expect("made above");
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:test-box:bind-group"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: frame.render_uniforms.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: uniforms.as_entire_binding(),
                    },
                ],
            });
            self.bind_group = Some((frame.render_uniforms.clone(), group));
        }
    }

    fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        let (Some((_, pipeline, _)), Some((_, bind_group))) = (&self.drawn, &self.bind_group)
        else {
            return; // not prepared yet: nothing to draw
        };
        pass.push_debug_group("relief:test-box");
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.draw(0..36, 0..1);
        pass.pop_debug_group();
    }
}
