// Bake pass: one invocation per texel writes normalised height (r) and the albedo-mix
// channel (g) into an rg32float storage texture. Composed after noise.wgsl.

struct BakeUniforms {
    size: u32,
    frequency: u32,
    octaves: u32,
    seed: u32,
    gain: f32,
    _pad: u32,
    // Scroll offset in tiles, reduced to [0, 1) on the CPU in f64.
    offset: vec2<f32>,
}

@group(0) @binding(0) var<uniform> bake: BakeUniforms;
@group(0) @binding(1) var terrain_out: texture_storage_2d<rg32float, write>;

@compute @workgroup_size(8, 8, 1)
fn bake_main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= bake.size || id.y >= bake.size {
        return;
    }
    let t = fbm_texel(id.xy, bake.size, bake.frequency, bake.octaves, bake.gain, bake.offset, bake.seed);
    textureStore(terrain_out, vec2<i32>(id.xy), vec4<f32>(t, 0.0, 1.0));
}
