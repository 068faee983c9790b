//! The visibility method's clouds' image (`wgsl/clouds_image.wgsl`), half the frame's size
//! each way: where the temporal service runs and the frame has clouds, one pixel of each
//! [`BLOCK`] x [`BLOCK`] block is marched a frame (every pixel in turn over [`BLOCK`]² frames,
//! in the order of a Bayer matrix, so each frame's are spread evenly) and the others are
//! carried over from the last frame's image, moved with the eye and the wind; the shading
//! reads each ray's clouds from it. Every pixel is marched where there is no last image, the
//! image's size or the layer changed, the sun turned by more than [`SUN_CUT_DEGREES`], the
//! clouds moved more than [`EYE_CUT_M`] as the eye sees them since the last frame, or the
//! world's history was reset (a cut, new parameters, shading or method: `cut_clouds`).

use glam::{DVec2, DVec3, Mat4, Vec3};

use crate::gpu::timing::{GpuTimer, Slot};

/// One pixel of each block of `BLOCK` x `BLOCK` is marched a frame.
pub const BLOCK: u32 = 4;
/// A sun turned further than this between two frames (degrees) marches every pixel: a slider
/// moved, not the day running (a day in a minute turns it 0.1 degrees a frame at 60 Hz).
pub const SUN_CUT_DEGREES: f32 = 1.0;
/// Clouds moved further than this between two frames, as the eye sees them (metres: the eye's
/// move less the wind's drift), march every pixel: a jump, or a new wind or clock.
pub const EYE_CUT_M: f64 = 500.0;
/// Per pixel: the light scattered towards the eye (linear) and the light kept.
const LIGHT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Per pixel: where along the ray the light was taken (first, half, last) and the clouds' mean
/// distance, metres.
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The clouds' shadows' map: texels a side, and metres a texel (it reaches 16 km from the eye
/// each way; beyond, and above the base, the shadows are marched).
pub const SHADOW_TEXELS: u32 = 512;
/// Metres a texel of the shadows' map.
pub const SHADOW_TEXEL_M: f64 = 64.0;
/// The shadows' map: the light that reaches the clouds' base from the sun.
const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
/// The pixel of a block each frame marches, by frame: a 4x4 Bayer matrix's order.
const ORDER: [[u32; 2]; 16] = [
    [0, 0],
    [2, 2],
    [2, 0],
    [0, 2],
    [1, 1],
    [3, 3],
    [3, 1],
    [1, 3],
    [1, 0],
    [3, 2],
    [3, 0],
    [1, 2],
    [0, 1],
    [2, 3],
    [2, 1],
    [0, 3],
];

/// What the world says of a frame drawn with the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CloudFrame {
    /// The camera-relative projection times view, unjittered: the image's pixels are the
    /// same rays in every frame of a still view.
    pub matrix: Mat4,
    /// The eye, world space.
    pub eye: DVec3,
    /// How far the wind has carried the clouds' shapes (x, z), metres.
    pub drift: DVec2,
    /// The layer and its march (coverage, base, top, type, steps): any change marches every
    /// pixel.
    pub layer: [f32; 5],
    /// Towards the sun.
    pub sun: Vec3,
}

/// Mirrors `CloudFrame` in `wgsl/clouds_image.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct CloudUniforms {
    now: [[f32; 4]; 4],
    inv: [[f32; 4]; 4],
    last: [[f32; 4]; 4],
    shift: [f32; 4],
    phase: [u32; 4],
    size: [u32; 4],
    shadow: [f32; 4],
}

/// The image's textures at one size: this frame's (which the shading reads) and the last's.
struct Images {
    size: (u32, u32),
    now: [wgpu::Texture; 2],
    now_views: [wgpu::TextureView; 2],
    last: [wgpu::Texture; 2],
    /// The shadows' map, as the shading reads it and the pass writes it.
    shadow: wgpu::TextureView,
    /// The passes' bind group: the uniforms, the last image read, this one written.
    group: Option<wgpu::BindGroup>,
}

/// The clouds' passes of a visibility method built with them.
pub(crate) struct Clouds {
    module: wgpu::ShaderModule,
    uniforms: wgpu::Buffer,
    /// The passes, built the first time a frame draws with the image.
    passes: Option<(wgpu::BindGroupLayout, [wgpu::ComputePipeline; 3])>,
    images: Option<Images>,
    /// This frame, where it draws with the image.
    frame: Option<CloudFrame>,
    /// The last frame drawn with the image: its matrix and what the world said of it.
    last: Option<(Mat4, CloudFrame)>,
    /// Frames since every pixel was marched.
    since: usize,
    /// The share of the pixels the last frame marched (1 without the image).
    pub marched: f64,
}

impl Clouds {
    /// For the visibility method's `module`, built with the image (`CloudCode::Image`).
    pub(crate) fn new(device: &wgpu::Device, module: &wgpu::ShaderModule) -> Self {
        Self {
            module: module.clone(),
            uniforms: crate::gpu::uniform_buffer::<CloudUniforms>(
                device,
                "relief:visibility:cloud-uniforms",
            ),
            passes: None,
            images: None,
            frame: None,
            last: None,
            since: 0,
            marched: 1.0,
        }
    }

    /// The shading's bindings of the image: its uniforms and this frame's image.
    pub(crate) fn entries() -> [wgpu::BindGroupLayoutEntry; 4] {
        let c = wgpu::ShaderStages::COMPUTE;
        [
            crate::gpu::uniform_entry::<CloudUniforms>(30, c),
            crate::gpu::texture_entry(31, c, false),
            crate::gpu::texture_entry(32, c, false),
            crate::gpu::texture_entry(37, c, false),
        ]
    }

    /// Sets what the next frame draws with: the image (`Some`) or the march along every ray.
    /// Returns whether the image's size changes (its bindings must be made again).
    pub(crate) fn set_frame(&mut self, frame: Option<CloudFrame>) -> bool {
        let was = self.frame.is_some();
        self.frame = frame;
        if frame.is_none() {
            self.last = None;
        }
        was != frame.is_some()
    }

    /// Makes the image for frames of `size` (1x1 where the frame marches every ray) and
    /// returns the shading's bindings of it.
    pub(crate) fn bind(
        &mut self,
        device: &wgpu::Device,
        size: (u32, u32),
        render: &wgpu::Buffer,
    ) -> [wgpu::BindGroupEntry<'_>; 4] {
        let (size, shadow) = if self.frame.is_some() {
            (image_size(size), SHADOW_TEXELS)
        } else {
            ((1, 1), 1)
        };
        if self.images.as_ref().is_none_or(|i| i.size != size) {
            self.last = None;
            let usage = wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST;
            let make = |label| {
                [LIGHT_FORMAT, DEPTH_FORMAT]
                    .map(|format| crate::gpu::texture_2d(device, label, size, format, usage))
            };
            let now = make("relief:visibility:clouds");
            let now_views = [&now[0], &now[1]].map(|t| t.create_view(&Default::default()));
            let last = make("relief:visibility:clouds-last");
            let shadow = crate::gpu::texture_2d(
                device,
                "relief:visibility:cloud-shadows",
                (shadow, shadow),
                SHADOW_FORMAT,
                wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
            )
            .create_view(&Default::default());
            self.images = Some(Images {
                size,
                now,
                now_views,
                last,
                shadow,
                group: None,
            });
        }
        if self.frame.is_some() {
            let (layout, _) = self
                .passes
                .get_or_insert_with(|| passes(device, &self.module));
            if let Some(images) = self.images.as_mut().filter(|i| i.group.is_none()) {
                images.group = Some(pass_group(device, layout, images, (render, &self.uniforms)));
            }
        }
        let images = self.images.as_ref().expect("made above");
        use wgpu::BindingResource::TextureView;
        let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
        [
            entry(30, self.uniforms.as_entire_binding()),
            entry(31, TextureView(&images.now_views[0])),
            entry(32, TextureView(&images.now_views[1])),
            entry(37, TextureView(&images.shadow)),
        ]
    }

    /// GPU memory of the image for frames of `size`, bytes (this frame's and the last's),
    /// where it is kept.
    pub(crate) fn bytes(&self, size: (u32, u32)) -> u64 {
        if self.frame.is_none() {
            return 0;
        }
        let texel = crate::gpu::texel_bytes(LIGHT_FORMAT) + crate::gpu::texel_bytes(DEPTH_FORMAT);
        let (w, h) = image_size(size);
        let shadow = crate::gpu::texel_bytes(SHADOW_FORMAT) * u64::from(SHADOW_TEXELS).pow(2);
        2 * texel * u64::from(w) * u64::from(h) + shadow
    }

    /// Records the frame's clouds for an image of `size`: its uniforms and, where it draws
    /// with the image, the march of one pixel of each block (or every pixel), the others
    /// carried over, and this image kept as the last.
    pub(crate) fn encode(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        size: (u32, u32),
        timer: Option<&GpuTimer>,
    ) {
        let size = image_size(size);
        let Some(frame) = self.frame else {
            self.marched = 1.0;
            queue.write_buffer(
                &self.uniforms,
                0,
                bytemuck::bytes_of(&CloudUniforms::zeroed()),
            );
            return;
        };
        let matrix = frame.matrix;
        // The clouds' move since the last frame, camera-relative: the eye's less the wind's.
        let moved = |last: &CloudFrame| {
            let wind = frame.drift - last.drift;
            (frame.eye - last.eye - DVec3::new(wind.x, 0.0, wind.y)).as_vec3()
        };
        let history = self.last.filter(|(_, last)| {
            last.layer == frame.layer
                && last.sun.angle_between(frame.sun).to_degrees() <= SUN_CUT_DEGREES
                && f64::from(moved(last).length()) <= EYE_CUT_M
        });
        let (last_matrix, shift) = match history {
            Some((m, last)) => {
                self.since += 1;
                (m, moved(&last))
            }
            None => {
                self.since = 0;
                (matrix, Vec3::ZERO)
            }
        };
        let all = history.is_none();
        let [px, py] = ORDER[self.since % ORDER.len()];
        let u = CloudUniforms {
            now: matrix.to_cols_array_2d(),
            inv: matrix.as_dmat4().inverse().as_mat4().to_cols_array_2d(),
            last: last_matrix.to_cols_array_2d(),
            shift: shift.extend(0.0).to_array(),
            phase: [px, py, u32::from(all), 1],
            size: [size.0, size.1, 0, 0],
            shadow: shadow_grid(&frame),
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        self.last = Some((matrix, frame));
        let (Some((_, [march, reproject, shadows])), Some(images)) = (&self.passes, &self.images)
        else {
            return;
        };
        let Some(group) = &images.group else {
            return;
        };
        let marched = if all {
            size
        } else {
            (size.0.div_ceil(BLOCK), size.1.div_ceil(BLOCK))
        };
        self.marched = if all {
            1.0
        } else {
            1.0 / f64::from(BLOCK * BLOCK)
        };
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("relief:visibility:clouds-pass"),
                timestamp_writes: timer.map(|t| t.compute_writes(Slot::Clouds)),
            });
            pass.set_bind_group(0, group, &[]);
            pass.set_pipeline(march);
            let w = crate::gpu::WORKGROUP;
            pass.dispatch_workgroups(marched.0.div_ceil(w), marched.1.div_ceil(w), 1);
            if !all {
                pass.set_pipeline(reproject);
                pass.dispatch_workgroups(size.0.div_ceil(w), size.1.div_ceil(w), 1);
            }
            pass.set_pipeline(shadows);
            let n = SHADOW_TEXELS.div_ceil(w);
            pass.dispatch_workgroups(n, n, 1);
        }
        for (now, last) in images.now.iter().zip(&images.last) {
            encoder.copy_texture_to_texture(now.as_image_copy(), last.as_image_copy(), now.size());
        }
    }
}

use bytemuck::Zeroable;

/// The shadows' map's grid (`CloudFrame::shadow` in `wgsl/clouds_image.wgsl`): its corner a
/// texel corner in the clouds' space (the eye less the wind's drift, reduced in f64), half the
/// map from the eye's texel, camera-relative.
fn shadow_grid(frame: &CloudFrame) -> [f32; 4] {
    let period = crate::world::clouds::CLOUD_PERIOD;
    let s = SHADOW_TEXEL_M;
    let half = f64::from(SHADOW_TEXELS / 2) * s;
    let at = |eye: f64, drift: f64| {
        let o = (eye - drift).rem_euclid(period);
        ((o / s).floor() * s - half - o) as f32
    };
    [
        at(frame.eye.x, frame.drift.x),
        at(frame.eye.z, frame.drift.y),
        s as f32,
        SHADOW_TEXELS as f32,
    ]
}

/// The image's size for frames of `size`: half of it each way, rounded up.
fn image_size(size: (u32, u32)) -> (u32, u32) {
    (size.0.div_ceil(2).max(1), size.1.div_ceil(2).max(1))
}

impl super::Visibility {
    /// What the next frame says of its clouds where it draws them with the image (`None`:
    /// marched along every ray); nothing where the method was built without clouds.
    pub(crate) fn set_cloud_frame(&mut self, frame: Option<CloudFrame>) {
        if let Some(clouds) = &mut self.clouds {
            if clouds.set_frame(frame) {
                self.images = None;
            }
        }
    }

    /// The next frame marches every pixel's clouds (a camera cut).
    pub(crate) fn cut_clouds(&mut self) {
        if let Some(clouds) = &mut self.clouds {
            clouds.last = None;
        }
    }

    /// The share of the pixels whose clouds the last frame marched (1: every one).
    pub(crate) fn clouds_marched(&self) -> f64 {
        self.clouds.as_ref().map_or(1.0, |c| c.marched)
    }
}

/// The passes' layout and their pipelines (`march_clouds`, `reproject_clouds`,
/// `shadow_clouds`).
fn passes(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
) -> (wgpu::BindGroupLayout, [wgpu::ComputePipeline; 3]) {
    use crate::gpu::render::RenderUniforms;
    let c = wgpu::ShaderStages::COMPUTE;
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("relief:visibility:clouds-layout"),
        entries: &[
            crate::gpu::uniform_entry::<RenderUniforms>(0, c),
            crate::gpu::uniform_entry::<CloudUniforms>(30, c),
            crate::gpu::texture_entry(33, c, false),
            crate::gpu::texture_entry(34, c, false),
            crate::gpu::storage_entry(35, LIGHT_FORMAT),
            crate::gpu::storage_entry(36, DEPTH_FORMAT),
            crate::gpu::storage_entry(38, SHADOW_FORMAT),
        ],
    });
    let pipelines = ["march_clouds", "reproject_clouds", "shadow_clouds"].map(|entry| {
        crate::gpu::compute_pipeline(device, "relief:visibility:clouds", &layout, module, entry)
    });
    (layout, pipelines)
}

/// The passes' bind group for `images`.
fn pass_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    images: &Images,
    (render, uniforms): (&wgpu::Buffer, &wgpu::Buffer),
) -> wgpu::BindGroup {
    use wgpu::BindingResource::TextureView;
    let last = [&images.last[0], &images.last[1]].map(|t| t.create_view(&Default::default()));
    let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("relief:visibility:clouds-group"),
        layout,
        entries: &[
            entry(0, render.as_entire_binding()),
            entry(30, uniforms.as_entire_binding()),
            entry(33, TextureView(&last[0])),
            entry(34, TextureView(&last[1])),
            entry(35, TextureView(&images.now_views[0])),
            entry(36, TextureView(&images.now_views[1])),
            entry(38, TextureView(&images.shadow)),
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shadows_grid_is_fixed_in_the_clouds_space_and_centred_on_the_eye() {
        let frame = |eye: DVec3, drift: DVec2| CloudFrame {
            matrix: Mat4::IDENTITY,
            eye,
            drift,
            layer: [0.5, 2600.0, 4600.0, 0.7, 48.0],
            sun: Vec3::Y,
        };
        let half = f64::from(SHADOW_TEXELS / 2) * SHADOW_TEXEL_M;
        for (eye, drift) in [
            (DVec3::new(1.0e7 + 5.0, 900.0, -3.0), DVec2::new(100.0, 0.0)),
            (DVec3::new(-42.5, 10.0, 77_777.0), DVec2::new(-3.25, 1.0e6)),
        ] {
            let g = shadow_grid(&frame(eye, drift));
            for (corner, e, d) in [(g[0], eye.x, drift.x), (g[1], eye.z, drift.y)] {
                // The eye lies in the middle texel, half the map from the corner.
                let corner = f64::from(corner);
                assert!(
                    corner <= -half && corner > -half - SHADOW_TEXEL_M,
                    "{corner}"
                );
                // The corner, in the clouds' space, is a whole number of texels.
                let o = (e - d).rem_euclid(crate::world::clouds::CLOUD_PERIOD);
                let texels = (corner + o) / SHADOW_TEXEL_M;
                assert!((texels - texels.round()).abs() < 1e-3, "{texels}");
            }
            assert_eq!(g[2], SHADOW_TEXEL_M as f32);
        }
    }

    #[test]
    fn each_block_marches_every_pixel_once_in_its_cycle() {
        let mut seen = [[false; 4]; 4];
        for [x, y] in ORDER {
            assert!(!seen[y as usize][x as usize]);
            seen[y as usize][x as usize] = true;
        }
        assert_eq!(ORDER.len() as u32, BLOCK * BLOCK);
        // Each four frames in a row cover each 2x2 quarter of the block once.
        for k in (0..16).step_by(4) {
            let mut quarters: Vec<_> = ORDER[k..k + 4]
                .iter()
                .map(|[x, y]| (x / 2, y / 2))
                .collect();
            quarters.sort();
            quarters.dedup();
            assert_eq!(quarters.len(), 4, "{k}");
        }
    }
}
