// import: fullscreen
// part of: visibility, mesh_history (each defines `composite_encodes` and imports shade)
// The composite of an image that relief shaded or accumulated into the host's render pass: one
// full-screen triangle; each pixel takes its colour (premultiplied linear colour and coverage,
// blended over what is there by its coverage where there is no sky) and its depth (1 for sky,
// which the host's less-or-equal test lets through only where nothing was drawn).
@group(0) @binding(13) var shown: texture_2d<f32>;
@group(0) @binding(14) var shown_depth: texture_2d<f32>;

@vertex
fn composite_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_xy(i), 0.0, 1.0);
}

struct CompositeOut {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

fn composite_color(c: vec4<f32>) -> vec4<f32> {
    if !composite_encodes() || c.a <= 0.0 {
        return c;
    }
    return vec4<f32>(srgb_encode(c.rgb / c.a) * c.a, c.a);
}

@fragment
fn composite_fs(@builtin(position) position: vec4<f32>) -> CompositeOut {
    let px = vec2<i32>(floor(position.xy));
    let c = textureLoad(shown, px, 0);
    if c.a <= 0.0 {
        discard;
    }
    var out: CompositeOut;
    out.color = composite_color(c);
    out.depth = textureLoad(shown_depth, px, 0).x;
    return out;
}

// The same for a host pass without depth.
@fragment
fn composite_fs_color(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(shown, vec2<i32>(floor(position.xy)), 0);
    if c.a <= 0.0 {
        discard;
    }
    return composite_color(c);
}
