// import: shade
// The test layer: a box standing on the terrain, drawn into the host's pass after the terrain
// with the frame's camera-relative matrix, depth-tested, lit by the frame's sun and ambient
// light. 36 vertices from the vertex index, no vertex buffer.

@group(0) @binding(0) var<uniform> r: RenderUniforms;

struct BoxUniforms {
    // xyz: the box's centre relative to the eye, metres.
    center: vec4<f32>,
    // xyz: half its size along x, y and z, metres.
    half_size: vec4<f32>,
    // rgb: its linear albedo.
    albedo: vec4<f32>,
}

@group(0) @binding(1) var<uniform> b: BoxUniforms;

struct BoxOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> BoxOut {
    // Six faces of two triangles; face f lies across axis f / 2, on its -1 side for even f.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let face = i / 6u;
    let c = corners[i % 6u];
    let side = select(-1.0, 1.0, (face & 1u) == 1u);
    let axis = face / 2u;
    var p = vec3<f32>(side, c.x, c.y);
    var n = vec3<f32>(side, 0.0, 0.0);
    if axis == 1u {
        p = vec3<f32>(c.y, side, c.x);
        n = vec3<f32>(0.0, side, 0.0);
    } else if axis == 2u {
        p = vec3<f32>(c.x, c.y, side);
        n = vec3<f32>(0.0, 0.0, side);
    }
    var out: BoxOut;
    out.clip = r.view_proj * vec4<f32>(b.center.xyz + p * b.half_size.xyz, 1.0);
    out.normal = n;
    return out;
}

@fragment
fn fs_main(in: BoxOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let light = r.ambient_color.rgb + r.sun_color.rgb * max(dot(n, r.sun_dir.xyz), 0.0);
    var c = b.albedo.rgb * light;
    if r.encode_srgb == 1u {
        c = srgb_encode(c);
    }
    return vec4<f32>(c, 1.0);
}
