// import: world
// The terrain's shadow-height map (src/gpu/air_shadow.rs): for each texel of a square around
// the eye, the altitude S below which the air over its centre lies in the terrain's shadow,
//
//     S(x) = max over t >= 0 of h(x + t d) - t tan(e),
//
// d the sun's horizontal direction and e its elevation, over the drawn surface's levels: the
// air at (x, y) sees the sun where y >= S(x), exactly for a height field. The light shafts read
// it (terrain_air_map.wgsl). Marched towards the sun from the texel's centre, in steps that
// grow with the distance (a cone, as the light bake's: world_light.wgsl), each reading the
// coarsest level whose spacing is within half the step and whose square holds the point, until
// nothing farther could rise above S (the line at e from S passes the peak) or no level holds
// the point. What a step leaves out is a ridge narrower than it: S comes out low there, by
// what that ridge stands above the samples beside it.

struct AirShadowBake {
    // Unit horizontal direction towards the sun (x, z), tan of its elevation, texel (metres).
    sun: vec2<f32>,
    tan_e: f32,
    texel: f32,
    // The camera-relative x and z of the square's first corner, and its texels a side.
    origin: vec2<f32>,
    texels: u32,
    // Steps per doubling of the distance.
    steps: f32,
}

@group(0) @binding(41) var<uniform> air_bake: AirShadowBake;
@group(0) @binding(42) var air_shadow_out: texture_storage_2d<rgba16float, write>;

// What `air_level_height` found: the height (metres) and the level it was read from.
struct AirHeight {
    height: f32,
    level: u32,
    found: bool,
}

// Level `lv`'s height (0 to 1) at `p` (its samples from its first), bilinearly: the texels'
// heights alone (world.wgsl's `sample_level` unpacks their slopes and colour too).
fn air_level_bilinear(lv: Level, p: vec2<f32>) -> f32 {
    let p0 = floor(p);
    let t = p - p0;
    let cells = vec2<i32>(i32(w.cells));
    let c0 = clamp(vec2<i32>(p0), vec2<i32>(0), cells);
    let c1 = min(c0 + vec2<i32>(1), cells);
    // The texels' places in the toroidal texture: one modulo a side, the next texel wraps by
    // hand (the side is the level's cells plus one, no power of two).
    let a = (lv.origin_mod + vec2<u32>(c0)) % vec2<u32>(w.side);
    var b = a + vec2<u32>(c1 - c0);
    b = select(b, b - vec2<u32>(w.side), b >= vec2<u32>(w.side));
    let l = i32(lv.layer);
    let h00 = level_texel_height(textureLoad(level_tex, vec2<i32>(a), l, 0).x);
    let h10 = level_texel_height(textureLoad(level_tex, vec2<i32>(i32(b.x), i32(a.y)), l, 0).x);
    let h01 = level_texel_height(textureLoad(level_tex, vec2<i32>(i32(a.x), i32(b.y)), l, 0).x);
    let h11 = level_texel_height(textureLoad(level_tex, vec2<i32>(b), l, 0).x);
    return mix(mix(h00, h10, t.x), mix(h01, h11, t.x), t.y);
}

// The height of the drawn levels at camera-relative `xz`, from the coarsest level from `start`
// on whose spacing is at most `step` metres (or `start` itself) and whose square holds the point.
fn air_level_height(xz: vec2<f32>, start: u32, step: f32) -> AirHeight {
    var out = AirHeight(0.0, start, false);
    let f = (xz + w.eye.xz) / w.eye.w;
    var l = start;
    for (var k = 0; k < 24; k++) {
        let lv = w.levels[l];
        let coarse = w.levels[lv.coarse];
        if lv.coarse != l && w.eye.w * f32(1u << coarse.shift) <= step {
            l = lv.coarse;
            continue;
        }
        let p = (f - vec2<f32>(lv.origin_rel)) / f32(1u << lv.shift);
        if all(p >= vec2<f32>(0.0)) && all(p <= vec2<f32>(f32(w.cells))) {
            out.height = air_level_bilinear(lv, p) * w.peak;
            out.level = l;
            out.found = true;
            return out;
        }
        if lv.coarse == l {
            return out;
        }
        l = lv.coarse;
    }
    return out;
}

@compute @workgroup_size(8, 8, 1)
fn bake_air_shadow(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= vec2<u32>(air_bake.texels)) {
        return;
    }
    let x = air_bake.origin + (vec2<f32>(id.xy) + 0.5) * air_bake.texel;
    let first = air_level_height(x, w.first, 0.0);
    var s = first.height;
    var j = first.level;
    let growth = 1.0 / air_bake.steps;
    var t = 0.5 * air_bake.texel;
    for (var i = 0; i < 4096 && first.found; i++) {
        if t * air_bake.tan_e > w.peak - s {
            break;
        }
        let step = max(0.5 * air_bake.texel, t * growth);
        // A level of half the step's spacing (the default landscape's map comes out nearer
        // the truth than with the step's own: tests/shafts.rs).
        let at = air_level_height(x + t * air_bake.sun, j, 0.5 * step);
        if !at.found {
            break;
        }
        j = at.level;
        s = max(s, at.height - t * air_bake.tan_e);
        t += step;
    }
    textureStore(air_shadow_out, id.xy, vec4<f32>(s, 0.0, 0.0, 1.0));
}
