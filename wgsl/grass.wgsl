// import: noise, shade
// Grass, first part (src/grass.rs is the CPU twin, cell for cell): the blade of each cell of the
// meadow's grid from a hash of the cell's 64-bit coordinates and the seed, its height varied by
// a value noise over clumps of whole cells, and where grass grows (`grass_cover`: the grass
// material's share in the shading, less snow and sand, none under water). Cells reach the GPU
// relative to the eye's cell, which is 64-bit: the hash sees the same integers anywhere.

struct GrassUniforms {
    // The eye's cell, 64-bit: x low and high words, z low and high words.
    eye_cell: vec4<u32>,
    // The clump holding the eye's cell, 64-bit as `eye_cell`.
    eye_clump: vec4<u32>,
    // The eye's cell less its clump's first cell, x and z.
    eye_rem: vec2<i32>,
    // Cells across a clump.
    clump_cells: i32,
    seed: u32,
    // The mean blade's height, metres.
    height: f32,
    // A cell's side, metres.
    cell: f32,
    _pad: vec2<f32>,
}

struct Blade {
    // The root within its cell, fractions of the cell's side.
    offset: vec2<f32>,
    height: f32,
    facing: f32,
    lean: f32,
    curve: f32,
    width: f32,
    shade: f32,
    keep: f32,
    far: f32,
}

const BLADE_STREAM: u32 = 0x67726173u;
const CLUMP_STREAM: u32 = 0x636c756du;
const BLADE_WIDTH: f32 = 0.03;
const GRASS_TAU: f32 = 6.28318530717958648;

// A 64-bit integer (low, high words) plus a 32-bit one.
fn add64(a: vec2<u32>, r: i32) -> vec2<u32> {
    let lo = a.x + bitcast<u32>(r);
    let carry = select(0u, 1u, lo < a.x);
    return vec2<u32>(lo, a.y + select(0u, 0xffffffffu, r < 0) + carry);
}

fn grass_cell_hash(c: vec4<u32>, seed: u32, stream: u32) -> u32 {
    return pcg(seed ^ pcg(c.x ^ pcg(c.y ^ pcg(c.z ^ pcg(c.w ^ stream)))));
}

// A hash value as a number in [0, 1): its top 24 bits, exact in f32.
fn grass_unit(h: u32) -> f32 {
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

fn floor_div(a: i32, k: i32) -> i32 {
    return select(a / k, (a - k + 1) / k, a < 0);
}

fn clump_corner(g: GrassUniforms, q: vec2<i32>) -> f32 {
    let c = vec4<u32>(add64(g.eye_clump.xy, q.x), add64(g.eye_clump.zw, q.y));
    return grass_unit(grass_cell_hash(c, g.seed, CLUMP_STREAM));
}

// The blade of the cell `rel` cells from the eye's.
fn blade_at(g: GrassUniforms, rel: vec2<i32>) -> Blade {
    let cell = vec4<u32>(add64(g.eye_cell.xy, rel.x), add64(g.eye_cell.zw, rel.y));
    var h = grass_cell_hash(cell, g.seed, BLADE_STREAM);
    var b: Blade;
    h = pcg(h);
    let ox = grass_unit(h);
    h = pcg(h);
    b.offset = vec2<f32>(ox, grass_unit(h));
    h = pcg(h);
    b.facing = grass_unit(h) * GRASS_TAU;
    h = pcg(h);
    b.lean = 0.15 + 0.35 * grass_unit(h);
    h = pcg(h);
    b.curve = grass_unit(h);
    h = pcg(h);
    b.width = BLADE_WIDTH * (0.7 + 0.6 * grass_unit(h));
    h = pcg(h);
    b.shade = grass_unit(h);
    h = pcg(h);
    b.keep = grass_unit(h);
    h = pcg(h);
    b.far = grass_unit(h);
    h = pcg(h);
    let own = grass_unit(h);
    // The clump: whole cells from the eye's clump, so the blade's place in it is exact.
    let k = g.clump_cells;
    let t = g.eye_rem + rel;
    let q = vec2<i32>(floor_div(t.x, k), floor_div(t.y, k));
    let inside = (vec2<f32>(t - q * k) + b.offset) / f32(k);
    let f = inside * inside * (3.0 - 2.0 * inside);
    let c00 = clump_corner(g, q);
    let c10 = clump_corner(g, q + vec2<i32>(1, 0));
    let c01 = clump_corner(g, q + vec2<i32>(0, 1));
    let c11 = clump_corner(g, q + vec2<i32>(1, 1));
    let bottom = c00 + f.x * (c10 - c00);
    let top = c01 + f.x * (c11 - c01);
    let clumped = bottom + f.y * (top - bottom);
    b.height = g.height * (0.4 + 1.2 * clumped) * (0.8 + 0.4 * own);
    return b;
}

// How much of the ground is grass, 0 to 1, where the surface's normal rises `n_y`, its
// normalised height is `h` and its colour channel `tint`: as `template_albedo` and
// `shade_through` (shade.wgsl) mix the materials.
fn grass_cover(r: RenderUniforms, n_y: f32, h: f32, tint: f32) -> f32 {
    let jitter = 2.0 * (tint - 0.5);
    let alpine = smoothstep(r.snow_height - 0.12, r.snow_height, h + 0.1 * jitter);
    let gentle = smoothstep(0.6, 0.95, n_y + 0.08 * jitter) * (1.0 - 0.6 * alpine);
    let line = r.snow_height + (tint - 0.5) * SNOW_JITTER;
    let snow = smoothstep(line - SNOW_EDGE, line + SNOW_EDGE, h) * smoothstep(0.45, 0.75, n_y);
    var sand = 0.0;
    if r.water_on != 0u {
        if h < r.water_level {
            return 0.0;
        }
        let top = r.water_level + r.sand_band * (0.6 + tint);
        sand = 1.0 - smoothstep(top - 0.5 * r.sand_band, top, h);
    }
    return gentle * (1.0 - snow) * (1.0 - sand);
}

// The gust waves (src/grass.rs: GUSTS): wavelength in metres, amplitude.
const GUST_WAVES: array<vec2<f32>, 2> = array<vec2<f32>, 2>(vec2<f32>(23.0, 0.3), vec2<f32>(9.0, 0.2));
const BEND_PER_SPEED: f32 = 0.03;
const MAX_BEND: f32 = 0.6;

// Where the wind blows the tip of a blade `height` metres tall rooted at camera-relative `xz`,
// in the `wind` (the direction it blows towards, x and z; its speed, m/s) with its two gust
// waves at these phases at the eye (turns).
fn wind_tip(wind: vec4<f32>, gust_phase: vec2<f32>, xz: vec2<f32>, height: f32) -> vec2<f32> {
    let speed = wind.z;
    if speed <= 0.0 {
        return vec2<f32>(0.0);
    }
    let along = dot(xz, wind.xy);
    var g = 0.5;
    for (var i = 0; i < 2; i++) {
        let turns = fract(gust_phase[i] + along / GUST_WAVES[i].x);
        g += GUST_WAVES[i].y * sin(6.28318530717958648 * turns);
    }
    let bend = min(BEND_PER_SPEED * speed * (0.5 + g), MAX_BEND);
    return wind.xy * bend * height;
}

// Whether a sphere at camera-relative `c` of radius `radius` touches the frustum of `view_proj`.
fn in_frustum(view_proj: mat4x4<f32>, c: vec3<f32>, radius: f32) -> bool {
    let m = transpose(view_proj);
    let planes = array<vec4<f32>, 6>(
        m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[2], m[3] - m[2]
    );
    for (var k = 0; k < 6; k++) {
        let pl = planes[k];
        if dot(pl.xyz, c) + pl.w < -radius * length(pl.xyz) {
            return false;
        }
    }
    return true;
}
