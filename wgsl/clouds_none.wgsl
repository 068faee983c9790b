// instead of: clouds, clouds_seen (shader::source_for, where the frame has no clouds)
// What clouds.wgsl gives at no coverage, without its march: no cloud along any ray and no
// shadow. The march is most of the time a shading pipeline takes to build, so the pipelines
// built while the frame has no clouds are built from this, and again from clouds.wgsl when
// they are turned on (src/gpu/world/mod.rs, `build_visibility`).

fn clouds_along(r: RenderUniforms, dir: vec3<f32>, far: f32) -> CloudLight {
    return cloud_none();
}

fn cloud_shadow(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    return 1.0;
}

fn cloud_shafts(r: RenderUniforms, dir: vec3<f32>, far: f32) -> f32 {
    return 1.0;
}
