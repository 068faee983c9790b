// Render pass: a G x G grid drawn as G-1 instanced triangle strips (no vertex or index
// buffers), displaced by the baked heights; per-pixel normals from the normal map;
// Blinn-Phong under a directional sun, two-colour albedo, a noise-jittered snow line and
// height ambient occlusion h^k.

struct RenderUniforms {
    view_proj: mat4x4<f32>,
    // xyz: camera position in world space.
    camera_pos: vec4<f32>,
    // xyz: unit vector towards the sun.
    sun_dir: vec4<f32>,
    // rgb: linear sun radiance.
    sun_color: vec4<f32>,
    // rgb: linear ambient (sky) radiance.
    ambient_color: vec4<f32>,
    // Linear albedos: low and high end of the colour channel, and snow.
    color_a: vec4<f32>,
    color_b: vec4<f32>,
    snow_color: vec4<f32>,
    height_scale: f32,
    snow_height: f32,
    ao_exponent: f32,
    shininess: f32,
    grid: u32,
    tex_size: u32,
    // 1 when the colour target is not an sRGB format and the shader must encode.
    encode_srgb: u32,
    specular: f32,
}

// World width of the tile (x and z span [-WORLD_SIZE/2, WORLD_SIZE/2]); see crate::WORLD_SIZE.
const WORLD_SIZE: f32 = 2.0;
// Half-width of the snow line's smooth edge and the amplitude of its noise jitter,
// in normalised height.
const SNOW_EDGE: f32 = 0.025;
const SNOW_JITTER: f32 = 0.12;

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
    let t = terrain_at(uv);
    let world = vec3<f32>((uv.x - 0.5) * WORLD_SIZE, t.x * r.height_scale, (uv.y - 0.5) * WORLD_SIZE);
    var out: VertexOut;
    out.clip = r.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.uv = uv;
    out.terrain = t;
    return out;
}

fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(textureSampleLevel(normal_map, normal_sampler, in.uv, 0.0).xyz);
    let h = in.terrain.x;
    let tint = in.terrain.y;

    var albedo = mix(r.color_a.rgb, r.color_b.rgb, smoothstep(0.2, 0.8, tint));
    // Snow above the snow height, its edge jittered by the colour noise so it does not follow
    // a contour line, and thinning on steep slopes where it would not settle.
    let line = r.snow_height + (tint - 0.5) * SNOW_JITTER;
    let snow = smoothstep(line - SNOW_EDGE, line + SNOW_EDGE, h) * smoothstep(0.45, 0.75, n.y);
    albedo = mix(albedo, r.snow_color.rgb, snow);

    // Valleys (low h) get less sky and less sun.
    let ao = pow(max(h, 1e-4), r.ao_exponent);

    let l = r.sun_dir.xyz;
    let v = normalize(r.camera_pos.xyz - in.world);
    let half_vec = normalize(l + v);
    let ndl = max(dot(n, l), 0.0);
    let spec = select(0.0, pow(max(dot(n, half_vec), 0.0), r.shininess), ndl > 0.0);
    let lit = albedo * (r.ambient_color.rgb + r.sun_color.rgb * ndl) * ao
        + r.sun_color.rgb * (spec * r.specular * (0.3 + 0.7 * snow) * ao);

    var color = clamp(lit, vec3<f32>(0.0), vec3<f32>(1.0));
    if r.encode_srgb != 0u {
        color = srgb_encode(color);
    }
    return vec4<f32>(color, 1.0);
}
