// part of: shade
// import: clouds_seen, terrain_air
// Clouds (src/world/clouds.rs): a layer of 3-D density between a base and a top altitude,
// marched along each view ray in `air_at` and `sky_pixel` (shade.wgsl), so every method that
// shades through the air draws them, and towards the sun for their shadows on everything lit.
//
// Density at a point: a weather field (two octaves of 2-D gradient noise, 4096 m cells) says
// how cloudy the column is; the layer's height profile (flat-bottomed, its top rounded and
// lower for a stratus `type` 0 than for a cumulus 1) times 3-D base noise (two octaves, 1024 m
// cells) is kept above a threshold the coverage lowers; 3-D detail noise (256 m cells) erodes
// its edges. Every noise repeats every CLOUD_PERIOD metres in x and z, so the CPU reduces the
// wind's drift modulo that period in f64 (`cloud_origin`), as it does the ripples'.
//
// Light: Beer's law towards the sun (three samples of the shape's first octave) with a
// sum of three scattering octaves for the light scattered many times (each weaker, less
// extinguished and less forward: Wrenninge's approximation), a Henyey-Greenstein phase, and
// the sky's ambient light, brighter towards the top. The layer curves with the planet (the
// altitude along a ray grows by t^2 / 2R), so a ray to the horizon meets the base far away,
// where the aerial perspective has taken it: no line marks the horizon.

const CLOUD_PERIOD: f32 = 40960.0;
const EARTH_RADIUS: f32 = 6371000.0;
// Extinction per metre at density 1 (a mean free path of 40 m, a thin cumulus's).
const CLOUD_SIGMA: f32 = 0.025;
// The longest stretch of the layer one view ray marches, metres.
const CLOUD_SPAN: f32 = 60000.0;
// The longest stretch towards the sun the shadow samples, metres.
const CLOUD_SHADOW_SPAN: f32 = 6000.0;

fn cloud_hash(x: u32, y: u32, z: u32) -> u32 {
    var h = (x * 0x8da6b343u) ^ (y * 0xd8163841u) ^ (z * 0xcb1ab31fu);
    h = (h ^ (h >> 16u)) * 0x7feb352du;
    h = (h ^ (h >> 15u)) * 0x846ca68bu;
    return h ^ (h >> 16u);
}

fn cloud_wrap(i: f32, period: u32) -> u32 {
    let p = i32(period);
    return u32(((i32(i) % p) + p) % p);
}

fn cloud_fade(t: vec3<f32>) -> vec3<f32> {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// Dot of the corner offset `f` with one of the twelve cube-edge gradients (and four repeated),
// chosen by the hash's top four bits.
fn cloud_grad(h: u32, f: vec3<f32>) -> f32 {
    let k = h >> 28u;
    let u = select(f.y, f.x, k < 8u);
    let v = select(select(f.z, f.x, k == 12u || k == 14u), f.y, k < 4u);
    return select(-u, u, (k & 1u) == 0u) + select(-v, v, (k & 2u) == 0u);
}

// 3-D gradient noise in about [-1, 1] at `p` (cells), repeating every `period` cells in x and z.
fn cloud_noise3(p: vec3<f32>, period: u32) -> f32 {
    let i = floor(p);
    let f = p - i;
    let x0 = cloud_wrap(i.x, period);
    let x1 = cloud_wrap(i.x + 1.0, period);
    let z0 = cloud_wrap(i.z, period);
    let z1 = cloud_wrap(i.z + 1.0, period);
    let y0 = bitcast<u32>(i32(i.y));
    let y1 = y0 + 1u;
    let u = cloud_fade(f);
    let a = mix(
        mix(cloud_grad(cloud_hash(x0, y0, z0), f), cloud_grad(cloud_hash(x1, y0, z0), f - vec3<f32>(1.0, 0.0, 0.0)), u.x),
        mix(cloud_grad(cloud_hash(x0, y1, z0), f - vec3<f32>(0.0, 1.0, 0.0)), cloud_grad(cloud_hash(x1, y1, z0), f - vec3<f32>(1.0, 1.0, 0.0)), u.x),
        u.y
    );
    let b = mix(
        mix(cloud_grad(cloud_hash(x0, y0, z1), f - vec3<f32>(0.0, 0.0, 1.0)), cloud_grad(cloud_hash(x1, y0, z1), f - vec3<f32>(1.0, 0.0, 1.0)), u.x),
        mix(cloud_grad(cloud_hash(x0, y1, z1), f - vec3<f32>(0.0, 1.0, 1.0)), cloud_grad(cloud_hash(x1, y1, z1), f - vec3<f32>(1.0, 1.0, 1.0)), u.x),
        u.y
    );
    return mix(a, b, u.z);
}

fn cloud_fade2(t: vec2<f32>) -> vec2<f32> {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// Dot of the corner offset `f` with one of eight unit gradients (the hash's top three bits).
fn cloud_grad2(h: u32, f: vec2<f32>) -> f32 {
    let k = h >> 29u;
    let g = select(vec2<f32>(1.0, 0.0), vec2<f32>(0.70710678, 0.70710678), (k & 1u) == 1u);
    let q = select(g, vec2<f32>(-g.y, g.x), (k & 2u) == 2u);
    let r = select(q, -q, (k & 4u) == 4u);
    return dot(r, f);
}

// 2-D gradient noise in about [-0.7, 0.7] at `p` (cells), repeating every `period` cells.
fn cloud_noise2(p: vec2<f32>, period: u32, stream: u32) -> f32 {
    let i = floor(p);
    let f = p - i;
    let x0 = cloud_wrap(i.x, period);
    let x1 = cloud_wrap(i.x + 1.0, period);
    let y0 = cloud_wrap(i.y, period);
    let y1 = cloud_wrap(i.y + 1.0, period);
    let u = cloud_fade2(f);
    return mix(
        mix(cloud_grad2(cloud_hash(x0, stream, y0), f), cloud_grad2(cloud_hash(x1, stream, y0), f - vec2<f32>(1.0, 0.0)), u.x),
        mix(cloud_grad2(cloud_hash(x0, stream, y1), f - vec2<f32>(0.0, 1.0)), cloud_grad2(cloud_hash(x1, stream, y1), f - vec2<f32>(1.0, 1.0)), u.x),
        u.y
    );
}

// The weather: how cloudy the column at cloud-space `xz` is, 0 to 1.
fn cloud_weather(xz: vec2<f32>) -> f32 {
    let p = xz * (10.0 / CLOUD_PERIOD);
    let n = cloud_noise2(p, 10u, 0x51u) + 0.5 * cloud_noise2(p * 2.0, 20u, 0x52u);
    return clamp(0.5 + 0.8 * n, 0.0, 1.0);
}

// The layer's height profile at `hf` (0 at the base, 1 at the top) for `kind` (0 stratus, 1
// cumulus).
fn cloud_profile(hf: f32, kind: f32) -> f32 {
    let top = mix(0.35, 1.0, kind);
    return smoothstep(0.0, 0.08, hf) * (1.0 - smoothstep(0.4 * top, top, hf));
}

// The layer's parameters and the eye: what the density needs.
struct CloudLayer {
    coverage: f32,
    base: f32,
    top: f32,
    kind: f32,
    origin: vec2<f32>,
    detail: vec2<f32>,
    eye: f32,
}

fn cloud_layer(r: RenderUniforms) -> CloudLayer {
    return CloudLayer(r.clouds.x, r.clouds.y, r.clouds.z, r.clouds.w, r.cloud_origin.xy, r.cloud_origin.zw, r.cloud_march.x);
}

// How much of the layer's column at camera-relative `rel` the weather lets the coverage
// fill, 0 to 1.
fn cloud_local(c: CloudLayer, rel: vec3<f32>) -> f32 {
    return min(c.coverage * (0.5 + cloud_weather(rel.xz + c.origin)), 1.0);
}

// Density (0 to 1) at camera-relative `rel` whose altitude is `alt`, in a column the weather
// fills `local` of (`cloud_local`); with `detail` above 0, two octaves of the shapes eroded
// by that much of the detail noise (what the view sees: less far away, where a step is longer
// than the detail), at 0 one octave (what light and shadows use).
fn cloud_density(c: CloudLayer, rel: vec3<f32>, alt: f32, local: f32, detail: f32) -> f32 {
    let hf = (alt - c.base) / (c.top - c.base);
    if hf <= 0.0 || hf >= 1.0 {
        return 0.0;
    }
    let profile = cloud_profile(hf, c.kind);
    // The shapes' noise is at most 1: where the profile cannot reach the threshold, no
    // noise is needed.
    if profile <= 1.0 - local || local <= 0.0 {
        return 0.0;
    }
    let xz = rel.xz + c.origin;
    let p = vec3<f32>(xz.x, alt, xz.y) * (40.0 / CLOUD_PERIOD);
    var n = cloud_noise3(p, 40u);
    if detail > 0.0 {
        n += 0.5 * cloud_noise3(p * 2.0, 80u);
    }
    let base = 0.5 + 0.5 * n;
    var d = clamp((base * profile - (1.0 - local)) / max(local, 0.05), 0.0, 1.0);
    if detail > 0.0 && d > 0.0 {
        let q = vec3<f32>(rel.x + c.detail.x, alt, rel.z + c.detail.y) * (160.0 / CLOUD_PERIOD);
        let e = 0.3 * detail * (0.5 + 0.5 * cloud_noise3(q, 160u));
        d = clamp((d - e) / (1.0 - e), 0.0, 1.0);
    }
    return d;
}

fn cloud_phase(g: f32, mu: f32) -> f32 {
    let k = 1.0 + g * g - 2.0 * g * mu;
    return (1.0 - g * g) / (12.566371 * k * sqrt(k));
}

// Where a ray from altitude `a0` with vertical direction `dy` meets altitude `h` over the
// curved planet (a(t) = a0 + dy t + (1 - dy^2) t^2 / 2R): both roots, the smaller first, or
// (-1, -1) where it never does.
fn cloud_cross(a0: f32, dy: f32, h: f32) -> vec2<f32> {
    let k = max((1.0 - dy * dy) / (2.0 * EARTH_RADIUS), 1e-12);
    let c = a0 - h;
    let disc = dy * dy - 4.0 * k * c;
    if disc < 0.0 {
        return vec2<f32>(-1.0);
    }
    let q = -0.5 * (dy + select(-1.0, 1.0, dy >= 0.0) * sqrt(disc));
    let r0 = q / k;
    let r1 = select(c / q, -1e30, q == 0.0);
    return vec2<f32>(min(r0, r1), max(r0, r1));
}

// The stretch [t0, t1] of the view ray along unit `dir` from the eye that first lies in the
// layer, cut at `far`; t1 <= t0 where it lies in none.
fn cloud_span(c: CloudLayer, dir: vec3<f32>, far: f32) -> vec2<f32> {
    let b = cloud_cross(c.eye, dir.y, c.base);
    let t = cloud_cross(c.eye, dir.y, c.top);
    var t0 = 0.0;
    var t1 = 0.0;
    if c.eye < c.base {
        // Below: in at the base's far root, out at the top's.
        t0 = b.y;
        t1 = t.y;
    } else if c.eye <= c.top {
        // Inside: out at the base going down, else at the top.
        t1 = select(t.y, b.x, b.x > 0.0);
    } else {
        // Above: in at the top's near root, if the ray comes down to it.
        if t.x <= 0.0 {
            return vec2<f32>(0.0);
        }
        t0 = t.x;
        t1 = select(t.y, b.x, b.x > 0.0);
    }
    return vec2<f32>(t0, min(min(t1, far), t0 + CLOUD_SPAN));
}

// The sun's light at a sample, as scattered towards the eye: Beer's law through `od` (optical
// depth towards the sun) over three scattering octaves.
fn cloud_sunlit(od: f32, mu: f32) -> f32 {
    var sum = 0.0;
    var a = 1.0;
    var b = 1.0;
    var g = 0.6;
    for (var i = 0; i < 3; i++) {
        sum += a * exp(-b * od) * mix(cloud_phase(g, mu), cloud_phase(-0.2, mu), 0.25);
        a *= 0.5;
        b *= 0.5;
        g *= 0.5;
    }
    return sum;
}

// Optical depth of the shape from camera-relative `rel` (altitude `alt`, in a column the
// weather fills `local` of: the light's samples lie within a weather cell) towards unit
// `to_sun` over `span` metres, three samples spaced wider the further they go.
fn cloud_optical_depth(c: CloudLayer, rel: vec3<f32>, alt: f32, local: f32, to_sun: vec3<f32>, span: f32) -> f32 {
    var od = 0.0;
    var at = 0.0;
    for (var i = 0u; i < 3u; i++) {
        let step = span * (f32(1u << i) / 7.0);
        at += step;
        let mid = at - 0.5 * step;
        od += cloud_density(c, rel + to_sun * mid, alt + to_sun.y * mid, local, 0.0) * step;
    }
    return od * CLOUD_SIGMA;
}

// What a march along a view ray found: what the clouds do to the light (`CloudLight`,
// shade.wgsl) and where along the ray they took it: from `first` (where the first cloud
// met begins), through `half` (where half the light was gone, or halfway to `last` where
// less was taken) to `last` (where the last cloud met ends, or almost no light was left);
// all 1e30 where the ray met none. What the clouds' image keeps (clouds_image.wgsl).
struct CloudMarch {
    seen: CloudLight,
    first: f32,
    half: f32,
    last: f32,
}

// The clouds between the eye and `far` along unit `dir`, marched in `steps` steps.
fn cloud_march(r: RenderUniforms, dir: vec3<f32>, far: f32, steps: u32) -> CloudMarch {
    var out = CloudMarch(cloud_none(), 1e30, 1e30, 1e30);
    if r.clouds.x <= 0.0 {
        return out;
    }
    let c = cloud_layer(r);
    let span = cloud_span(c, dir, far);
    if span.y <= span.x {
        return out;
    }
    let length = span.y - span.x;
    let inv = 1.0 / f32(max(steps, 1u));
    // A step offset a pixel's own (its direction's bits and the frame's seed): banding becomes
    // noise, which the temporal service averages away.
    let bits = bitcast<vec3<u32>>(dir);
    let jitter = fract(f32(cloud_hash(bits.x, bits.y, bits.z) >> 8u) / 16777216.0 + r.cloud_march.z);
    let to_sun = r.sun_dir.xyz;
    let mu = dot(dir, to_sun);
    let curve = (1.0 - dir.y * dir.y) / (2.0 * EARTH_RADIUS);
    var keep = 1.0;
    var light = vec3<f32>(0.0);
    var dist = 0.0;
    for (var i = 0u; i < max(steps, 1u); i++) {
        // Steps spaced as the square of their index: short where the ray enters the layer,
        // whose first optical depths make most of what is seen.
        let u = (f32(i) + jitter) * inv;
        let t = span.x + length * u * u;
        let dt = length * inv * (2.0 * u + inv);
        let rel = dir * t;
        let alt = c.eye + rel.y + curve * t * t;
        let local = cloud_local(c, rel);
        let d = cloud_density(c, rel, alt, local, max(1.0 - smoothstep(6000.0, 15000.0, t), 1e-3));
        if d <= 0.0 {
            continue;
        }
        let sigma = d * CLOUD_SIGMA;
        let hf = (alt - c.base) / (c.top - c.base);
        let od = cloud_optical_depth(c, rel, alt, local, to_sun, min(CLOUD_SHADOW_SPAN, c.top - c.base + 1000.0));
        let scattered = r.cloud_sun.rgb * (6.2831853 * cloud_sunlit(od, mu))
            + r.ambient_color.rgb * mix(0.45, 1.0, hf);
        let absorbed = 1.0 - exp(-sigma * dt);
        light += keep * absorbed * scattered;
        dist += keep * absorbed * t;
        keep *= 1.0 - absorbed;
        out.first = min(out.first, max(t - 0.5 * dt, span.x));
        out.last = t + 0.5 * dt;
        if keep <= 0.5 && out.half >= 1e30 {
            out.half = t;
        }
        if keep < 0.005 {
            break;
        }
    }
    let seen = 1.0 - keep;
    if out.half >= 1e30 {
        out.half = 0.5 * (out.first + out.last);
    }
    out.seen = CloudLight(keep, light, select(0.0, dist / seen, seen > 0.0));
    return out;
}

// The light of the sun that the clouds let through to camera-relative `rel` (1 without
// clouds): the shadows they cast on everything lit, marched there (`cloud_shadow` calls it,
// clouds_seen.wgsl or clouds_image.wgsl).
fn cloud_shadow_march(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    return cloud_shadow_steps(r, rel, 4u);
}

// The same in `steps` samples.
fn cloud_shadow_steps(r: RenderUniforms, rel: vec3<f32>, steps: u32) -> f32 {
    if r.clouds.x <= 0.0 {
        return 1.0;
    }
    let c = cloud_layer(r);
    let alt = c.eye + rel.y;
    let s = cloud_sun(r);
    let t0 = max((c.base - alt) / s.y, 0.0);
    let t1 = min((c.top - alt) / s.y, t0 + CLOUD_SHADOW_SPAN);
    if t1 <= t0 {
        return 1.0;
    }
    var od = 0.0;
    let dt = (t1 - t0) / f32(steps);
    for (var i = 0u; i < steps; i++) {
        let t = t0 + (f32(i) + 0.5) * dt;
        let p = rel + s * t;
        od += cloud_density(c, p, alt + s.y * t, cloud_local(c, p), 0.0) * dt;
    }
    return exp(-od * CLOUD_SIGMA);
}

// Towards the sun for the clouds' shadows: never lower than 0.05 (about 3 degrees), where the
// shadow would stretch without end.
fn cloud_sun(r: RenderUniforms) -> vec3<f32> {
    return normalize(vec3<f32>(r.sun_dir.x, max(r.sun_dir.y, 0.05), r.sun_dir.z));
}

// Light shafts: how much of the air's light along unit `dir` out to `far` (1e30: the sky)
// is left where the clouds' and the terrain's shadows lie in the air below the clouds' base
// (1: none; shadowed air scatters no sunlight). Points of the stretch below the base out to
// SHAFT_FAR, each weighted by the air's light from there (fog.g exp(-fog.g t) dt over all of it
// out to `far`), read the light the clouds let through (`cloud_shadow_air`, at
// `cloud_shaft_steps` of them: 12 reads of the shadows' map where the clouds' image keeps one,
// else 6 marches of one sample) where their sun ray meets the base within SHAFT_REACH, times
// the light the terrain lets through (`terrain_air_margin` at `terrain_air_points` of them:
// terrain_air.wgsl, or the module's stand-in); the sun's share of the air's light grows from
// SHAFT_SIDE across the sun's direction to SHAFT_SIDE + SHAFT_TOWARDS towards it, so the shafts
// show brightest towards the sun, and away from it as darker beams. Off (1) without clouds,
// without fog, or where `cloud_march.w` is 0 (`Clouds::shafts`).
const SHAFT_FAR: f32 = 8000.0;
// How far from the eye (horizontally) a point's sun ray may meet the base for its shadow to
// count: within the clouds' image's shadows' map (16 km each way) with a margin, so the image
// and the full march draw the same shafts, and a low sun's long rays cost no march.
const SHAFT_REACH: f32 = 15000.0;
const SHAFT_SIDE: f32 = 0.4;
const SHAFT_TOWARDS: f32 = 0.5;
// The terrain's shadows in the air (`terrain_air_margin`) fade out as the sun sets, over its
// last AIR_SUN_FADE radians (1 degree): below the horizon the planet shadows all the air alike,
// which the sky's dusk colours already show.
const AIR_SUN_FADE: f32 = 0.01745;
// The terrain's points along a shaft's stretch need be no closer than this (metres), ten of the
// shadow-height map's texels: its shadows' edges are interpolated between them.
const AIR_SPACING: f32 = 340.0;

// The lit share of a stretch along which the terrain's margin (`terrain_air_margin`: above 0
// lit) runs linearly from `a` to `b`; where it does not change, the share a point of that
// margin sees (`terrain_air_step`: the edge's penumbra).
fn air_lit_along(a: f32, b: f32) -> f32 {
    if a == b {
        return terrain_air_step(a);
    }
    if a >= 0.0 && b >= 0.0 {
        return 1.0;
    }
    if a <= 0.0 && b <= 0.0 {
        return 0.0;
    }
    return max(a, b) / abs(a - b);
}

fn cloud_shafts(r: RenderUniforms, dir: vec3<f32>, far: f32) -> f32 {
    let sigma = r.fog.g;
    if r.clouds.x <= 0.0 || r.cloud_march.w == 0.0 || sigma <= 0.0 {
        return 1.0;
    }
    let c = cloud_layer(r);
    let b = cloud_cross(c.eye, dir.y, c.base);
    var t0 = 0.0;
    var t1 = min(far, SHAFT_FAR);
    if c.eye < c.base {
        if b.y > 0.0 {
            t1 = min(t1, b.y);
        }
    } else {
        if b.x <= 0.0 {
            return 1.0;
        }
        t0 = b.x;
        t1 = min(t1, b.y);
    }
    if t1 <= t0 {
        return 1.0;
    }
    // The clouds' shadow at `cloud_shaft_steps` points, the terrain's at up to
    // `terrain_air_points` (a whole multiple of those, and at least as many), no closer than
    // needed to space them AIR_SPACING apart, each cloud's point standing for the terrain's in
    // its stretch.
    let steps = cloud_shaft_steps();
    let most = max(terrain_air_points() / steps, 1u);
    let per = clamp(u32(ceil((t1 - t0) / (f32(steps) * AIR_SPACING))), 1u, most);
    let points = steps * per;
    let dc = (t1 - t0) / f32(steps);
    let dt = dc / f32(per);
    // A pixel's own offset, decorrelated from the clouds' march's, moved by the frame's seed.
    let bits = bitcast<vec3<u32>>(dir);
    let jitter = fract(f32(cloud_hash(bits.y, bits.z, bits.x ^ 0x5bd1e995u) >> 8u) / 16777216.0 + r.cloud_march.z);
    var lost = 0.0;
    let s = cloud_sun(r);
    // The stretch in `points` pieces, their ends offset by the pixel's jitter (the first from
    // t0, the last to t1). The clouds' shadow is read at each `per` pieces' first end (as the
    // clouds' points always were: the stretch's `steps` parts, offset by the jitter); the
    // terrain's lit share of a piece is read off the margins at its ends (`terrain_air_margin`),
    // linearly between them: a shadow's edge inside a piece shades part of it, and the air at
    // the eye, whose light the fog keeps most of, counts.
    let terrain = smoothstep(0.0, AIR_SUN_FADE, r.sun_elevation);
    var t_last = t0;
    var m_last = 0.0;
    if terrain > 0.0 {
        m_last = terrain_air_margin(r, dir * t0);
    }
    for (var i = 0u; i < steps; i++) {
        let rel = dir * (t0 + (f32(i) + jitter) * dc);
        // Where the point's sun ray meets the base, from the eye: past SHAFT_REACH, no shadow.
        let base = rel.xz + s.xz * (max(c.base - (c.eye + rel.y), 0.0) / s.y);
        var cloud = 1.0;
        if dot(base, base) < SHAFT_REACH * SHAFT_REACH {
            cloud = cloud_shadow_air(r, rel);
        }
        // The cloud's point's `per` pieces, the last one's end at t1 (where it lies past it).
        for (var k = 0u; k < per; k++) {
            let t = min(t0 + (f32(i * per + k) + jitter) * dt, t1);
            var lit = cloud;
            if terrain > 0.0 {
                let m = terrain_air_margin(r, dir * t);
                lit *= 1.0 - terrain * (1.0 - air_lit_along(m_last, m));
                m_last = m;
            }
            lost += (1.0 - lit) * exp(-sigma * 0.5 * (t_last + t)) * (t - t_last);
            t_last = t;
        }
    }
    // The last piece, to t1.
    var lit = 1.0;
    if terrain > 0.0 {
        lit = 1.0 - terrain * (1.0 - air_lit_along(m_last, terrain_air_margin(r, dir * t1)));
    }
    lost += (1.0 - lit) * exp(-sigma * 0.5 * (t_last + t1)) * (t1 - t_last);
    // Of the air's light out to `far`, 1 - exp(-sigma far), the part lost.
    lost *= sigma / max(1.0 - exp(-sigma * far), 1e-6);
    let mu = max(dot(dir, r.sun_dir.xyz), 0.0);
    let share = SHAFT_SIDE + SHAFT_TOWARDS * (mu * mu) * (mu * mu);
    return 1.0 - share * min(lost, 1.0);
}
