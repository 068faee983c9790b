// import: clouds
// Shading shared by every way relief draws terrain (the mesh in world.wgsl, the
// ray casters in raymarch.wgsl and world_rays.wgsl, the sky pass in sky.wgsl): Blinn-Phong under
// a directional sun with a noise-jittered snow line, in one of two palettes (src/palette.rs):
// the blog's two colours with height ambient occlusion h^k, or the seed template's rock, grass
// and sand with sky, back and rim light, shadows and valley occlusion (src/light.rs) and a tone
// curve; seen through the air (aerial perspective), in front of the sky. Composed before the
// file that uses it. The sky and the fog are an analytic model whose CPU twin is src/sky.rs.

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
    // The grass's draw distance where the frame draws grass (metres; 0: none), and 1 where it
    // is the reference's, which draws every blade to that distance: `grass_ground`.
    grass_distance: f32,
    grass_reference: u32,
    // Inverse of view_proj: pixels to view directions for the sky.
    inv_view_proj: mat4x4<f32>,
    // Linear sky at the zenith (w: 1 for a flat sky of sky_horizon's colour) and the horizon.
    sky_zenith: vec4<f32>,
    sky_horizon: vec4<f32>,
    // A low sun's glow on the horizon towards it, and its strength in w.
    sky_sunset: vec4<f32>,
    // rgb: extinction per world unit (0: clear air).
    fog: vec4<f32>,
    // Horizontal distances where terrain begins and finishes fading into the sky (fade_end =
    // 0: no fade).
    fade_start: f32,
    fade_end: f32,
    // The sun's elevation, radians.
    sun_elevation: f32,
    // 1 when the caller's horizon casts shadows.
    shadows: u32,
    // Water: its level in normalised height, its plane's y here, the clock (s) modulo
    // CLOCK_PERIOD, 1 when there is water.
    water_level: f32,
    water_plane: f32,
    clock: f32,
    water_on: u32,
    // The eye's xz less the wind's drift, modulo RIPPLE_PERIOD (ripples stay put in the world
    // but for the wind).
    ripple_origin: vec2<f32>,
    // The sand band above the water, normalised height.
    sand_band: f32,
    // The palette: PALETTE_BLOG or PALETTE_TEMPLATE (src/palette.rs).
    palette: u32,
    // Where the frame draws grass, the blades a ray crosses in its field per unit of the
    // cotangent of its elevation (src/grass.rs: field_cover): `grass_ground`.
    grass_cover: f32,
    // Where the terrain's shading reads the props' shade map (props_map.wgsl), its levels
    // (0: it reads none); per level, the camera-relative xz of its first texel's corner and that
    // texel's place in the texture.
    props_map_levels: u32,
    _pad_end1: f32,
    _pad_end2: f32,
    props_map: array<vec4<f32>, 3>,
    // The clouds (clouds.wgsl, src/world/clouds.rs): coverage (0: none), base and top
    // altitudes (metres), type; cloud-space xz of the eye for the shapes and for the detail
    // (the wind's drift reduced modulo CLOUD_PERIOD); the eye's altitude, the view ray's steps,
    // the frame's step offset and 1 for light shafts; the sun's light at the layer (rgb).
    clouds: vec4<f32>,
    cloud_origin: vec4<f32>,
    cloud_march: vec4<f32>,
    cloud_sun: vec4<f32>,
    // The terrain's shadow-height map for the light shafts (terrain_air_map.wgsl): the
    // camera-relative x and z of its first corner, its texel (metres), its texels a side (0:
    // none baked, the air lit).
    air_shadow: vec4<f32>,
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

// The seed template's tone curve (src/palette.rs, tone_map): the identity up to SHOULDER, then
// a smooth roll-off towards 1.
const SHOULDER: f32 = 0.8;

fn tone_map(c: vec3<f32>) -> vec3<f32> {
    let k = 1.0 - SHOULDER;
    let rolled = SHOULDER + k * (1.0 - exp(-max(c - SHOULDER, vec3<f32>(0.0)) / k));
    return select(rolled, c, c <= vec3<f32>(SHOULDER));
}

// Tone-mapped (seed template), clamped and encoded for the target.
fn to_target(r: RenderUniforms, linear: vec3<f32>) -> vec3<f32> {
    var color = linear;
    if r.palette != PALETTE_BLOG {
        color = tone_map(max(color, vec3<f32>(0.0)));
    }
    color = clamp(color, vec3<f32>(0.0), vec3<f32>(1.0));
    if r.encode_srgb != 0u {
        color = srgb_encode(color);
    }
    return color;
}

// The sky's colour along unit `dir`, ready to store: what the sky pass and a missed ray show.
fn sky_pixel(r: RenderUniforms, dir: vec3<f32>) -> vec3<f32> {
    if r.clouds.x <= 0.0 {
        return to_target(r, sky_light(r, dir, true));
    }
    // The sky is the air's light from as far as the eye sees: the clouds' shadows in the air
    // below them take from it as from the fog's (`cloud_shafts`).
    let shafts = cloud_shafts(r, dir, 1e30);
    let a = through_clouds(r, Air(vec3<f32>(shafts), vec3<f32>(0.0)), dir, 1e30, shafts);
    return to_target(r, sky_light(r, dir, true) * a.keep + a.light);
}

// The sky's light along unit `dir` with its sun disc, behind the clouds.
fn sky_clouded(r: RenderUniforms, dir: vec3<f32>) -> vec3<f32> {
    let sky = sky_light(r, dir, true);
    if r.clouds.x <= 0.0 {
        return sky;
    }
    let a = through_clouds(r, Air(vec3<f32>(1.0), vec3<f32>(0.0)), dir, 1e30, 1.0);
    return sky * a.keep + a.light;
}

// What the clouds between the eye and `far` along unit `dir` do (`clouds_along`: clouds.wgsl,
// or clouds_none.wgsl where the frame has none): `keep` the light kept (transmittance), `light`
// the light they scatter towards the eye (linear), and `dist` their transmittance-weighted
// distance (for the air in front of them).
struct CloudLight {
    keep: f32,
    light: vec3<f32>,
    dist: f32,
}

fn cloud_none() -> CloudLight {
    return CloudLight(1.0, vec3<f32>(0.0), 0.0);
}

// `a`, the air along unit `dir` to `far`, with the clouds on that stretch: they hide what is
// behind them, and the air in front of them takes their light as it takes the terrain's, of
// which the light shafts leave `shafts` (`cloud_shafts`).
fn through_clouds(r: RenderUniforms, a: Air, dir: vec3<f32>, far: f32, shafts: f32) -> Air {
    let c = clouds_along(r, dir, far);
    if c.keep >= 1.0 {
        return a;
    }
    let air = sky_light(r, normalize(vec3<f32>(dir.x, max(dir.y, 0.0), dir.z)), false);
    let k = exp(-r.fog.rgb * c.dist);
    return Air(a.keep * c.keep, a.light * c.keep + c.light * k + air * (1.0 - k) * (1.0 - c.keep) * shafts);
}

// What the air between the eye and `world` does to light from there: the colour seen is
// lit * keep + light. A part exp(-fog * d) of the light survives, the rest is the sky's light
// along the same direction flattened to the horizon; and over the fade band it goes wholly into
// that light, so the drawn square's end is no edge. (Carried per vertex instead, it cost the
// mesh more than it saved on the benchmark's ground-level views on an H100: 1.5-1.9 ms more at
// 1080p with its six more interpolants, 1.6 ms less on the high oblique view.)
struct Air {
    keep: vec3<f32>,
    light: vec3<f32>,
}

fn air_at(r: RenderUniforms, world: vec3<f32>) -> Air {
    var out: Air;
    out.keep = vec3<f32>(1.0);
    out.light = vec3<f32>(0.0);
    let clear = r.fade_end <= 0.0 && all(r.fog.rgb == vec3<f32>(0.0));
    if clear && r.clouds.x <= 0.0 {
        return out;
    }
    let rel = world - r.camera_pos.xyz;
    let d = length(rel);
    let dir = rel / max(d, 1e-30);
    if !clear {
        let air = sky_light(r, normalize(vec3<f32>(dir.x, max(dir.y, 0.0), dir.z)), false);
        var keep = exp(-r.fog.rgb * d);
        if r.fade_end > 0.0 {
            keep *= 1.0 - smoothstep(r.fade_start, r.fade_end, length(rel.xz));
        }
        out.keep = keep;
        out.light = air * (1.0 - keep);
    }
    if r.clouds.x > 0.0 {
        var shafts = 1.0;
        if !clear {
            shafts = cloud_shafts(r, dir, d);
            out.light *= shafts;
        }
        out = through_clouds(r, out, dir, d, shafts);
    }
    return out;
}

// `lit` (linear) at `world` seen from the eye through the air.
fn fog(r: RenderUniforms, lit: vec3<f32>, world: vec3<f32>) -> vec3<f32> {
    let a = air_at(r, world);
    return lit * a.keep + a.light;
}

// Water (src/sky.rs documents the same constants): light left after a metre of clear water in
// red, green and blue, the colour it scatters back (times the light falling on it), and the
// ripples: plane waves of whole cycles per RIPPLE_PERIOD metres and CLOCK_PERIOD seconds, so
// the eye's position and the clock can be reduced modulo those periods.
const WATER_EXTINCTION: vec3<f32> = vec3<f32>(0.45, 0.09, 0.06);
const WATER_SCATTER: vec3<f32> = vec3<f32>(0.010, 0.040, 0.050);
const SAND: vec3<f32> = vec3<f32>(0.55, 0.45, 0.24);
const RIPPLE_PERIOD: f32 = 256.0;
const CLOCK_PERIOD: f32 = 4096.0;
const RIPPLES: array<vec4<f32>, 4> = array<vec4<f32>, 4>(
    // Cycles per RIPPLE_PERIOD in x and z, the wave's amplitude in metres, and its cycles per
    // CLOCK_PERIOD: a deep-water wave's angular frequency sqrt(g k) rounded to whole cycles
    // (src/gpu/wgsl_tests.rs checks them).
    vec4<f32>(37.0, 11.0, 0.020, 1987.0),
    vec4<f32>(-19.0, 41.0, 0.016, 2150.0),
    vec4<f32>(53.0, -29.0, 0.011, 2486.0),
    vec4<f32>(-71.0, -60.0, 0.007, 3084.0),
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
        let phase = dot(k, xz) - w.w * (6.2831853 / CLOCK_PERIOD) * r.clock;
        slope += w.z * fade * cos(phase) * k;
    }
    return normalize(vec3<f32>(-slope.x, 1.0, -slope.y));
}

// What the eye sees where its ray to terrain at `world` (lit `lit`)
// crosses the water first: the bottom through the water, and the sky in the ripples by
// Fresnel (Schlick, water's 2 % at normal incidence); `sunlit` is how much of the sun reaches
// the water. Returns the colour and the point seen.
fn water_surface(r: RenderUniforms, world: vec3<f32>, lit: vec3<f32>, sunlit: f32) -> array<vec3<f32>, 2> {
    let eye = r.camera_pos.xyz;
    let rel = world - eye;
    // The fraction of the way to the terrain where the ray meets the plane.
    let t = clamp((r.water_plane - eye.y) / min(rel.y, -1e-30), 0.0, 1.0);
    let surface = eye + rel * t;
    let dist = length(rel);
    let view = rel / max(dist, 1e-30);
    let n = ripple_normal(r, surface.xz + r.ripple_origin, dist * t);
    // The bottom, through the water it crosses (deeper looks darker and bluer).
    let through = exp(-WATER_EXTINCTION * dist * (1.0 - t));
    let light = r.ambient_color.rgb + r.sun_color.rgb * (max(r.sun_dir.y, 0.0) * sunlit);
    let below = lit * through + WATER_SCATTER * light * (1.0 - through);
    var reflected = reflect(view, n);
    reflected.y = abs(reflected.y);
    let cos_v = clamp(-dot(view, n), 0.0, 1.0);
    let fresnel = 0.02 + 0.98 * pow(1.0 - cos_v, 5.0);
    let color = mix(below, sky_clouded(r, reflected), fresnel);
    return array<vec3<f32>, 2>(color, surface);
}

// Sunlight and sky light over the terrain (src/light.rs has the same constants): the sun's disc
// is seen through a penumbra as wide as the disc above the terrain's horizon towards it, and
// ground lying below the mean height of a ring VALLEY_RADIUS metres around it gets less sky,
// down to VALLEY_FLOOR at a depth of VALLEY_DEPTH times the radius.
const VALLEY_RADIUS: f32 = 256.0;
const VALLEY_DEPTH: f32 = 0.5;
const VALLEY_FLOOR: f32 = 0.35;
const PALETTE_BLOG: u32 = 0u;
const PALETTE_TEMPLATE: u32 = 1u;

// What reaches a point (x: of the sun, y: of the ambient light), where the terrain's horizon
// towards the sun stands at `horizon` radians and the point lies `valley` metres above its
// surroundings. The blog's palette darkens low ground by h^k instead of valleys.
fn occlusion(r: RenderUniforms, h: f32, horizon: f32, valley: f32) -> vec2<f32> {
    var sun = 1.0;
    if r.shadows != 0u {
        sun = smoothstep(-SUN_RADIUS, SUN_RADIUS, r.sun_elevation - horizon);
    }
    if r.palette == PALETTE_BLOG {
        return vec2<f32>(sun, pow(max(h, 1e-4), r.ao_exponent));
    }
    let open = smoothstep(-VALLEY_DEPTH * VALLEY_RADIUS, 0.1 * VALLEY_RADIUS, valley);
    return vec2<f32>(sun, VALLEY_FLOOR + (1.0 - VALLEY_FLOOR) * open);
}

// What the tile shades with: no shadows, the palette's occlusion.
fn unshadowed(r: RenderUniforms, h: f32) -> vec2<f32> {
    return vec2<f32>(1.0, occlusion(r, h, -2.0, 0.0).y);
}

fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

// The colour `c` (0..1) in 8-bit steps: the nearest of 255, a tie rounded up. Written out
// rather than left to `pack4x8unorm`, whose SPIR-V lets the device round a tie either way (on
// lavapipe 11 values of a 960x540 frame's 2.1 M came out a step under a tie rounded up), or to
// an 8-bit store.
fn unorm8_steps(c: vec3<f32>) -> vec3<f32> {
    return floor(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)) * 255.0 + 0.5);
}

// The colour `c` (0..1) packed as the bytes of an RGBA8 texel, alpha 255 (`unorm8_steps`).
fn pack_unorm8(c: vec3<f32>) -> u32 {
    let s = vec3<u32>(unorm8_steps(c));
    return s.x | (s.y << 8u) | (s.z << 16u) | (255u << 24u);
}

// The colour `c` (0..1) at its 8-bit step (`unorm8_steps`) and a quarter step up, for a store
// into an 8-bit target (the ray casts', and the visibility method's frame stored straight into
// a target that takes storage writes). Such a store converts by a rounding the device chooses:
// the H100's put a smooth sky one step under the nearest in about 3% of its values, where
// lavapipe's rounds to the nearest. A value a quarter step over a step stays on that step
// whether the store rounds to the nearest, down or toward zero, so the bytes stored (the
// reference's among them) are the same on such devices, and the same as `pack_unorm8`'s. (A
// store that rounded up would still move them; packing the bytes, as the presented frame's
// buffer does, is exact everywhere.)
fn unorm8_exact(c: vec3<f32>) -> vec3<f32> {
    return min((unorm8_steps(c) + 0.25) / 255.0, vec3<f32>(1.0));
}

// The seed template's materials (src/palette.rs): linear albedos of rock (dark to light with
// the colour noise), grass (lush low, dry towards the snow line).
const ROCK_DARK: vec3<f32> = vec3<f32>(0.10, 0.085, 0.07);
const ROCK_LIGHT: vec3<f32> = vec3<f32>(0.32, 0.27, 0.22);
const GRASS: vec3<f32> = vec3<f32>(0.06, 0.12, 0.025);
const DRY_GRASS: vec3<f32> = vec3<f32>(0.22, 0.19, 0.08);

// Rock where it is steep, grass where it is gentle (drier higher up), each edge moved by the
// colour noise so that no edge follows a contour or a slope line.
// Lush and dry blades of grass (linear albedos), the lighter towards the tips.
const BLADE_LUSH: vec3<f32> = vec3<f32>(0.07, 0.16, 0.03);
const BLADE_DRY: vec3<f32> = vec3<f32>(0.22, 0.21, 0.08);
// What light through a blade takes on: yellower.
const THROUGH: vec3<f32> = vec3<f32>(0.9, 0.85, 0.35);

// The light leaving a blade of grass (grass_blade.wgsl) at camera-relative `rel` with normal
// `normal`, `along` of the way up, its shade and the sun's and sky's occlusion at its root in
// `look`, for `lin`: lit as a thin leaf (the sun through either side, |N.L|, warmer where it
// shines through from behind; the sky's light; a little sheen; darker toward the root).
fn blade_radiance(lin: RenderUniforms, rel: vec3<f32>, normal: vec3<f32>, along: f32, look: vec3<f32>) -> vec3<f32> {
    let l = lin.sun_dir.xyz;
    let v = normalize(lin.camera_pos.xyz - rel);
    // The side the eye sees, its normal bent towards the sky: a blade is rounded, and a
    // meadow's blades face every way, so more of it faces up than a flat strip does.
    var n = normalize(normal);
    n = select(n, -n, dot(n, v) < 0.0);
    let rounded = normalize(n + vec3<f32>(0.0, 0.8, 0.0));
    let shade = look.x;
    let sun = lin.sun_color.rgb * (look.y * cloud_shadow(lin, rel));
    let ao = look.z * mix(0.4, 1.0, along);
    let albedo = mix(BLADE_LUSH, BLADE_DRY, shade * shade) * mix(0.55, 1.2, along);
    // The sun on the side seen, and through the blade from the other side.
    let front = max(dot(rounded, l), 0.0);
    let back = 0.6 * max(dot(-n, l), 0.0);
    let sky = lin.ambient_color.rgb * (0.75 + 0.25 * rounded.y);
    let half_vec = normalize(l + v);
    let sheen = 0.06 * pow(max(dot(rounded, half_vec), 0.0), 24.0) * along;
    return albedo * (sky * ao + sun * (front + back * THROUGH)) + sun * sheen;
}

// The light leaving the field of blades at camera-relative `rel` (where the ground's normal is
// `n`) where single blades are no longer drawn, under the sun's and the sky's occlusion `occl`:
// `blade_radiance` over the blades' facings (each blade turns its face to
// the eye, so their normals span the half circle facing it: two at 45 degrees either side
// stand for them), at the middle shade of the blades' spread, at the height up the blades
// that shows: their middle by area (a third of the way up, as they taper) seen from above,
// higher (FIELD_ALONG) at a grazing angle, where the blades in front hide the lower parts.
const FIELD_ALONG: f32 = 0.6;
fn field_radiance(r: RenderUniforms, rel: vec3<f32>, n: vec3<f32>, occl: vec2<f32>) -> vec3<f32> {
    let to_eye = r.camera_pos.xyz - rel;
    let s = clamp(dot(n, to_eye) / max(length(to_eye), 1e-6), 0.0, 1.0);
    let along = mix(FIELD_ALONG, 1.0 / 3.0, s);
    let e = to_eye.xz / max(length(to_eye.xz), 1e-6);
    let l = r.sun_dir.xyz;
    // The two normals, horizontal, 45 degrees either side of the way to the eye; bent up as
    // `blade_radiance` bends them (y 0.8 before normalising: 1 / sqrt(1.64)).
    let k = 0.70710678;
    let n1 = vec2<f32>(k * (e.x - e.y), k * (e.x + e.y));
    let n2 = vec2<f32>(k * (e.x + e.y), k * (e.y - e.x));
    let bent = 0.78086881;
    let r1 = vec3<f32>(n1.x, 0.8, n1.y) * bent;
    let r2 = vec3<f32>(n2.x, 0.8, n2.y) * bent;
    let front = max(dot(r1, l), 0.0) + max(dot(r2, l), 0.0);
    let back = 0.6 * (max(-dot(n1, l.xz), 0.0) + max(-dot(n2, l.xz), 0.0));
    let h = normalize(l + to_eye / max(length(to_eye), 1e-6));
    let sheen = 0.06 * along * (pow(max(dot(r1, h), 0.0), 24.0) + pow(max(dot(r2, h), 0.0), 24.0));
    // The blades' shade is uniform in [0, 1] and their albedo follows its square: a third.
    let albedo = mix(BLADE_LUSH, BLADE_DRY, 1.0 / 3.0) * mix(0.55, 1.2, along);
    let sky = r.ambient_color.rgb * (0.75 + 0.25 * 0.8 * bent);
    let ao = occl.y * mix(0.4, 1.0, along);
    let sun = r.sun_color.rgb * occl.x;
    return albedo * (sky * ao + 0.5 * sun * (front + back * THROUGH)) + 0.5 * sun * sheen;
}

// The ground where grass grows and the frame (or the reference) draws its blades
// (`grass_distance` > 0), for the grass material `plain`: bare earth, where it shows between
// the blades. Where the blades thin out, and beyond, the field stands in for them
// (`field_share`).
const DIRT: vec3<f32> = vec3<f32>(0.075, 0.06, 0.035);
fn grass_ground(r: RenderUniforms, plain: vec3<f32>) -> vec3<f32> {
    return select(plain, DIRT, r.grass_distance > 0.0);
}

// How much of the frame's grass ground at `rel` from the eye, where the surface's normal is
// `n`, shows the field of blades (`field_radiance`) rather than its earth: from 0.45 of the draw
// distance (horizontally; the blades thin out from 0.4 of it, most of them past the middle) to
// where the last goes, more and more of the share of the ground the blades hide at the ray's elevation θ, 1 - exp(-c / tan θ)
// (c: src/grass.rs's field_cover). So no line marks where the blades end
// (crates/eval/tests/grass_reference.rs measures it against the reference). The reference's
// blades stand at full density to its `grass_distance` (twice the frame's): the field only
// beyond, where it has no blades (the frame's stand-in there, not a truth).
fn field_share(r: RenderUniforms, rel: vec3<f32>, n: vec3<f32>) -> f32 {
    if r.grass_distance <= 0.0 {
        return 0.0;
    }
    let s = clamp(-dot(n, rel) / max(length(rel), 1e-6), 1e-3, 1.0);
    let hidden = 1.0 - exp(-r.grass_cover * sqrt(1.0 - s * s) / s);
    let d = length(rel.xz);
    var far = clamp((d - 0.45 * r.grass_distance) / (0.55 * r.grass_distance), 0.0, 1.0);
    if r.grass_reference != 0u {
        far = select(0.0, 1.0, d >= r.grass_distance);
    }
    return far * hidden;
}

// The seed template's albedo (earth under the grass where blades are drawn: `grass_ground`).
fn template_albedo(r: RenderUniforms, n: vec3<f32>, h: f32, tint: f32) -> vec3<f32> {
    let jitter = 2.0 * (tint - 0.5);
    let rock = mix(ROCK_DARK, ROCK_LIGHT, smoothstep(0.25, 0.75, tint));
    let alpine = smoothstep(r.snow_height - 0.12, r.snow_height, h + 0.1 * jitter);
    let grass = grass_ground(r, mix(GRASS, DRY_GRASS, alpine));
    return mix(rock, grass, grass_share(r, n, h, tint));
}

// The grass material's share of the seed template's ground (its slope and height; before snow
// and sand).
fn grass_share(r: RenderUniforms, n: vec3<f32>, h: f32, tint: f32) -> f32 {
    let jitter = 2.0 * (tint - 0.5);
    let alpine = smoothstep(r.snow_height - 0.12, r.snow_height, h + 0.1 * jitter);
    return smoothstep(0.6, 0.95, n.y + 0.08 * jitter) * (1.0 - 0.6 * alpine);
}

// Colour of terrain at `world` with unit normal `n`, normalised height `h`, colour channel
// `tint` and occlusion `occl` (x: of the sun, y: of the ambient light; see `occlusion`), ready
// to store in the target (sRGB-encoded when the target is not an sRGB format).
fn shade(r: RenderUniforms, world: vec3<f32>, n: vec3<f32>, h: f32, tint: f32, occl: vec2<f32>) -> vec3<f32> {
    return shade_through(r, world, n, h, tint, occl, air_at(r, world));
}

// `shade` with the air between the eye and `world` given (`air_at` there, or interpolated from
// the vertices around it).
fn shade_through(r: RenderUniforms, world: vec3<f32>, n: vec3<f32>, h: f32, tint: f32, occl_in: vec2<f32>, air: Air) -> vec3<f32> {
    // The clouds' shadow takes the sun's share as the terrain's own does.
    let occl = vec2<f32>(occl_in.x * cloud_shadow(r, world - r.camera_pos.xyz), occl_in.y);
    let blog = r.palette == PALETTE_BLOG;
    var albedo: vec3<f32>;
    if blog {
        albedo = mix(r.color_a.rgb, r.color_b.rgb, smoothstep(0.2, 0.8, tint));
    } else {
        albedo = template_albedo(r, n, h, tint);
    }
    // Snow above the snow height, its edge jittered by the colour noise so it does not follow
    // a contour line, and thinning on steep slopes where it would not settle.
    let line = r.snow_height + (tint - 0.5) * SNOW_JITTER;
    let snow = smoothstep(line - SNOW_EDGE, line + SNOW_EDGE, h) * smoothstep(0.45, 0.75, n.y);
    albedo = mix(albedo, r.snow_color.rgb, snow);
    // Sand along the shore, its upper edge jittered by the colour noise as the snow line is.
    var sand = 0.0;
    if r.water_on != 0u {
        let top = r.water_level + r.sand_band * (0.6 + tint);
        sand = 1.0 - smoothstep(top - 0.5 * r.sand_band, top, h);
        albedo = mix(albedo, SAND, sand);
    }

    let ao = occl.y;
    let sun = r.sun_color.rgb * occl.x;
    let l = r.sun_dir.xyz;
    let v = normalize(r.camera_pos.xyz - world);
    let half_vec = normalize(l + v);
    let ndl = max(dot(n, l), 0.0);
    let spec = select(0.0, pow(max(dot(n, half_vec), 0.0), r.shininess), ndl > 0.0);
    var lit: vec3<f32>;
    if blog {
        lit = albedo * (r.ambient_color.rgb + sun * ndl) * ao
            + sun * (spec * r.specular * (0.3 + 0.7 * snow) * ao);
    } else {
        // A hemisphere of sky light (half as bright from below), a back light from the side
        // away from the sun, and a Fresnel rim of the horizon's light at grazing angles.
        let sky = r.ambient_color.rgb * (0.75 + 0.25 * n.y);
        let away = vec3<f32>(-l.x, 0.0, -l.z);
        let back = r.sun_color.rgb * 0.1 * max(dot(n, away / max(length(away), 1e-4)), 0.0);
        // Where the frame draws grass its ground is a field of blades: no smooth surface's
        // rim or highlight (`grass_ground`).
        let field = select(0.0, grass_share(r, n, h, tint) * (1.0 - snow), r.grass_distance > 0.0);
        let rim = r.sky_horizon.rgb * 0.2 * pow(1.0 - clamp(dot(n, v), 0.0, 1.0), 5.0) * (1.0 - field);
        lit = albedo * ((sky + back) * ao + sun * ndl) + rim * ao
            + sun * (spec * r.specular * (0.3 + 0.7 * snow) * (1.0 - field));
        // Where the frame's blades thin out, the field of them stands in.
        let stand_in = field * (1.0 - sand) * field_share(r, world - r.camera_pos.xyz, n);
        if stand_in > 0.0 {
            lit = mix(lit, field_radiance(r, world - r.camera_pos.xyz, n, occl), stand_in);
        }
    }

    // Terrain under water, seen from above it: the water's surface is what the ray meets.
    if r.water_on != 0u && h < r.water_level && r.camera_pos.y > r.water_plane {
        let w = water_surface(r, world, lit, occl.x);
        return to_target(r, fog(r, w[0], w[1]));
    }
    return to_target(r, lit * air.keep + air.light);
}
