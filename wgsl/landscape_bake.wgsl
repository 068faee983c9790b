// Landscape bake pass: one invocation per sample of a rectangle of a level (or a region)
// writes (height, dh/dx, dh/dz, colour channel) at toroidal (wrapping) texel addresses, so a
// moving level bakes only the rows and columns the camera uncovers: into an rgba32float
// texture-array layer for region bakes read back whole (`landscape_bake_main`), or packed
// into rg32uint for the levels the renderer draws from (`landscape_bake_levels`,
// level_texel.wgsl). Composed after noise.wgsl, landscape.wgsl and level_texel.wgsl.

@group(0) @binding(0) var<uniform> land: LandscapeUniforms;
@group(0) @binding(1) var region_out: texture_storage_2d_array<rgba32float, write>;
@group(0) @binding(2) var level_out: texture_storage_2d_array<rg32uint, write>;

// The sample of invocation `id` and the texel it goes to; false outside the rectangle.
fn bake_target(id: vec2<u32>, s: ptr<function, vec2<i32>>, dest: ptr<function, vec2<u32>>) -> bool {
    if id.x >= land.extent.x || id.y >= land.extent.y {
        return false;
    }
    *s = land.origin + vec2<i32>(id);
    *dest = (land.dest_origin + id) % vec2<u32>(land.wrap);
    return true;
}

@compute @workgroup_size(8, 8, 1)
fn landscape_bake_main(@builtin(global_invocation_id) id: vec3<u32>) {
    var s: vec2<i32>;
    var dest: vec2<u32>;
    if bake_target(id.xy, &s, &dest) {
        textureStore(region_out, vec2<i32>(dest), i32(land.layer), landscape_samples(s, land));
    }
}

@compute @workgroup_size(8, 8, 1)
fn landscape_bake_levels(@builtin(global_invocation_id) id: vec3<u32>) {
    var s: vec2<i32>;
    var dest: vec2<u32>;
    if bake_target(id.xy, &s, &dest) {
        let packed = pack_level_texel(landscape_samples(s, land), land.level_log2);
        textureStore(level_out, vec2<i32>(dest), i32(land.layer), vec4<u32>(packed, 0u, 0u));
    }
}
