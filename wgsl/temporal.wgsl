// The temporal service's resolve (src/gpu/temporal.rs, src/temporal.rs): blends this frame,
// drawn through a jittered projection, into the history of the frames before it.
//
// - fresh: the frame is shown as drawn, and starts the history;
// - still (the same view as the last frame): each pixel's running mean of up to `cap` frames,
//   so a still view converges to the mean of its jittered frames;
// - moved: each pixel's point is carried to where the last frame saw it (`reproject`, and
//   back along its own motion where it moved: a blade of grass in the wind); the history there
//   is read bilinearly from the texels whose depth agrees with the point's (none: a
//   disocclusion, the frame is shown as drawn), clamped into the range of this frame's 3x3
//   neighbourhood, and blended in. A point that moved in a still view is carried so too.
//
// The history holds premultiplied linear colour and coverage (as the shaded image does) and,
// beside it, the nearest and farthest clip w of each pixel's 3x3 neighbourhood and the frames
// its mean holds.

struct TemporalUniforms {
    // The last frame's clip space (unjittered) from this frame's normalised device coordinates
    // (unjittered), both camera-relative.
    reproject: mat4x4<f32>,
    // The last frame's clip space (unjittered) from a camera-relative point: what carries a
    // point's own motion back.
    last: mat4x4<f32>,
    // x, y: clip w from depth d is y / (d + x); z: how far the history's w may differ from the
    // point's, as a fraction of it; w: 1 where `current_motion` holds this frame's motion.
    depth: vec4<f32>,
    size: vec2<u32>,
    // The most frames a pixel's mean holds.
    cap: u32,
    // 0: fresh, 1: still, 2: moved.
    mode: u32,
}

@group(0) @binding(0) var<uniform> t: TemporalUniforms;
@group(0) @binding(1) var current: texture_2d<f32>;
@group(0) @binding(2) var current_depth: texture_2d<f32>;
@group(0) @binding(3) var history: texture_2d<f32>;
@group(0) @binding(4) var history_info: texture_2d<f32>;
@group(0) @binding(5) var out_color: texture_storage_2d<rgba32float, write>;
@group(0) @binding(6) var out_info: texture_storage_2d<rgba32float, write>;
// How far each pixel's point moved since the last frame besides the eye's move (camera-relative
// metres), where `t.depth.w` says the frame wrote it.
@group(0) @binding(7) var current_motion: texture_2d<f32>;

const STILL: u32 = 1u;
const MOVED: u32 = 2u;
// A pixel moving this many pixels a frame keeps one frame in its mean (at least two).
const SPEED_FRAMES: f32 = 4.0;
// Standard deviations of the neighbourhood the history may lie from its mean.
const GAMMA: f32 = 1.5;

// The history at texel position `at` (texel centres at whole numbers) from the texels whose
// neighbourhood's clip w spanned `w` (within the tolerance): premultiplied colour, and in
// `.count` the most frames any of them held (0: none agreed). A texel beside an edge spans
// both sides of it, so the edge keeps its history wherever the jitter put its sample; a
// point that was hidden behind a nearer surface falls outside (a disocclusion).
struct Fetched {
    color: vec4<f32>,
    count: f32,
}

fn fetch_history(at: vec2<f32>, w: f32, tolerance: f32) -> Fetched {
    let base = floor(at);
    let f = at - base;
    let size = vec2<i32>(t.size);
    var sum = vec4<f32>(0.0);
    var weights = 0.0;
    var count = 0.0;
    for (var i = 0; i < 4; i++) {
        let o = vec2<i32>(i & 1, i >> 1u);
        let texel = vec2<i32>(base) + o;
        if any(texel < vec2<i32>(0)) || any(texel >= size) {
            continue;
        }
        let info = textureLoad(history_info, texel, 0);
        if w < info.x - tolerance || w > info.y + tolerance {
            continue;
        }
        let fo = vec2<f32>(o);
        let bilinear = mix(1.0 - f.x, f.x, fo.x) * mix(1.0 - f.y, f.y, fo.y);
        sum += bilinear * textureLoad(history, texel, 0);
        weights += bilinear;
        count = max(count, info.z);
    }
    if weights < 1e-3 {
        return Fetched(vec4<f32>(0.0), 0.0);
    }
    if weights < 0.999 {
        // A depth edge: the texels of this surface alone, bilinearly.
        return Fetched(sum / weights, count);
    }
    // The same surface all round: Catmull-Rom over the 4x4 texels (bilinear blurs a little
    // more each frame the history is carried; the cubic keeps it sharp).
    let wx = catmull_rom(f.x);
    let wy = catmull_rom(f.y);
    var cubic = vec4<f32>(0.0);
    for (var j = 0; j < 4; j++) {
        for (var i = 0; i < 4; i++) {
            let texel = clamp(vec2<i32>(base) + vec2<i32>(i - 1, j - 1), vec2<i32>(0), size - 1);
            cubic += wx[i] * wy[j] * textureLoad(history, texel, 0);
        }
    }
    return Fetched(max(cubic, vec4<f32>(0.0)), count);
}

// Catmull-Rom weights of the texels at -1, 0, 1 and 2 for a position `f` past texel 0.
fn catmull_rom(f: f32) -> vec4<f32> {
    let f2 = f * f;
    let f3 = f2 * f;
    return vec4<f32>(
        -0.5 * f3 + f2 - 0.5 * f,
        1.5 * f3 - 2.5 * f2 + 1.0,
        -1.5 * f3 + 2.0 * f2 + 0.5 * f,
        0.5 * f3 - 0.5 * f2,
    );
}

// Clip w of this frame at pixel `q` (clamped to the image).
fn w_at(q: vec2<i32>) -> f32 {
    let c = clamp(q, vec2<i32>(0), vec2<i32>(t.size) - 1);
    return t.depth.y / (textureLoad(current_depth, c, 0).x + t.depth.x);
}

// How much clip w changes a pixel across and a pixel down at `px` (whose w is `w`), each
// the smaller of the two one-sided differences.
fn depth_slope(px: vec2<i32>, w: f32) -> f32 {
    let dx = min(abs(w_at(px + vec2<i32>(1, 0)) - w), abs(w_at(px - vec2<i32>(1, 0)) - w));
    let dy = min(abs(w_at(px + vec2<i32>(0, 1)) - w), abs(w_at(px - vec2<i32>(0, 1)) - w));
    return dx + dy;
}

@compute @workgroup_size(8, 8)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= t.size.x || id.y >= t.size.y {
        return;
    }
    let px = vec2<i32>(id.xy);
    let now = textureLoad(current, px, 0);
    // The nearest and farthest depth of the 3x3 neighbourhood (kept with the history), and
    // the range of its colours (what the history is clamped to).
    let d = textureLoad(current_depth, px, 0).x;
    var near = d;
    var far = d;
    var m1 = vec4<f32>(0.0);
    var m2 = vec4<f32>(0.0);
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            let q = clamp(px + vec2<i32>(i, j), vec2<i32>(0), vec2<i32>(t.size) - 1);
            let dq = textureLoad(current_depth, q, 0).x;
            near = min(near, dq);
            far = max(far, dq);
            let c = textureLoad(current, q, 0);
            m1 += c;
            m2 += c * c;
        }
    }
    // The box the history is clipped to: the neighbourhood's mean within GAMMA standard
    // deviations (variance clipping: tighter than its whole range where one odd pixel, the
    // far side of an edge, would let an old colour through).
    let mean = m1 / 9.0;
    let sigma = sqrt(max(m2 / 9.0 - mean * mean, vec4<f32>(0.0)));
    let lo = mean - GAMMA * sigma;
    let hi = mean + GAMMA * sigma;
    let w = t.depth.y / (d + t.depth.x);
    var color = now;
    var frames = 1.0;
    var motion = vec3<f32>(0.0);
    if t.depth.w != 0.0 {
        motion = textureLoad(current_motion, px, 0).xyz;
    }
    let moving = any(motion != vec3<f32>(0.0));
    if t.mode == STILL && !moving {
        let info = textureLoad(history_info, px, 0);
        frames = min(info.z + 1.0, f32(t.cap));
        color = mix(textureLoad(history, px, 0), now, 1.0 / frames);
    } else if t.mode == MOVED || t.mode == STILL {
        let size = vec2<f32>(t.size);
        let centre = vec2<f32>(id.xy) + 0.5;
        let ndc = vec2<f32>(centre.x / size.x * 2.0 - 1.0, 1.0 - centre.y / size.y * 2.0);
        // Where the point was: (ndc, d, 1) is its clip position over its clip w, and its own
        // motion is taken off in the last frame's clip space over the same w.
        let clip = t.reproject * vec4<f32>(ndc, d, 1.0) - t.last * vec4<f32>(motion / w, 0.0);
        if clip.w > 0.0 {
            let then = clip.xy / clip.w;
            let at = vec2<f32>(then.x * 0.5 + 0.5, 0.5 - then.y * 0.5) * size - 0.5;
            // `reproject` takes (ndc, d, 1), the point over this frame's clip w: the last
            // frame's clip w of the point is its w times this frame's.
            let then_w = clip.w * w;
            // Within a fraction of the distance, and what the surface's own slope spans over
            // two pixels here (ground seen at a grazing angle changes its distance by more
            // than a tenth a pixel): the smaller difference to a neighbour each way, so that
            // an edge beside the pixel does not widen it.
            let slope = depth_slope(px, w);
            let h = fetch_history(at, then_w, t.depth.z * then_w + 2.0 * slope * then_w / w);
            if h.count > 0.0 {
                // The faster the pixel moves, the more each resample of the history blurs it:
                // a moving pixel keeps fewer frames.
                let speed = length(at - vec2<f32>(id.xy));
                frames = min(min(h.count + 1.0, f32(t.cap)), max(SPEED_FRAMES / speed, 2.0));
                color = mix(clamp(h.color, lo, hi), now, 1.0 / frames);
            }
        }
    }
    textureStore(out_color, px, color);
    let w_of = t.depth.y / (vec2<f32>(near, far) + t.depth.x);
    textureStore(out_info, px, vec4<f32>(w_of, frames, 0.0));
}
