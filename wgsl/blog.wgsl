// The seed blog's terrain pipeline ("Terrain", 2024, in ../shared/seeds), written again from its
// published description as relief's benchmark peer `blog` (src/gpu/blog.rs). Every frame it
// bakes two channels of gradient noise (a sine hash, five octaves) into an rgba8unorm texture
// (`blog_bake`), derives normals from it by wrap-around differences into a second rgba8unorm
// texture (`blog_normals`), and draws a grid mesh displaced by the heights (`vs_blog`,
// `fs_blog`) with Blinn-Phong, a hard snow line and height occlusion h^3.
//
// `vs_exact` and `fs_exact` draw the same terrain without the textures: heights from the noise
// at every vertex, height, colour and the normal from the noise's value and analytic gradient at
// every fragment. That is the truth the blog's frame is scored against (its 8 bits, its normal
// pass and its lack of anti-aliasing are what the score measures).
//
// The blog's grid spans [-1, 1] with heights up its z axis; here it spans relief's tile
// (x and z in [-1, 1], y up), so that both are seen through the same camera.

struct BlogUniforms {
    view_proj: mat4x4<f32>,
    // xyz: the eye in world space.
    camera_pos: vec4<f32>,
    // xyz: unit vector towards the light.
    sun_dir: vec4<f32>,
    // World height of baked height 1, and the snow line in baked height.
    height_scale: f32,
    snow_height: f32,
    // The blog's scroll along u (its "progress"), in texture widths.
    progress: f32,
    // 1 when the colour target is not an sRGB format and the shader must encode.
    encode_srgb: u32,
    // Texture side in texels, and grid vertices per side.
    size: u32,
    grid: u32,
    _pad: vec2<u32>,
}

@group(0) @binding(0) var<uniform> blog: BlogUniforms;
@group(0) @binding(1) var noise_out: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(2) var noise_map: texture_2d<f32>;
@group(0) @binding(3) var bilinear: sampler;
@group(0) @binding(4) var normal_out: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(5) var normal_map: texture_2d<f32>;

// The blog's hash constants, one matrix and scale per channel.
const HEIGHT_MAT: mat2x2<f32> = mat2x2<f32>(231.1, 283.7, 143.8, 113.3);
const HEIGHT_SCALE: f32 = 14232.34234;
const COLOR_MAT: mat2x2<f32> = mat2x2<f32>(423.5, 342.3, 153.7, 342.5);
const COLOR_SCALE: f32 = 18473.58352;
// Octaves, and lattice cells across the texture at the first.
const OCTAVES: i32 = 5;
const BASE_FREQUENCY: f32 = 4.0;

// The gradient at lattice corner `c`: each component the sine of a pseudo-random angle made
// from the fractional part of a large multiple of sin(c * m).
fn blog_gradient(c: vec2<f32>, m: mat2x2<f32>, k: f32) -> vec2<f32> {
    let angle = -1.0 + 2.0 * fract(sin(c * m) * k);
    return sin(angle * 6.283);
}

// Gradient noise with the cubic fade at `p`: x the value, yz its gradient (the analytic
// derivative of the same expression; the bake uses the value only).
fn blog_perlin(p: vec2<f32>, m: mat2x2<f32>, k: f32) -> vec3<f32> {
    let i = floor(p);
    let f = p - i;
    let w = f * f * (3.0 - 2.0 * f);
    let dw = 6.0 * f * (1.0 - f);
    let g00 = blog_gradient(i, m, k);
    let g10 = blog_gradient(i + vec2<f32>(1.0, 0.0), m, k);
    let g01 = blog_gradient(i + vec2<f32>(0.0, 1.0), m, k);
    let g11 = blog_gradient(i + vec2<f32>(1.0, 1.0), m, k);
    let f00 = dot(g00, f);
    let f10 = dot(g10, f - vec2<f32>(1.0, 0.0));
    let f01 = dot(g01, f - vec2<f32>(0.0, 1.0));
    let f11 = dot(g11, f - vec2<f32>(1.0, 1.0));
    let x0 = mix(f00, f10, w.x);
    let x1 = mix(f01, f11, w.x);
    let d0 = mix(g00, g10, w.x) + vec2<f32>(dw.x * (f10 - f00), 0.0);
    let d1 = mix(g01, g11, w.x) + vec2<f32>(dw.x * (f11 - f01), 0.0);
    let d = mix(d0, d1, w.y) + vec2<f32>(0.0, dw.y * (x1 - x0));
    return vec3<f32>(mix(x0, x1, w.y), d);
}

// The blog's octave sum at texture coordinate `uv`, normalised by the sum of the amplitudes
// (so in about [-1, 1]): x the value, yz its gradient with respect to uv.
fn blog_fbm(uv: vec2<f32>, m: mat2x2<f32>, k: f32) -> vec3<f32> {
    var p = uv * BASE_FREQUENCY;
    var a = 1.0;
    var frequency = BASE_FREQUENCY;
    var r = vec3<f32>(0.0);
    var s = 0.0;
    for (var i = 0; i < OCTAVES; i += 1) {
        let n = blog_perlin(p, m, k);
        r += a * vec3<f32>(n.x, n.yz * frequency);
        s += a;
        p *= 2.0;
        a *= 0.5;
        frequency *= 2.0;
    }
    return r / s;
}

@compute @workgroup_size(16, 16, 1)
fn blog_bake(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= blog.size || id.y >= blog.size {
        return;
    }
    let n = f32(blog.size);
    let uv = vec2<f32>(f32(id.x) / n + blog.progress, f32(id.y) / n);
    let height = (blog_fbm(uv, HEIGHT_MAT, HEIGHT_SCALE).x + 1.0) * 0.5;
    let color = (blog_fbm(uv, COLOR_MAT, COLOR_SCALE).x + 1.0) * 0.5;
    textureStore(noise_out, vec2<i32>(id.xy), vec4<f32>(height, color, 0.0, 1.0));
}

// The blog's normal pass as published: the filtered heights one texel edge either side (with
// the texture's wrap-around at its borders), over a run of one texel per side of the grid's
// span, stored in rgba8unorm (which cannot hold the negative components).
@compute @workgroup_size(16, 16, 1)
fn blog_normals(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= blog.size || id.y >= blog.size {
        return;
    }
    let x = f32(id.x);
    let y = f32(id.y);
    let n = f32(blog.size);
    var left = vec2<f32>((x - 1.0) / n, y / n);
    var right = vec2<f32>((x + 1.0) / n, y / n);
    var down = vec2<f32>(x / n, (y - 1.0) / n);
    var up = vec2<f32>(x / n, (y + 1.0) / n);
    if x == 0.0 {
        left.x = (n - 1.0) / n;
    }
    if x == n - 1.0 {
        right.x = 0.0;
    }
    if y == n - 1.0 {
        up.y = 0.0;
    }
    if y == 0.0 {
        down.y = (n - 1.0) / n;
    }
    let l = textureSampleLevel(noise_map, bilinear, left, 0.0).r;
    let r = textureSampleLevel(noise_map, bilinear, right, 0.0).r;
    let u = textureSampleLevel(noise_map, bilinear, up, 0.0).r;
    let d = textureSampleLevel(noise_map, bilinear, down, 0.0).r;
    let dx = vec3<f32>(2.0 / n, 0.0, (r - l) * blog.height_scale);
    let dy = vec3<f32>(0.0, 2.0 / n, (u - d) * blog.height_scale);
    textureStore(normal_out, vec2<i32>(id.xy), vec4<f32>(normalize(cross(dx, dy)), 0.0));
}

struct BlogVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) height: f32,
    @location(3) color: f32,
    // Texture coordinate (the exact path shades from it).
    @location(4) uv: vec2<f32>,
}

fn blog_vertex(t: vec2<f32>, height: f32) -> BlogVertex {
    var out: BlogVertex;
    out.world = vec3<f32>(t.x * 2.0 - 1.0, height * blog.height_scale, t.y * 2.0 - 1.0);
    out.clip = blog.view_proj * vec4<f32>(out.world, 1.0);
    out.height = height;
    out.uv = t;
    return out;
}

@vertex
fn vs_blog(@builtin(vertex_index) index: u32) -> BlogVertex {
    // Grid vertex `index`, row-major, `blog.grid` per side.
    let n = blog.grid;
    let t = vec2<f32>(f32(index % n), f32(index / n)) / f32(n - 1u);
    let normal = textureSampleLevel(normal_map, bilinear, t, 0.0).xyz;
    let noise = textureSampleLevel(noise_map, bilinear, t, 0.0);
    var out = blog_vertex(t, noise.r);
    // The blog's z-up texture frame in relief's y-up world.
    out.normal = normalize(normal.xzy);
    out.color = noise.g;
    return out;
}

// The blog's palette and light: two colours mixed by the colour channel, white above the snow
// line, occlusion h^3, Blinn-Phong with ambient 0.1, shininess 1 and a light of strength 3,
// written as display values (its canvas is not sRGB).
const COLOR_1: vec3<f32> = vec3<f32>(0.13, 0.7, 0.13);
const COLOR_2: vec3<f32> = vec3<f32>(0.55, 0.194, 0.0);
const LIGHT_STRENGTH: f32 = 3.0;
const AMBIENT: f32 = 0.1;

fn decode_srgb(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(high, low, c <= vec3<f32>(0.04045));
}

fn blog_shade(world: vec3<f32>, normal: vec3<f32>, height: f32, color: f32) -> vec4<f32> {
    var albedo = mix(COLOR_1, COLOR_2, vec3<f32>(color));
    if height > blog.snow_height {
        albedo = vec3<f32>(1.0);
    }
    let occlusion = height * height * height;
    let to_eye = normalize(blog.camera_pos.xyz - world);
    let light = blog.sun_dir.xyz;
    let strength = LIGHT_STRENGTH * max(dot(light, normal), 0.0);
    let halfway = normalize(to_eye + light);
    let specular = max(dot(halfway, normal), 0.0);
    let lit = AMBIENT + (1.0 + specular) * strength;
    var shown = clamp(albedo * occlusion * lit, vec3<f32>(0.0), vec3<f32>(1.0));
    if blog.encode_srgb == 0u {
        // An sRGB target encodes what the shader writes: write what displays as the blog's.
        shown = decode_srgb(shown);
    }
    return vec4<f32>(shown, 1.0);
}

@fragment
fn fs_blog(v: BlogVertex) -> @location(0) vec4<f32> {
    return blog_shade(v.world, v.normal, v.height, v.color);
}

// Where the blog's texel centres put texture coordinate `t` in noise coordinates (texel x holds
// the noise at x / size and sits at (x + 0.5) / size), scrolled by its progress.
fn exact_uv(t: vec2<f32>) -> vec2<f32> {
    return t - vec2<f32>(0.5 / f32(blog.size)) + vec2<f32>(blog.progress, 0.0);
}

// Vertex `index` of the exact grid, drawn without an index buffer: six per cell, in the order
// of the blog's index list.
@vertex
fn vs_exact(@builtin(vertex_index) index: u32) -> BlogVertex {
    let cells = blog.grid - 1u;
    let cell = index / 6u;
    let corner = index % 6u;
    let x = cell % cells + ((0x34u >> corner) & 1u);
    let y = cell / cells + ((0x1au >> corner) & 1u);
    let t = vec2<f32>(f32(x), f32(y)) / f32(cells);
    let height = (blog_fbm(exact_uv(t), HEIGHT_MAT, HEIGHT_SCALE).x + 1.0) * 0.5;
    var out = blog_vertex(t, height);
    out.normal = vec3<f32>(0.0, 1.0, 0.0);
    out.color = 0.0;
    return out;
}

@fragment
fn fs_exact(v: BlogVertex) -> @location(0) vec4<f32> {
    let uv = exact_uv(v.uv);
    let h = blog_fbm(uv, HEIGHT_MAT, HEIGHT_SCALE);
    let color = (blog_fbm(uv, COLOR_MAT, COLOR_SCALE).x + 1.0) * 0.5;
    // World x and z run twice as fast as u and v; heights are half the noise times the scale.
    let slope = h.yz * 0.25 * blog.height_scale;
    let normal = normalize(vec3<f32>(-slope.x, 1.0, -slope.y));
    return blog_shade(v.world, normal, (h.x + 1.0) * 0.5, color);
}
