// Normal pass: wrap-around central differences of the baked heights into a signed
// rgba16float normal map (xyz = unit normal, y up; w unused). The tile is periodic, so the
// neighbours of an edge texel are on the opposite edge.

struct NormalUniforms {
    size: u32,
    _pad: u32,
    // World height of normalised height 1.
    height_scale: f32,
    // World distance between neighbouring texels.
    texel_world: f32,
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
