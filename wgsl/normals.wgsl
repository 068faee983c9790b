// import: noise
// Normal pass: a signed rgba16float normal map (xyz = unit normal, y up; w unused) by one of
// two methods. 0: wrap-around central differences of the baked heights (the tile is periodic,
// so the neighbours of an edge texel are on the opposite edge). 1: the analytic gradient of the
// fBm at the texel centre (composed after noise.wgsl).

struct NormalUniforms {
    size: u32,
    method: u32,
    // World height of normalised height 1.
    height_scale: f32,
    // World distance between neighbouring texels.
    texel_world: f32,
    frequency: u32,
    octaves: u32,
    seed: u32,
    gain: f32,
    // Scroll offset in tiles, reduced to [0, 1).
    offset: vec2<f32>,
    _pad: vec2<u32>,
}

@group(0) @binding(0) var<uniform> normals: NormalUniforms;
@group(0) @binding(1) var terrain_in: texture_2d<f32>;
@group(0) @binding(2) var normal_out: texture_storage_2d<rgba16float, write>;

fn height(x: u32, y: u32) -> f32 {
    return textureLoad(terrain_in, vec2<u32>(x, y), 0).r;
}

@compute @workgroup_size(8, 8, 1)
fn normals_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = normals.size;
    if id.x >= n || id.y >= n {
        return;
    }
    if normals.method == 1u {
        let u = (vec2<f32>(id.xy) + 0.5) / f32(n);
        let g = fbm_grad(u, normals.frequency, normals.octaves, normals.octaves, normals.gain, normals.offset, normals.seed, CHANNEL_HEIGHT);
        // World x = (u - 0.5) * WORLD_SIZE, and WORLD_SIZE = size * texel_world.
        let slope = g.yz * normals.height_scale / (f32(n) * normals.texel_world);
        textureStore(normal_out, vec2<i32>(id.xy), vec4<f32>(normalize(vec3<f32>(-slope.x, 1.0, -slope.y)), 0.0));
        return;
    }
    let xl = (id.x + n - 1u) % n;
    let xr = (id.x + 1u) % n;
    let yd = (id.y + n - 1u) % n;
    let yu = (id.y + 1u) % n;
    let k = normals.height_scale / (2.0 * normals.texel_world);
    let dhdx = k * (height(xr, id.y) - height(xl, id.y));
    let dhdz = k * (height(id.x, yu) - height(id.x, yd));
    let normal = normalize(vec3<f32>(-dhdx, 1.0, -dhdz));
    textureStore(normal_out, vec2<i32>(id.xy), vec4<f32>(normal, 0.0));
}
