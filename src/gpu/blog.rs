//! The seed blog's per-frame pipeline (`wgsl/blog.wgsl`), written again from its published
//! description as the method `blog`: relief's peer in the benchmark, and a way to see the
//! blog's picture in the window and on the page.
//!
//! Every frame it bakes its own terrain (a sine-hash gradient noise, five octaves, height and
//! colour) into an 8-bit texture, derives 8-bit normals from it and draws a 1024²-vertex grid
//! displaced by the heights, forward shaded without anti-aliasing. [`Blog::exact`] draws the same
//! terrain from the noise itself (heights at every vertex of a finer grid, height, colour and
//! normal at every fragment): the surface the blog's frame is scored against.
//!
//! Its compute work is recorded into the host's encoder before the host's render pass
//! ([`Blog::encode_bake`]) and it draws into that pass ([`Blog::render`]), as [`crate::Terrain`]
//! does.

use super::timing::{GpuTimer, Slot};
use super::Targets;
use crate::camera::View;
use crate::error::Result;
use crate::params::{Shading, TerrainParams};

/// Mirrors `BlogUniforms` in `wgsl/blog.wgsl` field by field.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BlogUniforms {
    /// Projection times view.
    pub view_proj: [[f32; 4]; 4],
    /// The eye (w unused).
    pub camera_pos: [f32; 4],
    /// Unit vector towards the light (w unused).
    pub sun_dir: [f32; 4],
    /// World height of baked height 1.
    pub height_scale: f32,
    /// Snow line in baked height.
    pub snow_height: f32,
    /// The blog's scroll along u, in texture widths.
    pub progress: f32,
    /// 1 when the target is not sRGB and the shader encodes.
    pub encode_srgb: u32,
    /// Texture side.
    pub size: u32,
    /// Grid vertices per side.
    pub grid: u32,
    /// Padding to the WGSL struct's size.
    pub _pad: [u32; 2],
}

/// The blog's texture side and grid (its `TEX_SIZE`: one vertex per texel).
pub const BLOG_SIZE: u32 = 1024;
/// Grid vertices per side of [`Blog::exact`]: four per texel of the blog's, so that the finest
/// octave (64 cycles across) gets 64 vertices a cycle.
pub const EXACT_GRID: u32 = 4096;
/// The blog's octaves (of its own noise, from 4 cells across the texture).
pub const BLOG_OCTAVES: u32 = 5;
/// The blog's texture format for both its maps.
pub const BLOG_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The blog's workgroup side.
const BLOG_WORKGROUP: u32 = 16;

/// Which of the two it draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// The blog's pipeline: bake, normals, textured grid.
    Pipeline,
    /// The same terrain from the noise itself, no textures.
    Exact,
}

/// The bake and the normal pass, each a pipeline with its bind group.
type Passes = [(wgpu::ComputePipeline, wgpu::BindGroup); 2];

/// The blog's pipeline (or its exact surface) built for the host's targets.
pub struct Blog {
    kind: Kind,
    targets: Targets,
    grid: u32,
    uniforms: wgpu::Buffer,
    draw: wgpu::RenderPipeline,
    draw_group: wgpu::BindGroup,
    /// The bake and normal passes with their bind groups (the pipeline only).
    passes: Option<Passes>,
    /// The pipeline's index buffer (the exact grid is drawn without one).
    indices: Option<wgpu::Buffer>,
    /// Indices (or vertices, without an index buffer) drawn.
    count: u32,
    /// The height map (height, colour) and normal map, rgba8unorm (the pipeline only).
    pub maps: Option<[wgpu::Texture; 2]>,
}

fn storage_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format: BLOG_FORMAT,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        count: None,
    }
}

fn sampler_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    }
}

/// A bind group layout of `entries` and its bind group of `resources`, in the same order.
fn group(
    device: &wgpu::Device,
    label: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
    resources: &[wgpu::BindingResource<'_>],
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(&format!("{label}:bind-group-layout")),
        entries,
    });
    let entries: Vec<wgpu::BindGroupEntry<'_>> = entries
        .iter()
        .zip(resources)
        .map(|(e, r)| wgpu::BindGroupEntry {
            binding: e.binding,
            resource: r.clone(),
        })
        .collect();
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(&format!("{label}:bind-group")),
        layout: &layout,
        entries: &entries,
    });
    (layout, group)
}

/// The blog's index list for a `grid`-vertex-square grid: two triangles per cell, u32.
fn grid_indices(grid: u32) -> Vec<u32> {
    let mut out = Vec::with_capacity(((grid - 1) * (grid - 1) * 6) as usize);
    for y in 0..grid - 1 {
        for x in 0..grid - 1 {
            let (a, b) = (x + y * grid, x + (y + 1) * grid);
            out.extend_from_slice(&[a, b, a + 1, b, b + 1, a + 1]);
        }
    }
    out
}

impl Blog {
    /// The blog's pipeline for the host's `targets`.
    pub fn new(device: &wgpu::Device, targets: Targets) -> Result<Self> {
        Self::build(device, targets, Kind::Pipeline, BLOG_SIZE)
    }

    /// The blog's terrain drawn exactly (no textures) on a `grid`-vertex grid: the truth its
    /// frame is scored against ([`EXACT_GRID`] for the benchmark).
    pub fn exact(device: &wgpu::Device, targets: Targets, grid: u32) -> Result<Self> {
        Self::build(device, targets, Kind::Exact, grid)
    }

    fn build(device: &wgpu::Device, targets: Targets, kind: Kind, grid: u32) -> Result<Self> {
        targets.validate()?;
        if !(2..=crate::params::MAX_GRID).contains(&grid) {
            return Err(crate::Error::invalid(
                "grid",
                grid,
                format!("2 to {}", crate::params::MAX_GRID),
            ));
        }
        super::scoped(device, || Self::create(device, targets, kind, grid))?
    }

    fn create(device: &wgpu::Device, targets: Targets, kind: Kind, grid: u32) -> Result<Self> {
        let module =
            super::shader::module(device, "relief:blog:shader", &super::shader::source("blog"));
        let uniforms = super::uniform_buffer::<BlogUniforms>(device, "relief:blog:uniforms");
        let (draw_layout, draw_group, entries, textured) = match kind {
            Kind::Pipeline => {
                let (layout, group, textured) = Self::textured(device, &module, &uniforms);
                (layout, group, ("vs_blog", "fs_blog"), Some(textured))
            }
            // The exact surface reads no maps: its uniforms alone.
            Kind::Exact => {
                let uniform =
                    super::uniform_entry::<BlogUniforms>(0, wgpu::ShaderStages::VERTEX_FRAGMENT);
                let entries = [uniforms.as_entire_binding()];
                let (layout, group) = group(device, "relief:blog:exact", &[uniform], &entries);
                (layout, group, ("vs_exact", "fs_exact"), None)
            }
        };
        let draw = super::render_pipeline(
            device,
            ("relief:blog", &draw_layout, &module, entries),
            &targets,
            wgpu::PrimitiveTopology::TriangleList,
            &[],
            (true, wgpu::CompareFunction::Less),
        );
        let count = (grid - 1) * (grid - 1) * 6;
        let indices = (kind == Kind::Pipeline).then(|| {
            wgpu::util::DeviceExt::create_buffer_init(
                device,
                &wgpu::util::BufferInitDescriptor {
                    label: Some("relief:blog:indices"),
                    contents: bytemuck::cast_slice(&grid_indices(grid)),
                    usage: wgpu::BufferUsages::INDEX,
                },
            )
        });
        let (passes, maps) = textured.unzip();
        Ok(Self {
            kind,
            targets,
            grid,
            uniforms,
            draw,
            draw_group,
            passes,
            count,
            indices,
            maps,
        })
    }

    /// The pipeline's maps, its draw's bind group (layout and group) and its bake and normal
    /// passes.
    fn textured(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        uniforms: &wgpu::Buffer,
    ) -> (
        wgpu::BindGroupLayout,
        wgpu::BindGroup,
        (Passes, [wgpu::Texture; 2]),
    ) {
        use wgpu::ShaderStages as S;
        let u = || uniforms.as_entire_binding();
        let usage = wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let size = (BLOG_SIZE, BLOG_SIZE);
        let make = |label| super::texture_2d(device, label, size, BLOG_FORMAT, usage);
        let maps = [make("relief:blog:noise"), make("relief:blog:normals")];
        let views = maps
            .clone()
            .map(|t| t.create_view(&wgpu::TextureViewDescriptor::default()));
        // The blog's sampler: bilinear, clamped to the edge.
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("relief:blog:sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let uniform = super::uniform_entry::<BlogUniforms>(0, S::VERTEX_FRAGMENT | S::COMPUTE);
        let view = |i: usize| wgpu::BindingResource::TextureView(&views[i]);
        let sampled = wgpu::BindingResource::Sampler(&sampler);
        let (draw_layout, draw_group) = group(
            device,
            "relief:blog:draw",
            &[
                uniform,
                super::texture_entry(2, S::VERTEX, true),
                sampler_entry(3, S::VERTEX),
                super::texture_entry(5, S::VERTEX, true),
            ],
            &[u(), view(0), sampled.clone(), view(1)],
        );
        let (bake_layout, bake_group) = group(
            device,
            "relief:blog:bake",
            &[uniform, storage_entry(1)],
            &[u(), view(0)],
        );
        let (normal_layout, normal_group) = group(
            device,
            "relief:blog:normals",
            &[
                uniform,
                super::texture_entry(2, S::COMPUTE, true),
                sampler_entry(3, S::COMPUTE),
                storage_entry(4),
            ],
            &[u(), view(0), sampled, view(1)],
        );
        let pipeline =
            |label, layout, entry| super::compute_pipeline(device, label, layout, module, entry);
        let passes = [
            (
                pipeline("relief:blog:bake", &bake_layout, "blog_bake"),
                bake_group,
            ),
            (
                pipeline("relief:blog:normals", &normal_layout, "blog_normals"),
                normal_group,
            ),
        ];
        (draw_layout, draw_group, (passes, maps))
    }

    /// The uniforms for `params` (its height scale and snow line; the blog's terrain has its own
    /// noise), the light of `shading`, seen through `view`, scrolled by `progress` texture
    /// widths (the blog's animation; 0 for a still).
    pub fn uniforms(
        &self,
        params: &TerrainParams,
        shading: &Shading,
        view: &View,
        progress: f32,
    ) -> BlogUniforms {
        let sun = glam::Vec3::from(shading.sun_direction).normalize_or(glam::Vec3::Y);
        BlogUniforms {
            view_proj: view.view_proj.to_cols_array_2d(),
            camera_pos: view.eye.extend(1.0).to_array(),
            sun_dir: sun.extend(0.0).to_array(),
            height_scale: params.height_scale,
            snow_height: params.snow_height,
            progress,
            encode_srgb: u32::from(!self.targets.color_format.is_srgb()),
            size: BLOG_SIZE,
            grid: self.grid,
            _pad: [0; 2],
        }
    }

    /// Writes this frame's uniforms ([`Blog::uniforms`]).
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        params: &TerrainParams,
        shading: &Shading,
        view: &View,
        progress: f32,
    ) {
        let u = self.uniforms(params, shading, view, progress);
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
    }

    /// Records the blog's bake and normal passes (timed as [`Slot::Bake`] and
    /// [`Slot::Normals`]), as the blog does every frame; nothing for the exact surface.
    pub fn encode_bake(&self, encoder: &mut wgpu::CommandEncoder, timer: Option<&GpuTimer>) {
        let Some(passes) = &self.passes else {
            return;
        };
        let groups = BLOG_SIZE.div_ceil(BLOG_WORKGROUP);
        for ((pipeline, group), slot) in passes.iter().zip([Slot::Bake, Slot::Normals]) {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("relief:blog:pass"),
                timestamp_writes: timer.map(|t| t.compute_writes(slot)),
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(groups, groups, 1);
        }
    }

    /// Draws the grid into the host's pass.
    pub fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.draw);
        pass.set_bind_group(0, &self.draw_group, &[]);
        match &self.indices {
            Some(indices) => {
                pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..self.count, 0, 0..1);
            }
            None => pass.draw(0..self.count, 0..1),
        }
    }

    /// The targets it draws into.
    pub fn targets(&self) -> &Targets {
        &self.targets
    }

    /// Triangles drawn per frame.
    pub fn triangles(&self) -> u64 {
        u64::from(self.count / 3)
    }

    /// Whether this draws the exact surface rather than the blog's pipeline.
    pub fn is_exact(&self) -> bool {
        self.kind == Kind::Exact
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_is_two_triangles_per_cell_over_every_vertex() {
        let i = grid_indices(3);
        assert_eq!(i.len(), 2 * 2 * 6);
        assert_eq!(&i[..6], &[0, 3, 1, 3, 4, 1]);
        assert_eq!(*i.iter().max().unwrap(), 8);
    }
}
