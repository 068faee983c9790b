// import: march, fullscreen
// part of: raymarch, world_rays_io (each defines the caster it calls)
// The ray casters' entry points, shared by the tile's (raymarch.wgsl) and the endless world's
// (world_rays.wgsl) casters, composed after either and march.wgsl: a compute shader writing
// storage textures and a full-screen fragment shader writing two colour targets. The caster's
// files declare `color_out`, `distance_out` and `cast_pixel(pixel) -> (colour, distance)`.

// Each colour goes through `unorm8_exact` (shade.wgsl) before an 8-bit store.

@compute @workgroup_size(8, 8, 1)
fn raymarch_cs(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= ray.width || id.y >= ray.height {
        return;
    }
    let c = cast_pixel(vec2<f32>(id.xy) + 0.5);
    textureStore(color_out, vec2<i32>(id.xy), vec4<f32>(unorm8_exact(c.rgb), 1.0));
    textureStore(distance_out, vec2<i32>(id.xy), vec4<f32>(c.w, 0.0, 0.0, 0.0));
}

@vertex
fn fullscreen_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_xy(i), 0.0, 1.0);
}

struct FragmentOut {
    @location(0) color: vec4<f32>,
    @location(1) distance: vec4<f32>,
}

@fragment
fn raymarch_fs(@builtin(position) position: vec4<f32>) -> FragmentOut {
    let c = cast_pixel(position.xy);
    var out: FragmentOut;
    out.color = vec4<f32>(unorm8_exact(c.rgb), 1.0);
    out.distance = vec4<f32>(c.w, 0.0, 0.0, 0.0);
    return out;
}
