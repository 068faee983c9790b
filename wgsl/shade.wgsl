// Shading shared by every way relief draws terrain (the mesh in render.wgsl, the ray casters
// in raymarch.wgsl): Blinn-Phong under a directional sun, two-colour albedo, a noise-jittered
// snow line and height ambient occlusion h^k. Composed before the file that uses it.

struct RenderUniforms {
    view_proj: mat4x4<f32>,
    // xyz: camera position in world space.
    camera_pos: vec4<f32>,
    // xyz: unit vector towards the sun.
    sun_dir: vec4<f32>,
    // rgb: linear sun radiance.
    sun_color: vec4<f32>,
    // rgb: linear ambient (sky) radiance.
    ambient_color: vec4<f32>,
    // Linear albedos: low and high end of the colour channel, and snow.
    color_a: vec4<f32>,
    color_b: vec4<f32>,
    snow_color: vec4<f32>,
    height_scale: f32,
    snow_height: f32,
    ao_exponent: f32,
    shininess: f32,
    grid: u32,
    tex_size: u32,
    // 1 when the colour target is not an sRGB format and the shader must encode.
    encode_srgb: u32,
    specular: f32,
    // The tile's texture reads less where it was baked, in tiles: the scroll without a bake.
    shift: vec2<f32>,
    _pad_shift: vec2<u32>,
}

// World width of the tile (x and z span [-WORLD_SIZE/2, WORLD_SIZE/2]); see crate::WORLD_SIZE.
const WORLD_SIZE: f32 = 2.0;
// Half-width of the snow line's smooth edge and the amplitude of its noise jitter,
// in normalised height.
const SNOW_EDGE: f32 = 0.025;
const SNOW_JITTER: f32 = 0.12;


fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

// Colour of terrain at `world` with unit normal `n`, normalised height `h` and colour channel
// `tint`, ready to store in the target (sRGB-encoded when the target is not an sRGB format).
fn shade(r: RenderUniforms, world: vec3<f32>, n: vec3<f32>, h: f32, tint: f32) -> vec3<f32> {
    var albedo = mix(r.color_a.rgb, r.color_b.rgb, smoothstep(0.2, 0.8, tint));
    // Snow above the snow height, its edge jittered by the colour noise so it does not follow
    // a contour line, and thinning on steep slopes where it would not settle.
    let line = r.snow_height + (tint - 0.5) * SNOW_JITTER;
    let snow = smoothstep(line - SNOW_EDGE, line + SNOW_EDGE, h) * smoothstep(0.45, 0.75, n.y);
    albedo = mix(albedo, r.snow_color.rgb, snow);

    // Valleys (low h) get less sky and less sun.
    let ao = pow(max(h, 1e-4), r.ao_exponent);

    let l = r.sun_dir.xyz;
    let v = normalize(r.camera_pos.xyz - world);
    let half_vec = normalize(l + v);
    let ndl = max(dot(n, l), 0.0);
    let spec = select(0.0, pow(max(dot(n, half_vec), 0.0), r.shininess), ndl > 0.0);
    let lit = albedo * (r.ambient_color.rgb + r.sun_color.rgb * ndl) * ao
        + r.sun_color.rgb * (spec * r.specular * (0.3 + 0.7 * snow) * ao);

    var color = clamp(lit, vec3<f32>(0.0), vec3<f32>(1.0));
    if r.encode_srgb != 0u {
        color = srgb_encode(color);
    }
    return color;
}
