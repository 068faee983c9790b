// import: shade, fullscreen
// with: terrain_air_map
// The sky pass: one full-screen triangle at the far plane (depth 1), drawn after the terrain
// with a less-or-equal depth test, so it fills exactly the pixels nothing nearer covered (or
// before the terrain where the host's pass has no depth). Each pixel shows `sky_pixel` (from
// shade.wgsl, composed before this) along its view direction: the same sky a missed ray shows.

@group(0) @binding(0) var<uniform> r: RenderUniforms;

struct SkyOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> SkyOut {
    let xy = fullscreen_xy(i);
    var out: SkyOut;
    out.clip = vec4<f32>(xy, 1.0, 1.0);
    out.ndc = xy;
    return out;
}

@fragment
fn fs_main(in: SkyOut) -> @location(0) vec4<f32> {
    let far = r.inv_view_proj * vec4<f32>(in.ndc, 1.0, 1.0);
    let dir = normalize(far.xyz / far.w - r.camera_pos.xyz);
    return vec4<f32>(sky_pixel(r, dir), 1.0);
}
