// import: landscape, level_texel
// Landscape bake pass: one invocation per sample of a rectangle of a level (or a region)
// writes (height, dh/dx, dh/dz, colour channel) at toroidal (wrapping) texel addresses, so a
// moving level bakes only the rows and columns the camera uncovers: into an rgba32float
// texture-array layer for region bakes read back whole (`landscape_bake_main`), or packed
// into rg32uint for the levels the renderer draws from (`landscape_bake_levels`,
// level_texel.wgsl). Composed after noise.wgsl, landscape.wgsl and level_texel.wgsl.

@group(0) @binding(0) var<uniform> land: LandscapeUniforms;
@group(0) @binding(1) var region_out: texture_storage_2d_array<rgba32float, write>;
@group(0) @binding(2) var level_out: texture_storage_2d_array<rg32uint, write>;

// Each invocation bakes a 2x2 quad of samples (landscape_samples_quad): the quads lie on even
// world sample coordinates, from the rectangle's origin rounded down, and the samples of a
// quad outside the rectangle are not written.

// The first sample of invocation `id`'s quad; false when the whole quad is past the rectangle.
fn quad_origin(id: vec2<u32>, s: ptr<function, vec2<i32>>) -> bool {
    *s = (land.origin & vec2<i32>(-2)) + 2 * vec2<i32>(id);
    let r = *s - land.origin;
    return all(r < vec2<i32>(land.extent));
}

// Where sample `s` goes; false outside the rectangle.
fn bake_target(s: vec2<i32>, dest: ptr<function, vec2<u32>>) -> bool {
    let r = s - land.origin;
    if any(r < vec2<i32>(0)) || any(r >= vec2<i32>(land.extent)) {
        return false;
    }
    *dest = (land.dest_origin + vec2<u32>(r)) % vec2<u32>(land.wrap);
    return true;
}

@compute @workgroup_size(8, 8, 1)
fn landscape_bake_main(@builtin(global_invocation_id) id: vec3<u32>) {
    var s: vec2<i32>;
    if !quad_origin(id.xy, &s) {
        return;
    }
    let samples = landscape_samples_quad(s, land);
    for (var k = 0u; k < 4u; k++) {
        var dest: vec2<u32>;
        if bake_target(s + quad_offset(k), &dest) {
            textureStore(region_out, vec2<i32>(dest), i32(land.layer), samples[k]);
        }
    }
}

@compute @workgroup_size(8, 8, 1)
fn landscape_bake_levels(@builtin(global_invocation_id) id: vec3<u32>) {
    var s: vec2<i32>;
    if !quad_origin(id.xy, &s) {
        return;
    }
    let samples = landscape_samples_quad(s, land);
    for (var k = 0u; k < 4u; k++) {
        var dest: vec2<u32>;
        if bake_target(s + quad_offset(k), &dest) {
            let packed = pack_level_texel(samples[k], land.level_log2);
            textureStore(level_out, vec2<i32>(dest), i32(land.layer), vec4<u32>(packed, 0u, 0u));
        }
    }
}
