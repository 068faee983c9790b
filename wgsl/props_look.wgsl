// import: shade
// What the props' march (props_march.wgsl) leaves a pixel for the shading (visibility.wgsl),
// and how a prop's surface is lit there: the terrain's light (shade.wgsl's sky, sun and air)
// on a rough, matte stone.

// A unit vector in two numbers in [-1, 1] (the octahedron folded flat) and back.
fn oct_encode(n: vec3<f32>) -> vec2<f32> {
    let p = n.xz / (abs(n.x) + abs(n.y) + abs(n.z));
    if n.y >= 0.0 {
        return p;
    }
    return (1.0 - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
}

fn oct_decode(e: vec2<f32>) -> vec3<f32> {
    var n = vec3<f32>(e.x, 1.0 - abs(e.x) - abs(e.y), e.y);
    let t = max(-n.y, 0.0);
    n.x += select(t, -t, n.x >= 0.0);
    n.z += select(t, -t, n.z >= 0.0);
    return normalize(n);
}

// No prop at a pixel: its depth (the far plane, behind everything), the sky unoccluded (bits)
// and the sun unshadowed (bits). The march leaves the props' occlusion of the sky and their
// shadow on the surface the raster drew in the same places.
fn no_prop() -> vec4<u32> {
    return vec4<u32>(bitcast<u32>(1.0), bitcast<u32>(1.0), 0u, bitcast<u32>(1.0));
}

// The light leaving a prop's surface at camera-relative `rel` with normal `n`, linear
// `albedo`, the sky's share `ao` and the sun's `sun`, through the air, for `lin`.
fn prop_light(lin: RenderUniforms, rel: vec3<f32>, n: vec3<f32>, albedo: vec3<f32>, ao: f32, sun: f32) -> vec3<f32> {
    let l = lin.sun_dir.xyz;
    let v = normalize(lin.camera_pos.xyz - rel);
    let sky = lin.ambient_color.rgb * (0.75 + 0.25 * n.y);
    let away = vec3<f32>(-l.x, 0.0, -l.z);
    let back = lin.sun_color.rgb * 0.1 * max(dot(n, away / max(length(away), 1e-4)), 0.0);
    let ndl = max(dot(n, l), 0.0);
    let half_vec = normalize(l + v);
    let spec = 0.04 * pow(max(dot(n, half_vec), 0.0), 24.0) * ndl;
    let rim = lin.sky_horizon.rgb * 0.2 * pow(1.0 - clamp(dot(n, v), 0.0, 1.0), 5.0);
    let sunlight = lin.sun_color.rgb * (sun * cloud_shadow(lin, rel));
    let lit = albedo * ((sky + back) * ao + sunlight * ndl) + rim * ao + sunlight * spec;
    let air = air_at(lin, rel);
    return to_target(lin, lit * air.keep + air.light);
}

// The colour of the prop the march left in `hit` at camera-relative `rel`.
fn prop_color(lin: RenderUniforms, rel: vec3<f32>, hit: vec4<u32>) -> vec3<f32> {
    let n = oct_decode(unpack2x16snorm(hit.y));
    let look = unpack4x8unorm(hit.z);
    return prop_light(lin, rel, n, look.rgb * look.rgb, look.a, bitcast<f32>(hit.w));
}
