// part of: shade (through clouds.wgsl, which imports it)
// The clouds along a view ray as the shading sees them: here the march itself, for every pixel
// every frame (the reference's way, and wherever a frame keeps no clouds' image); where the
// visibility method keeps the image, clouds_image.wgsl stands in for this file
// (shader::source_for).

// What the clouds between the eye and `far` along unit `dir` do (`CloudLight`, shade.wgsl).
fn clouds_along(r: RenderUniforms, dir: vec3<f32>, far: f32) -> CloudLight {
    return cloud_march(r, dir, far, u32(r.cloud_march.y)).seen;
}
