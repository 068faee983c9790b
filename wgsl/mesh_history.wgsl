// import: shade, composite
// The forward mesh through the temporal service (src/gpu/world/mesh_history.rs): the mesh and
// its sky are drawn, jittered, into relief's own image (linear colour, the host's samples);
// `copy_depth` keeps each pixel's nearest sample's depth for the resolve (temporal.wgsl),
// which reads depth as a float image; the composite (composite.wgsl) puts the history the
// resolve wrote into the host's pass, colour and depth.

struct MeshHistoryUniforms {
    size: vec2<u32>,
    // 1 where the host's target is not an sRGB format and the composite encodes.
    encode_srgb: u32,
    _pad: u32,
}

@group(0) @binding(12) var<uniform> m: MeshHistoryUniforms;

fn composite_encodes() -> bool {
    return m.encode_srgb != 0u;
}

@group(0) @binding(15) var mesh_depth: texture_depth_2d;
@group(0) @binding(16) var depth_out: texture_storage_2d<r32float, write>;
@group(0) @binding(17) var mesh_depth_ms: texture_depth_multisampled_2d;

@compute @workgroup_size(8, 8)
fn copy_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= m.size.x || id.y >= m.size.y {
        return;
    }
    textureStore(depth_out, id.xy, vec4<f32>(textureLoad(mesh_depth, id.xy, 0), 0.0, 0.0, 0.0));
}

// The nearest of a pixel's samples (the visibility method keeps the same).
@compute @workgroup_size(8, 8)
fn copy_depth_samples(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= m.size.x || id.y >= m.size.y {
        return;
    }
    var d = 1.0;
    for (var s = 0u; s < textureNumSamples(mesh_depth_ms); s++) {
        d = min(d, textureLoad(mesh_depth_ms, id.xy, i32(s)));
    }
    textureStore(depth_out, id.xy, vec4<f32>(d, 0.0, 0.0, 0.0));
}
