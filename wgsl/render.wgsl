// Render pass: a G x G grid drawn as G-1 instanced triangle strips (no vertex or index
// buffers), displaced by the baked heights; per-pixel normals from the normal map, shaded by
// shade.wgsl (composed before this file). The textures are read `r.shift` tiles on from where
// they were baked (wrapping: the tile is periodic), so the scroll animation bakes nothing.

@group(0) @binding(0) var<uniform> r: RenderUniforms;
@group(0) @binding(1) var terrain: texture_2d<f32>;
@group(0) @binding(2) var normal_map: texture_2d<f32>;
@group(0) @binding(3) var normal_sampler: sampler;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) uv: vec2<f32>,
    // x: normalised height, y: colour channel.
    @location(2) terrain: vec2<f32>,
}

fn wrap(i: i32, n: i32) -> i32 {
    return ((i % n) + n) % n;
}

// Bilinear, wrap-around read of the rg32float terrain texture by hand: core WebGPU cannot
// filter 32-bit floats. Texel centres sit at (i + 0.5) / size, as in the bake.
fn terrain_at(uv: vec2<f32>) -> vec2<f32> {
    let n = i32(r.tex_size);
    let s = uv * f32(n) - 0.5;
    let s0 = floor(s);
    let t = s - s0;
    let x0 = wrap(i32(s0.x), n);
    let y0 = wrap(i32(s0.y), n);
    let x1 = wrap(x0 + 1, n);
    let y1 = wrap(y0 + 1, n);
    let a = textureLoad(terrain, vec2<i32>(x0, y0), 0).rg;
    let b = textureLoad(terrain, vec2<i32>(x1, y0), 0).rg;
    let c = textureLoad(terrain, vec2<i32>(x0, y1), 0).rg;
    let d = textureLoad(terrain, vec2<i32>(x1, y1), 0).rg;
    return mix(mix(a, b, t.x), mix(c, d, t.x), t.y);
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) row: u32) -> VertexOut {
    let cells = f32(r.grid - 1u);
    let ij = vec2<u32>(vi >> 1u, row + (vi & 1u));
    let uv = vec2<f32>(ij) / cells;
    let t = terrain_at(uv + r.shift);
    let world = vec3<f32>((uv.x - 0.5) * WORLD_SIZE, t.x * r.height_scale, (uv.y - 0.5) * WORLD_SIZE);
    var out: VertexOut;
    out.clip = r.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.uv = uv;
    out.terrain = t;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(textureSampleLevel(normal_map, normal_sampler, in.uv + r.shift, 0.0).xyz);
    // Height (for snow and AO) and the colour channel per pixel, not per vertex: a coarse grid
    // would otherwise smear the colour noise and the snow line (the benchmark measures this).
    let t = terrain_at(in.uv + r.shift);
    return vec4<f32>(shade(r, in.world, n, t.x, t.y, unshadowed(r, t.x)), 1.0);
}
