// import: shade
// One blade of grass, as every way of drawing it builds and lights it: the GPU's rasteriser
// (grass_draw.wgsl, an instance a blade) and the compute raster with ids (raster_blades.wgsl,
// shaded by visibility.wgsl). A blade is stored as the scatter writes it (grass_scatter.wgsl):
// root (camera-relative) and facing; height, lean, curve, width; shade and the sun's and the
// sky's occlusion at the root; the wind's push on its tip.

// Segments of a blade at most (near the eye): a strip of 2 * segments + 1 vertices, the last
// the tip.
const BLADE_SEGMENTS: u32 = 4u;

// A point of a blade: camera-relative position, the normal across the blade in the plane of
// its bend (either side may face the eye), and how far up the blade (0 root, 1 tip).
struct BladePoint {
    p: vec3<f32>,
    n: vec3<f32>,
    t: f32,
}

// How much lower a blade `height` tall stands with its tip pushed by `tip`: its height times
// this.
fn blade_droop(tip: vec2<f32>, height: f32) -> f32 {
    return sqrt(max(1.0 - dot(tip, tip) / (height * height), 0.3));
}

// How far the point `along` of the way up a blade `height` tall moved since the last frame, the
// wind's push on its tip now `tip` and `moved` more than then: camera-relative metres, for the
// temporal service (the eye's own move is the reprojection's). What `blade_point` moves.
fn blade_motion(height: f32, tip: vec2<f32>, moved: vec2<f32>, along: f32) -> vec3<f32> {
    let sink = blade_droop(tip, height) - blade_droop(tip - moved, height);
    return vec3<f32>(moved.x * along * along, height * along * sink, moved.y * along * along);
}

// Vertex `vi` of the strip of blade (`a`, `b`, `tip`: its first, second and fourth vec4s) drawn
// in `segments` segments: vertices 2k and 2k + 1 the two edges at k / segments of the way up,
// vertex 2 segments the tip. Fewer segments sample the same curve.
fn blade_point(a: vec4<f32>, b: vec4<f32>, tip: vec2<f32>, segments: u32, vi: u32) -> BladePoint {
    let root = a.xyz;
    let facing = vec2<f32>(cos(a.w), sin(a.w));
    let across = vec2<f32>(-facing.y, facing.x);
    let height = b.x;
    let lean = b.y * height;
    // The lean grows as t^k: k = 1 a straight slant, larger an upright blade bent at the top.
    let k = 1.0 + 2.0 * b.z;
    let last = 2u * segments;
    let t = min(f32(vi / 2u) / f32(segments), 1.0);
    let side = select(-0.5, 0.5, (vi & 1u) == 1u && vi < last);
    let width = b.w * (1.0 - t) * select(1.0, 0.0, vi >= last);
    let bend = lean * pow(t, k);
    // The wind pushes the blade over more toward its tip; a bent blade stands lower.
    let pushed = tip * t * t;
    let droop = blade_droop(tip, height);
    var out: BladePoint;
    out.p = root + vec3<f32>(
        facing.x * bend + across.x * side * width + pushed.x,
        height * t * droop,
        facing.y * bend + across.y * side * width + pushed.y,
    );
    // The tangent up the blade, and the normal across it in the plane of its bend.
    let dbend = lean * k * pow(max(t, 1e-3), k - 1.0);
    out.n = normalize(vec3<f32>(facing.x * height, -dbend, facing.y * height));
    out.t = t;
    return out;
}

// The colour of a blade's point at camera-relative `rel` with normal `normal`, `along` of the
// way up, its shade and the sun's and sky's occlusion at its root in `look`, as `to_target`
// gives it for `lin`: lit as `blade_radiance` (shade.wgsl) lights it, then through the air as
// the terrain is.
fn blade_light(lin: RenderUniforms, rel: vec3<f32>, normal: vec3<f32>, along: f32, look: vec3<f32>) -> vec3<f32> {
    let lit = blade_radiance(lin, rel, normal, along, look);
    let air = air_at(lin, rel);
    return to_target(lin, lit * air.keep + air.light);
}
