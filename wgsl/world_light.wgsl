// import: landscape, level_texel
// The endless world's light bake: for each sample of a rectangle of a level, the elevation of
// the terrain's horizon towards the sun's azimuth (what a sun lower than it cannot light) and
// how far the sample lies below its neighbourhood (valley occlusion), written into an r32uint
// texture-array layer at the same toroidal texel as the sample's heights. Reads the levels'
// baked heights, and near the sample the terrain function itself (composed after noise.wgsl and
// landscape.wgsl). The truth it is measured against is src/light.rs.
//
// The horizon: from the sample, march towards the sun. Near it (NEAR samples of its level),
// where an error in height is a large error in angle, every half sample, evaluating the
// octaves the level keeps at the point; then in steps that grow with the distance (a cone: at
// distance t, a step of max(spacing, t / STEPS_PER_DOUBLING)), reading the finest level whose
// spacing is within the step and whose square holds the point, bilinearly: what that level
// leaves out subtends about its spacing over the distance, under the step's angle. The elevation is independent of
// the sun's elevation, so moving the sun up or down bakes nothing; turning it re-bakes.

struct LightLevel {
    // The level's first sample, in its samples, and that sample's texel.
    origin: vec2<i32>,
    origin_mod: vec2<u32>,
    spacing_log2: i32,
    layer: u32,
    // 1 when the level is active and wholly baked (its texels can be read).
    usable: u32,
    _pad: u32,
}

struct LightUniforms {
    // Unit horizontal direction towards the sun.
    sun: vec2<f32>,
    cells: u32,
    side: u32,
    levels: u32,
    // World height of normalised height 1.
    peak: f32,
    // Steps per doubling of the distance, and the valley radius in metres.
    steps: f32,
    valley_radius: f32,
    // The terrain function (see LandscapeUniforms).
    seed: u32,
    total_octaves: u32,
    terrain: u32,
    gain: f32,
    feature_log2: i32,
    period: u32,
    _pad1: u32,
    _pad2: u32,
    entries: array<LightLevel, 24>,
}

// Samples of its level out to which the march evaluates the terrain function.
const NEAR: f32 = 4.0;

// One rectangle: its level, its first sample (the level's samples) and its size.
struct LightRect {
    origin: vec2<i32>,
    extent: vec2<u32>,
    level: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> light: LightUniforms;
@group(0) @binding(1) var<uniform> rect: LightRect;
// The levels' packed texels (level_texel.wgsl), of which the light reads the height.
@group(0) @binding(2) var heights: texture_2d_array<u32>;
// Horizon elevation and valley depth as two 16-bit floats in one 32-bit texel.
@group(0) @binding(3) var light_out: texture_storage_2d_array<r32uint, write>;

fn height_texel(lv: LightLevel, ij: vec2<i32>) -> f32 {
    let t = (lv.origin_mod + vec2<u32>(ij)) % vec2<u32>(light.side);
    return level_texel_height(textureLoad(heights, vec2<i32>(t), i32(lv.layer), 0).x);
}

// Height in metres at `local` (this level's samples from its first), bilinearly; the caller
// has checked that the point lies in the level's square.
fn level_height(lv: LightLevel, local: vec2<f32>) -> f32 {
    let p0 = min(floor(local), vec2<f32>(f32(light.cells - 1u)));
    let f = local - p0;
    let i = vec2<i32>(p0);
    let a = height_texel(lv, i);
    let b = height_texel(lv, i + vec2<i32>(1, 0));
    let c = height_texel(lv, i + vec2<i32>(0, 1));
    let d = height_texel(lv, i + vec2<i32>(1, 1));
    return light.peak * mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

// The sample `s` of level `k` seen from level `j` (j >= k): its position in level j's samples
// from level j's first. Integer until the last step, so it is exact far from the origin.
fn in_level(s: vec2<i32>, k: u32, j: u32) -> vec2<f32> {
    let lj = light.entries[j];
    let shift = u32(lj.spacing_log2 - light.entries[k].spacing_log2);
    let rel = s - (lj.origin << vec2<u32>(shift));
    return vec2<f32>(rel) * ldexp(1.0, -i32(shift));
}

// Height in metres at `offset` metres from sample `s` of level `k`, from the first usable
// level from `from` on whose square holds the point; `found` false when none does.
struct Lookup {
    height: f32,
    found: bool,
}

fn height_near(s: vec2<i32>, k: u32, first: u32, offset: vec2<f32>) -> Lookup {
    var out: Lookup;
    out.found = false;
    for (var j = first; j < light.levels; j++) {
        let lj = light.entries[j];
        if lj.usable == 0u {
            continue;
        }
        let local = in_level(s, k, j) + offset * ldexp(1.0, -lj.spacing_log2);
        if all(local >= vec2<f32>(0.0)) && all(local <= vec2<f32>(f32(light.cells))) {
            out.height = level_height(lj, local);
            out.found = true;
            return out;
        }
    }
    return out;
}

// The coarsest level whose spacing is at most `step` metres, from `k` on.
fn level_for(k: u32, step: f32) -> u32 {
    var j = k;
    while j + 1u < light.levels && ldexp(1.0, light.entries[j + 1u].spacing_log2) <= step {
        j += 1u;
    }
    return j;
}

@compute @workgroup_size(8, 8, 1)
fn light_main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= rect.extent.x || id.y >= rect.extent.y {
        return;
    }
    let k = rect.level;
    let lk = light.entries[k];
    let s = rect.origin + vec2<i32>(id.xy);
    let own = vec2<i32>(in_level(s, k, k));
    let h = light.peak * height_texel(lk, own);
    let spacing = ldexp(1.0, lk.spacing_log2);

    // The horizon's slope (rise over run) towards the sun; never under 0, since a sun below
    // the horizontal lights nothing anyway.
    var slope = 0.0;
    var u: LandscapeUniforms;
    u.seed = light.seed;
    u.total_octaves = light.total_octaves;
    u.terrain = light.terrain;
    u.gain = light.gain;
    u.feature_log2 = light.feature_log2;
    u.period = light.period;
    u.level_log2 = lk.spacing_log2;
    u.octaves = u32(clamp(light.feature_log2 - lk.spacing_log2, 0, i32(light.total_octaves)));
    // The texel's own height (`h`) is this evaluation at offset 0, baked: read, not evaluated
    // again.
    for (var i = 1u; i <= u32(2.0 * NEAR); i++) {
        let d = 0.5 * f32(i);
        let at = light.peak * landscape_sample_at(s, d * light.sun, u, CHANNEL_HEIGHT).x;
        slope = max(slope, (at - h) / (d * spacing));
    }
    var t = NEAR * spacing;
    let growth = 1.0 / light.steps;
    // The level read grows with the step (never shrinks: the step only grows).
    var j = k;
    loop {
        // Nothing farther can rise above the horizon found so far.
        if t * max(slope, 1e-3) > light.peak - h {
            break;
        }
        let step = max(spacing, t * growth);
        while j + 1u < light.levels && ldexp(1.0, light.entries[j + 1u].spacing_log2) <= step {
            j += 1u;
        }
        let at = height_near(s, k, j, t * light.sun);
        if !at.found {
            break;
        }
        slope = max(slope, (at.height - h) / t);
        t += step;
    }

    // Valley occlusion: the sample's height less the mean of eight around it at the valley
    // radius, from a level some eight samples to the radius (or this one, if coarser).
    let r = light.valley_radius;
    let ring = level_for(k, r * 0.125);
    var sum = 0.0;
    var count = 0.0;
    for (var i = 0u; i < 8u; i++) {
        let a = f32(i) * 0.78539816;
        let at = height_near(s, k, ring, r * vec2<f32>(cos(a), sin(a)));
        if at.found {
            sum += at.height;
            count += 1.0;
        }
    }
    let valley = select(0.0, h - sum / max(count, 1.0), count > 0.0);

    let dest = (lk.origin_mod + vec2<u32>(own)) % vec2<u32>(light.side);
    let packed = pack2x16float(vec2<f32>(atan(slope), valley));
    textureStore(light_out, vec2<i32>(dest), i32(lk.layer), vec4<u32>(packed, 0u, 0u, 0u));
}
