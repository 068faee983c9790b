// import: vis_common, props_look, fullscreen
// The props drawn over a frame whose method does not march them (src/gpu/props_overlay.rs):
// the march (props_march.wgsl, with no raster's depth) left each pixel's nearest prop in an
// image; one full-screen triangle in the host's pass shades each pixel that holds one, with the
// terrain's light, air and tone curve, and writes its depth, which the host's depth test keeps
// where nothing nearer was drawn (the terrain, a host's geometry).

@group(0) @binding(0) var<uniform> r: RenderUniforms;
@group(0) @binding(22) var overlay_hit: texture_2d<u32>;

@vertex
fn overlay_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_xy(i), 0.0, 1.0);
}

struct OverlayOut {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn overlay_fs(@builtin(position) position: vec4<f32>) -> OverlayOut {
    let hit = textureLoad(overlay_hit, vec2<i32>(floor(position.xy)), 0);
    let d = bitcast<f32>(hit.x);
    if d >= 1.0 {
        discard;
    }
    let rel = point_at(sample_ray(position.xy), d);
    var out: OverlayOut;
    out.color = vec4<f32>(prop_color(r, rel, hit), 1.0);
    out.depth = d;
    return out;
}
