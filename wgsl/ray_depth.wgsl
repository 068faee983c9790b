// import: fullscreen
// The depth of a ray cast for the layers drawn over it (src/gpu/ray_layers.rs): each pixel's
// distance along its unit ray (rays.wgsl's `distance` target: -1 for the sky, -2 unresolved)
// becomes the depth the layers' own matrix gives that point, so a layer rasterised after the
// cast is depth-tested against the surface the cast found. The sky and unresolved pixels are
// at the far plane.

struct RayDepthUniforms {
    // Inverse of the cast's camera-relative projection times view: a pixel's ray, as
    // `pixel_far` in march.wgsl finds it.
    inv_ray: mat4x4<f32>,
    // The layers' camera-relative projection times view (the eye at the origin).
    layer: mat4x4<f32>,
    // The cast's size in pixels.
    size: vec2<f32>,
    pad: vec2<f32>,
}

@group(0) @binding(0) var<uniform> u: RayDepthUniforms;
@group(0) @binding(1) var distance: texture_2d<f32>;

@vertex
fn depth_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_xy(i), 0.0, 1.0);
}

@fragment
fn depth_fs(@builtin(position) position: vec4<f32>) -> @builtin(frag_depth) f32 {
    let t = textureLoad(distance, vec2<i32>(position.xy), 0).x;
    if t < 0.0 {
        return 1.0;
    }
    let ndc = vec2<f32>(2.0 * position.x / u.size.x - 1.0, 1.0 - 2.0 * position.y / u.size.y);
    let far = u.inv_ray * vec4<f32>(ndc, 1.0, 1.0);
    let p = normalize(far.xyz / far.w) * t;
    let clip = u.layer * vec4<f32>(p, 1.0);
    return clamp(clip.z / clip.w, 0.0, 1.0);
}
