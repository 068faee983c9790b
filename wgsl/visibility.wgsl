// The visibility method (src/gpu/visibility.rs): the raster pass (world.wgsl's `vs_samples`
// and `fs_attributes`, or depth alone for the tile) leaves each MSAA sample's depth and, for the
// endless world, its surface attributes; this compute pass shades every sample with the
// shading every method shares (shade.wgsl) and averages the samples of a pixel in linear light;
// a full-screen pass composites the result, colour and depth, into the host's render pass.
// Composed after shade.wgsl, level_texel.wgsl and world.wgsl (their uniforms and the tile's
// texture reads).

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
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(7) var depth_ms: texture_depth_multisampled_2d;
@group(0) @binding(8) var surface_ms: texture_multisampled_2d<f32>;
@group(0) @binding(9) var valley_ms: texture_multisampled_2d<f32>;
@group(0) @binding(10) var shaded: texture_storage_2d<rgba16float, write>;
@group(0) @binding(11) var shaded_depth: texture_storage_2d<r32float, write>;
@group(0) @binding(12) var<uniform> vis: VisUniforms;
// The same targets single-sampled (the method at one sample a pixel).
@group(0) @binding(15) var depth_1: texture_depth_2d;
@group(0) @binding(16) var surface_1: texture_2d<f32>;
@group(0) @binding(17) var valley_1: texture_2d<f32>;

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

// The colour (linear, tone-mapped) of one sample at `pixel` (pixels from the top left) whose
// depth is `d` (1: no terrain, the sky), with the endless world's attributes `s` and `valley`.
fn shade_sample(lin: RenderUniforms, pixel: vec2<f32>, d: f32, s: vec4<f32>, valley: f32) -> vec3<f32> {
    let dir = sample_ray(pixel);
    if d >= 1.0 {
        return sky_pixel(lin, dir);
    }
    let rel = point_at(dir, d);
    if vis.world != 0u {
        let h = (rel.y + w.eye.y) / w.peak;
        let n = normalize(vec3<f32>(-s.x, 1.0, -s.y));
        return shade(lin, rel, n, h, s.z, occlusion(lin, h, s.w, valley));
    }
    let uv = (rel.xz + w.tile_eye) * w.tile_inv + r.shift;
    let n = normalize(textureSampleLevel(tile_normals, tile_sampler, uv, 0.0).xyz);
    let t = tile_terrain_at(uv);
    return shade(lin, rel, n, t.x, t.y, unshadowed(lin, t.x));
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

@compute @workgroup_size(8, 8)
fn shade_samples(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let px = vec2<i32>(id.xy);
    let lin = linear_uniforms();
    var sum = vec3<f32>(0.0);
    var covered = 0u;
    var nearest = 1.0;
    for (var i = 0; i < 4; i++) {
        let d = textureLoad(depth_ms, px, i);
        if d < 1.0 {
            covered += 1u;
            nearest = min(nearest, d);
        } else if vis.sky == 0u {
            continue;
        }
        let s = textureLoad(surface_ms, px, i);
        let valley = textureLoad(valley_ms, px, i).x;
        sum += shade_sample(lin, vec2<f32>(id.xy) + SAMPLES[i], d, s, valley);
    }
    store_pixel(px, sum, 4u, covered, nearest);
}

@compute @workgroup_size(8, 8)
fn shade_pixels(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let px = vec2<i32>(id.xy);
    let d = textureLoad(depth_1, px, 0);
    let covered = u32(d < 1.0);
    var color = vec3<f32>(0.0);
    if covered != 0u || vis.sky != 0u {
        let s = textureLoad(surface_1, px, 0);
        let valley = textureLoad(valley_1, px, 0).x;
        color = shade_sample(linear_uniforms(), vec2<f32>(id.xy) + 0.5, d, s, valley);
    }
    store_pixel(px, color, 1u, covered, d);
}

// The composite: one full-screen triangle; each pixel takes its shaded colour (blended over what
// is there by its coverage where there is no sky) and its nearest sample's depth (1 for sky,
// which the host's less-or-equal test lets through only where nothing was drawn).
@group(0) @binding(13) var shown: texture_2d<f32>;
@group(0) @binding(14) var shown_depth: texture_2d<f32>;

@vertex
fn composite_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0);
}

struct CompositeOut {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

fn composite_color(c: vec4<f32>) -> vec4<f32> {
    if vis.encode_srgb == 0u || c.a <= 0.0 {
        return c;
    }
    return vec4<f32>(srgb_encode(c.rgb / c.a) * c.a, c.a);
}

@fragment
fn composite_fs(@builtin(position) position: vec4<f32>) -> CompositeOut {
    let px = vec2<i32>(floor(position.xy));
    let c = textureLoad(shown, px, 0);
    if c.a <= 0.0 {
        discard;
    }
    var out: CompositeOut;
    out.color = composite_color(c);
    out.depth = textureLoad(shown_depth, px, 0).x;
    return out;
}

// The same for a host pass without depth.
@fragment
fn composite_fs_color(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(shown, vec2<i32>(floor(position.xy)), 0);
    if c.a <= 0.0 {
        discard;
    }
    return composite_color(c);
}
