// import: shade
// part of: visibility, hybrid, props_march, props_overlay (each declares the uniforms `r`)
// What the visibility method's compute passes share (src/gpu/visibility.rs): its uniforms, the
// raster pass's targets and the shaded images, the rays through a pixel's samples, and the
// store of a shaded pixel. Composed into the visibility module (after world.wgsl) and the
// hybrid's (after world_rays.wgsl); either declares `r` (RenderUniforms).

struct VisUniforms {
    // Inverse of the camera-relative projection times view: pixels to view directions (read
    // at the near plane, where the inverse loses nothing).
    inv: mat4x4<f32>,
    // Row 3 of the projection times view: clip w of a camera-relative point.
    w_row: vec4<f32>,
    // x, y: clip w from depth d is y / (d + x); z, w unused.
    depth: vec4<f32>,
    // The images' size in pixels.
    size: vec2<u32>,
    // 1 where the sky fills the samples no terrain covers (else they stay transparent).
    sky: u32,
    // 1 for the endless world's attributes, 0 for the tile's textures.
    world: u32,
    // 1 where the host's target is not an sRGB format and the composite encodes.
    encode_srgb: u32,
    // 32-bit words a pixel of `raster_depth`: 2 where the raster kept each pixel's triangle
    // (raster_ids.wgsl; the depth's the second word), else 1.
    depth_stride: u32,
    // 1 where the props' march (props_march.wgsl) left each pixel's prop in `prop_hit`.
    props: u32,
    _pad: u32,
}

@group(0) @binding(7) var depth_ms: texture_depth_multisampled_2d;
@group(0) @binding(8) var surface_ms: texture_multisampled_2d<f32>;
@group(0) @binding(9) var valley_ms: texture_multisampled_2d<f32>;
@group(0) @binding(10) var shaded: texture_storage_2d<rgba32float, write>;
@group(0) @binding(11) var shaded_depth: texture_storage_2d<r32float, write>;
@group(0) @binding(12) var<uniform> vis: VisUniforms;
// The same targets single-sampled (the method at one sample a pixel).
@group(0) @binding(15) var depth_1: texture_depth_2d;
@group(0) @binding(16) var surface_1: texture_2d<f32>;
@group(0) @binding(17) var valley_1: texture_2d<f32>;

// The compute raster's depth (raster.wgsl): per pixel, row by row, the nearest depth's
// complemented bits, 0 where nothing was drawn (`depth_stride` words a pixel, the depth's the
// last); its attributes are in surface_1 and valley_1.
@group(0) @binding(19) var<storage, read> raster_depth: array<u32>;

// The compute raster's depth at pixel `id` (1: nothing drawn).
fn rasterised_depth(id: vec2<u32>) -> f32 {
    let stride = vis.depth_stride;
    let bits = raster_depth[(id.y * vis.size.x + id.x) * stride + stride - 1u];
    return select(bitcast<f32>(~bits), 1.0, bits == 0u);
}

// The layer that kept pixel `id` in the compute raster (raster.wgsl's LAYER_SHIFT: 0 the
// terrain, 1 a blade of grass); 0 where the raster keeps no ids.
fn rasterised_layer(id: vec2<u32>) -> u32 {
    if vis.depth_stride < 2u {
        return 0u;
    }
    return raster_depth[(id.y * vis.size.x + id.x) * vis.depth_stride] >> 28u;
}

// The standard 4x MSAA sample positions within a pixel (WebGPU and Vulkan fix them).
const SAMPLES: array<vec2<f32>, 4> = array<vec2<f32>, 4>(
    vec2<f32>(0.375, 0.125),
    vec2<f32>(0.875, 0.375),
    vec2<f32>(0.125, 0.625),
    vec2<f32>(0.625, 0.875),
);

// The unit view direction through `pixel` (pixels from the top left) and the camera-relative
// point on it at depth `d`.
fn sample_ray(pixel: vec2<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(pixel.x / f32(vis.size.x) * 2.0 - 1.0, 1.0 - pixel.y / f32(vis.size.y) * 2.0);
    let near = vis.inv * vec4<f32>(ndc, 0.0, 1.0);
    return normalize(near.xyz / near.w);
}

fn point_at(dir: vec3<f32>, d: f32) -> vec3<f32> {
    let clip_w = vis.depth.y / (d + vis.depth.x);
    return dir * ((clip_w - vis.w_row.w) / dot(vis.w_row.xyz, dir));
}

// Linear output: the composite encodes for the target, after the samples are averaged.
fn linear_uniforms() -> RenderUniforms {
    var lin = r;
    lin.encode_srgb = 0u;
    return lin;
}

// Stores a pixel: `sum` of `n` samples' colours of which `covered` hit terrain, premultiplied
// (opaque where the sky fills the rest, else by coverage), and the nearest hit's depth.
fn store_pixel(px: vec2<i32>, sum: vec3<f32>, n: u32, covered: u32, nearest: f32) {
    var alpha = f32(covered) / f32(n);
    if vis.sky != 0u {
        alpha = 1.0;
    }
    textureStore(shaded, px, vec4<f32>(sum / f32(n), alpha));
    textureStore(shaded_depth, px, vec4<f32>(nearest, 0.0, 0.0, 0.0));
}

