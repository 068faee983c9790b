// Shading shared by every way relief draws terrain (the mesh in render.wgsl and world.wgsl, the
// ray casters in raymarch.wgsl and world_rays.wgsl, the sky pass in sky.wgsl): Blinn-Phong under
// a directional sun, two-colour albedo, a noise-jittered snow line and height ambient occlusion
// h^k, seen through the air (aerial perspective), in front of the sky. Composed before the file
// that uses it. The sky and the fog are an analytic model whose CPU twin is src/sky.rs.

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
    // Inverse of view_proj: pixels to view directions for the sky.
    inv_view_proj: mat4x4<f32>,
    // Linear sky at the zenith (w: 1 for a flat sky of sky_horizon's colour) and the horizon.
    sky_zenith: vec4<f32>,
    sky_horizon: vec4<f32>,
    // A low sun's glow on the horizon towards it, and its strength in w.
    sky_sunset: vec4<f32>,
    // rgb: extinction per world unit (0: clear air).
    fog: vec4<f32>,
    // x, y: horizontal distance where terrain begins and finishes fading into the sky (y = 0:
    // no fade).
    fade: vec4<f32>,
}

// World width of the tile (x and z span [-WORLD_SIZE/2, WORLD_SIZE/2]); see crate::WORLD_SIZE.
const WORLD_SIZE: f32 = 2.0;
// Half-width of the snow line's smooth edge and the amplitude of its noise jitter,
// in normalised height.
const SNOW_EDGE: f32 = 0.025;
const SNOW_JITTER: f32 = 0.12;


// The sky model's constants (src/sky.rs has the same): the sun disc's angular radius and how
// fast the horizon's haze gives way to the zenith colour.
const SUN_RADIUS: f32 = 0.008726646;
const HAZE_FALLOFF: f32 = 8.0;

fn pow_n(x: f32, n: u32) -> f32 {
    var y = 1.0;
    var b = x;
    var k = n;
    while k > 0u {
        if (k & 1u) != 0u {
            y *= b;
        }
        b *= b;
        k >>= 1u;
    }
    return y;
}

// Linear radiance of the sky along unit `dir`, with the sun's disc or without it (what the air
// between the eye and the terrain takes on).
fn sky_light(r: RenderUniforms, dir: vec3<f32>, disc: bool) -> vec3<f32> {
    if r.sky_zenith.w != 0.0 {
        return r.sky_horizon.rgb;
    }
    let haze = exp(-HAZE_FALLOFF * max(dir.y, 0.0));
    let mu = max(dot(dir, r.sun_dir.xyz), 0.0);
    let warm = r.sky_sunset.w * mu * mu * haze;
    let halo = 0.04 * pow_n(mu, 12u) + 0.15 * pow_n(mu, 400u);
    var glow = 0.0;
    if disc {
        glow = 10.0 * smoothstep(cos(1.3 * SUN_RADIUS), cos(SUN_RADIUS), mu)
            * smoothstep(-0.01, 0.01, dir.y);
    }
    var base = mix(r.sky_zenith.rgb, r.sky_horizon.rgb, haze);
    base = mix(base, r.sky_sunset.rgb, warm);
    return base + r.sun_color.rgb * (halo + glow);
}

// Clamped and encoded for the target.
fn to_target(r: RenderUniforms, linear: vec3<f32>) -> vec3<f32> {
    var color = clamp(linear, vec3<f32>(0.0), vec3<f32>(1.0));
    if r.encode_srgb != 0u {
        color = srgb_encode(color);
    }
    return color;
}

// The sky's colour along unit `dir`, ready to store: what the sky pass and a missed ray show.
fn sky_pixel(r: RenderUniforms, dir: vec3<f32>) -> vec3<f32> {
    return to_target(r, sky_light(r, dir, true));
}

// `lit` (linear) at `world` seen from the eye through the air: a part exp(-fog * d) of it
// survives, the rest is the sky's light along the same direction flattened to the horizon; and
// over the fade band it goes wholly into that light, so the drawn square's end is no edge.
fn fog(r: RenderUniforms, lit: vec3<f32>, world: vec3<f32>) -> vec3<f32> {
    if r.fade.y <= 0.0 && all(r.fog.rgb == vec3<f32>(0.0)) {
        return lit;
    }
    let rel = world - r.camera_pos.xyz;
    let d = length(rel);
    let dir = rel / max(d, 1e-30);
    let air = sky_light(r, normalize(vec3<f32>(dir.x, max(dir.y, 0.0), dir.z)), false);
    var c = mix(air, lit, exp(-r.fog.rgb * d));
    if r.fade.y > 0.0 {
        c = mix(c, air, smoothstep(r.fade.x, r.fade.y, length(rel.xz)));
    }
    return c;
}

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

    return to_target(r, fog(r, lit, world));
}
