// Landscape bake pass: one invocation per sample of a rectangle of a level (or a region)
// writes (height, dh/dx, dh/dz, colour channel) into an rgba32float texture-array layer, at
// toroidal (wrapping) texel addresses, so a moving level bakes only the rows and columns the
// camera uncovers. Composed after noise.wgsl and landscape.wgsl.

@group(0) @binding(0) var<uniform> land: LandscapeUniforms;
@group(0) @binding(1) var level_out: texture_storage_2d_array<rgba32float, write>;

@compute @workgroup_size(8, 8, 1)
fn landscape_bake_main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= land.extent.x || id.y >= land.extent.y {
        return;
    }
    let s = land.origin + vec2<i32>(id.xy);
    let dest = (land.dest_origin + id.xy) % vec2<u32>(land.wrap);
    textureStore(level_out, vec2<i32>(dest), i32(land.layer), landscape_samples(s, land));
}
