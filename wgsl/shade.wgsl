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
    // Water: level in normalised height, its plane's y here, time (s), 1 when there is water.
    water: vec4<f32>,
    // xy: the eye's xz modulo RIPPLE_PERIOD (ripples stay put in the world); z: the sand band
    // above the water, normalised height.
    water_origin: vec4<f32>,
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

// Water (src/sky.rs documents the same constants): light left after a metre of clear water in
// red, green and blue, the colour it scatters back (times the light falling on it), and the
// ripples: plane waves of whole cycles per RIPPLE_PERIOD metres, so the eye's position can be
// reduced modulo that period.
const WATER_EXTINCTION: vec3<f32> = vec3<f32>(0.45, 0.09, 0.06);
const WATER_SCATTER: vec3<f32> = vec3<f32>(0.010, 0.040, 0.050);
const SAND: vec3<f32> = vec3<f32>(0.55, 0.45, 0.24);
const RIPPLE_PERIOD: f32 = 256.0;
const RIPPLES: array<vec3<f32>, 4> = array<vec3<f32>, 4>(
    // Cycles per period in x and z, and the wave's amplitude in metres.
    vec3<f32>(37.0, 11.0, 0.020),
    vec3<f32>(-19.0, 41.0, 0.016),
    vec3<f32>(53.0, -29.0, 0.011),
    vec3<f32>(-71.0, -60.0, 0.007),
);

// The water's normal at `xz` (world metres, reduced) `d` metres from the eye: the slope of
// four travelling plane waves, each faded out where it is too fine for the distance (about
// 100 wavelengths away it is gone), so far water is a calm mirror rather than noise.
fn ripple_normal(r: RenderUniforms, xz: vec2<f32>, d: f32) -> vec3<f32> {
    var slope = vec2<f32>(0.0);
    for (var i = 0u; i < 4u; i++) {
        let w = RIPPLES[i];
        let k = w.xy * (6.2831853 / RIPPLE_PERIOD);
        let wavelength = 6.2831853 / length(k);
        let fade = 1.0 - smoothstep(25.0 * wavelength, 100.0 * wavelength, d);
        // Deep-water waves: angular frequency sqrt(g k).
        let phase = dot(k, xz) - sqrt(9.81 * length(k)) * r.water.z;
        slope += w.z * fade * cos(phase) * k;
    }
    return normalize(vec3<f32>(-slope.x, 1.0, -slope.y));
}

// What the eye sees where its ray to terrain at `world` (lit `lit`, normalised height `h`)
// crosses the water first: the bottom through the water, and the sky in the ripples by
// Fresnel (Schlick, water's 2 % at normal incidence). Returns the colour and the point seen.
fn water_surface(r: RenderUniforms, world: vec3<f32>, lit: vec3<f32>, h: f32) -> array<vec3<f32>, 2> {
    let eye = r.camera_pos.xyz;
    let rel = world - eye;
    // The fraction of the way to the terrain where the ray meets the plane.
    let t = clamp((r.water.y - eye.y) / min(rel.y, -1e-30), 0.0, 1.0);
    let surface = eye + rel * t;
    let dist = length(rel);
    let view = rel / max(dist, 1e-30);
    let n = ripple_normal(r, surface.xz + r.water_origin.xy, dist * t);
    // The bottom, through the water it crosses (deeper looks darker and bluer).
    let through = exp(-WATER_EXTINCTION * dist * (1.0 - t));
    let light = r.ambient_color.rgb + r.sun_color.rgb * max(r.sun_dir.y, 0.0);
    let below = lit * through + WATER_SCATTER * light * (1.0 - through);
    var reflected = reflect(view, n);
    reflected.y = abs(reflected.y);
    let cos_v = clamp(-dot(view, n), 0.0, 1.0);
    let fresnel = 0.02 + 0.98 * pow(1.0 - cos_v, 5.0);
    let color = mix(below, sky_light(r, reflected, true), fresnel);
    return array<vec3<f32>, 2>(color, surface);
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
    // Sand along the shore, its upper edge jittered by the colour noise as the snow line is.
    if r.water.w != 0.0 {
        let top = r.water.x + r.water_origin.z * (0.6 + tint);
        albedo = mix(albedo, SAND, 1.0 - smoothstep(top - 0.5 * r.water_origin.z, top, h));
    }

    // Valleys (low h) get less sky and less sun.
    let ao = pow(max(h, 1e-4), r.ao_exponent);

    let l = r.sun_dir.xyz;
    let v = normalize(r.camera_pos.xyz - world);
    let half_vec = normalize(l + v);
    let ndl = max(dot(n, l), 0.0);
    let spec = select(0.0, pow(max(dot(n, half_vec), 0.0), r.shininess), ndl > 0.0);
    let lit = albedo * (r.ambient_color.rgb + r.sun_color.rgb * ndl) * ao
        + r.sun_color.rgb * (spec * r.specular * (0.3 + 0.7 * snow) * ao);

    // Terrain under water, seen from above it: the water's surface is what the ray meets.
    if r.water.w != 0.0 && h < r.water.x && r.camera_pos.y > r.water.y {
        let w = water_surface(r, world, lit, h);
        return to_target(r, fog(r, w[0], w[1]));
    }
    return to_target(r, fog(r, lit, world));
}
