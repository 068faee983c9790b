// part of: shade (through clouds.wgsl, which imports it)
// The clouds along a view ray and their shadows as the shading sees them: here marched, for
// every pixel every frame (the reference's way, and wherever a frame keeps no clouds' image);
// where the visibility method keeps the image, clouds_image.wgsl stands in for this file
// (shader::source_for).

// What the clouds between the eye and `far` along unit `dir` do (`CloudLight`, shade.wgsl).
fn clouds_along(r: RenderUniforms, dir: vec3<f32>, far: f32) -> CloudLight {
    return cloud_march(r, dir, far, u32(r.cloud_march.y)).seen;
}

// The light of the sun that the clouds let through to camera-relative `rel` (1 without
// clouds): the shadows they cast on everything lit.
fn cloud_shadow(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    return cloud_shadow_march(r, rel);
}

// The sun's light the clouds let through to camera-relative `rel` in the air, for the light
// shafts (`cloud_shafts`): their shadow's march in one sample, halfway through the layer.
fn cloud_shadow_air(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    return cloud_shadow_steps(r, rel, 1u);
}

// The light shafts' points along a view ray (`cloud_shafts`), each a march towards the sun.
fn cloud_shaft_steps() -> u32 {
    return 6u;
}
