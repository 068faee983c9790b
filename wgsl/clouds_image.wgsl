// instead of: clouds_seen (shader::source_for, where the visibility method keeps the clouds' image)
// The clouds' image (src/gpu/visibility/clouds.rs), half the frame's size each way: where the
// temporal service runs, the visibility and hybrid methods march the clouds along one pixel of
// each 4x4 block a frame (`march_clouds`) and carry the other fifteen over from the last
// frame's image (`reproject_clouds`); the shading then reads each ray's clouds from the image
// and cuts them at its surface. A pixel keeps its ray's whole march, to where the ray leaves the
// layer, and where along the ray the light was taken (`CloudMarch`: first, half, last): a
// surface in front of `first` has no cloud before it, one past `last` all of them, and one
// between takes the light taken up to it, as if it were taken evenly between those points.
// Composed into the visibility and hybrid modules (the uniforms `r` they declare).

struct CloudFrame {
    // The camera-relative projection times view of this frame (unjittered: the image's pixels
    // are the same rays in every frame of a still view), its inverse, and the last frame's.
    now: mat4x4<f32>,
    inv: mat4x4<f32>,
    last: mat4x4<f32>,
    // xyz: a point of the clouds at camera-relative p in this frame was at p + shift,
    // camera-relative, in the last (the eye's move less the wind's drift).
    shift: vec4<f32>,
    // x, y: the pixel of each 4x4 block marched this frame; z: 1 where every pixel is (no
    // history); w: 1 where the shading reads the image.
    phase: vec4<u32>,
    // x, y: the image's size, half the frame's (rounded up).
    size: vec4<u32>,
    // The shadows' map: x, y the camera-relative x and z of its grid's origin (a texel corner
    // fixed in the clouds' space, so the wind carries the grid with the clouds), z its texel
    // (metres), w its texels a side.
    shadow: vec4<f32>,
}

@group(0) @binding(30) var<uniform> cloud_frame: CloudFrame;
// The image this frame: the light scattered towards the eye (linear) and the light kept;
// first, half, last and the clouds' mean distance (`CloudLight::dist`), metres.
@group(0) @binding(31) var cloud_light_now: texture_2d<f32>;
@group(0) @binding(32) var cloud_depth_now: texture_2d<f32>;
// The last frame's, which the passes read, and this frame's as they write it.
@group(0) @binding(33) var cloud_light_last: texture_2d<f32>;
@group(0) @binding(34) var cloud_depth_last: texture_2d<f32>;
@group(0) @binding(35) var cloud_light_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(36) var cloud_depth_out: texture_storage_2d<rgba32float, write>;
// The clouds' shadows on the plane of their base around the eye (`shadow_clouds`): the light
// that reaches the base from the sun, which is what reaches any point below it along the same
// sun ray (x: marched in four samples, the ground's shadows; y: in one, the air's, as
// `cloud_shadow_air` marches it where there is no map); the shading reads it, the pass writes
// it.
@group(0) @binding(37) var cloud_shadow_map: texture_2d<f32>;
@group(0) @binding(38) var cloud_shadow_out: texture_storage_2d<rg32float, write>;

// Where homogeneous camera-relative `p` falls in the image through `m`, in its pixels from the
// top left (pixel centres at +0.5), or (-1e9, -1e9) where it lies behind the eye.
fn cloud_at(m: mat4x4<f32>, p: vec4<f32>) -> vec2<f32> {
    let clip = m * p;
    if clip.w <= 0.0 {
        return vec2<f32>(-1e9);
    }
    let ndc = clip.xy / clip.w;
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2<f32>(cloud_frame.size.xy);
}

// The image's pixel that homogeneous camera-relative `p` falls in through `m`, or (-1, -1)
// where it lies behind the eye or outside the image.
fn cloud_pixel(m: mat4x4<f32>, p: vec4<f32>) -> vec2<i32> {
    let at = cloud_at(m, p);
    if any(at < vec2<f32>(0.0)) || any(at >= vec2<f32>(cloud_frame.size.xy)) {
        return vec2<i32>(-1);
    }
    return vec2<i32>(at);
}

// The image's four pixels nearest `at` (`cloud_at`), clamped into it, and their weights.
struct CloudTexels {
    px: array<vec2<i32>, 4>,
    w: vec4<f32>,
}

fn cloud_texels(at: vec2<f32>) -> CloudTexels {
    let p = at - 0.5;
    let base = vec2<i32>(floor(p));
    let f = p - floor(p);
    let last = vec2<i32>(cloud_frame.size.xy) - 1;
    var out: CloudTexels;
    for (var k = 0; k < 4; k++) {
        let o = vec2<i32>(k & 1, k >> 1);
        out.px[k] = clamp(base + o, vec2<i32>(0), last);
        out.w[k] = mix(1.0 - f.x, f.x, f32(o.x)) * mix(1.0 - f.y, f.y, f32(o.y));
    }
    return out;
}

// The ray through the centre of the image's pixel `px`.
fn cloud_ray(px: vec2<u32>) -> vec3<f32> {
    let at = (vec2<f32>(px) + 0.5) / vec2<f32>(cloud_frame.size.xy);
    let near = cloud_frame.inv * vec4<f32>(at.x * 2.0 - 1.0, 1.0 - at.y * 2.0, 0.0, 1.0);
    return normalize(near.xyz / near.w);
}

// The clouds a pixel's image holds (`light`, `depth`) in front of a surface `far` away.
fn cloud_cut(light: vec4<f32>, depth: vec4<f32>, far: f32) -> CloudLight {
    let all = 1.0 - light.w;
    if all <= 0.0 || far <= depth.x {
        return cloud_none();
    }
    if far >= depth.z {
        return CloudLight(light.w, light.rgb, depth.w);
    }
    // The share of the light taken by `half`, and by `far` along straight lines between
    // first, half and last.
    let at_half = select(0.5 * all, 0.5, all > 0.5);
    var taken = at_half * (far - depth.x) / max(depth.y - depth.x, 1e-3);
    if far > depth.y {
        taken = at_half + (all - at_half) * (far - depth.y) / max(depth.z - depth.y, 1e-3);
    }
    taken = clamp(taken, 0.0, all);
    return CloudLight(1.0 - taken, light.rgb * (taken / all), min(depth.w, 0.5 * (depth.x + far)));
}

// What the clouds between the eye and `far` along unit `dir` do (`CloudLight`, shade.wgsl):
// read from the image where the frame keeps one and `dir` is in it (between its four nearest
// pixels, each cut at `far`); else marched (a ray that leaves the image is the water's
// reflection: a quarter of the steps).
fn clouds_along(r: RenderUniforms, dir: vec3<f32>, far: f32) -> CloudLight {
    var steps = u32(r.cloud_march.y);
    if cloud_frame.phase.w != 0u {
        let at = cloud_at(cloud_frame.now, vec4<f32>(dir, 0.0));
        if all(at >= vec2<f32>(0.0)) && all(at <= vec2<f32>(cloud_frame.size.xy)) {
            let t = cloud_texels(at);
            var out = CloudLight(0.0, vec3<f32>(0.0), 0.0);
            // The clouds' distance weighted by the light each texel's clouds take, as the
            // march weights it (a clear texel's distance is none).
            var taken = 0.0;
            for (var k = 0; k < 4; k++) {
                let c = cloud_cut(textureLoad(cloud_light_now, t.px[k], 0), textureLoad(cloud_depth_now, t.px[k], 0), far);
                out.keep += t.w[k] * c.keep;
                out.light += t.w[k] * c.light;
                let w = t.w[k] * (1.0 - c.keep);
                out.dist += w * c.dist;
                taken += w;
            }
            out.dist = select(0.0, out.dist / taken, taken > 0.0);
            return out;
        }
        steps = max(steps / 4u, 8u);
    }
    // One call of the march in the module: each call is compiled, and the march is most of a
    // shading pipeline's build.
    return cloud_march(r, dir, far, steps).seen;
}

// The light of the sun that the clouds let through to camera-relative `rel` (1 without
// clouds): below the base, read from the shadows' map between its four nearest texels where
// the sun ray meets the base within it; elsewhere marched. (Its march is called in three
// places: with one call after the map's branch, lavapipe's compiler crashed on the shading.)
fn cloud_shadow(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    if cloud_frame.phase.w == 0u || r.clouds.x <= 0.0 {
        return cloud_shadow_march(r, rel);
    }
    let below = r.clouds.y - (r.cloud_march.x + rel.y);
    if below <= 0.0 {
        return cloud_shadow_march(r, rel);
    }
    let s = cloud_sun(r);
    let base = rel.xz + s.xz * (below / s.y);
    let p = cloud_map_texel(base);
    let n = cloud_frame.shadow.w;
    if any(p < vec2<f32>(0.0)) || any(p > vec2<f32>(n - 1.0)) {
        return cloud_shadow_march(r, rel);
    }
    return cloud_map_read(p).x;
}

// Where the shadows' map holds camera-relative `xz` on the base, in its texels (centres at
// whole numbers).
fn cloud_map_texel(xz: vec2<f32>) -> vec2<f32> {
    return (xz - cloud_frame.shadow.xy) / cloud_frame.shadow.z - 0.5;
}

// The shadows' map at texel `p` (within it), bilinearly: the ground's and the air's.
fn cloud_map_read(p: vec2<f32>) -> vec2<f32> {
    let n = cloud_frame.shadow.w;
    let i = vec2<i32>(floor(p));
    let f = p - floor(p);
    let last = i32(n) - 1;
    let a = textureLoad(cloud_shadow_map, i, 0).xy;
    let b = textureLoad(cloud_shadow_map, min(i + vec2<i32>(1, 0), vec2<i32>(last)), 0).xy;
    let c = textureLoad(cloud_shadow_map, min(i + vec2<i32>(0, 1), vec2<i32>(last)), 0).xy;
    let d = textureLoad(cloud_shadow_map, min(i + vec2<i32>(1, 1), vec2<i32>(last)), 0).xy;
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

// The sun's light the clouds let through to camera-relative `rel` in the air below their base,
// for the light shafts (`cloud_shafts`): the shadows' map's, as `clouds_seen.wgsl` marches it
// (one sample halfway through the layer), which beyond the map and where the frame keeps no
// image is marched here too.
fn cloud_shadow_air(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    if cloud_frame.phase.w == 0u {
        return cloud_shadow_steps(r, rel, 1u);
    }
    let below = max(r.clouds.y - (r.cloud_march.x + rel.y), 0.0);
    let s = cloud_sun(r);
    let p = cloud_map_texel(rel.xz + s.xz * (below / s.y));
    if any(p < vec2<f32>(0.0)) || any(p > vec2<f32>(cloud_frame.shadow.w - 1.0)) {
        return cloud_shadow_steps(r, rel, 1u);
    }
    return cloud_map_read(p).y;
}

// The light shafts' points along a view ray (`cloud_shafts`): 12 reads of the shadows' map, or
// 6 marches where the frame keeps no image.
fn cloud_shaft_steps() -> u32 {
    return select(6u, 12u, cloud_frame.phase.w != 0u);
}

// The shadows' map: each texel the light that reaches the base from the sun at its centre.
@compute @workgroup_size(8, 8)
fn shadow_clouds(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = u32(cloud_frame.shadow.w);
    if any(id.xy >= vec2<u32>(n)) {
        return;
    }
    let xz = cloud_frame.shadow.xy + (vec2<f32>(id.xy) + 0.5) * cloud_frame.shadow.z;
    let rel = vec3<f32>(xz.x, r.clouds.y - r.cloud_march.x, xz.y);
    let ground = cloud_shadow_march(r, rel);
    let air = cloud_shadow_steps(r, rel, 1u);
    textureStore(cloud_shadow_out, id.xy, vec4<f32>(ground, air, 0.0, 1.0));
}

// The last frame's clouds along `dir` where they were then (their mean distance read
// where the ray's direction was, moved by the eye and the wind), their distances moved by how
// much nearer the eye came; `ok` false where they were outside the last image. Read between
// the last image's four nearest pixels (a nearest pixel's would hold a slowly moving view's
// clouds still until they are marched again), the distances from those with clouds.
struct CloudCarried {
    light: vec4<f32>,
    depth: vec4<f32>,
    ok: bool,
}

fn cloud_carried(dir: vec3<f32>) -> CloudCarried {
    var out = CloudCarried(vec4<f32>(0.0), vec4<f32>(0.0), false);
    var at = cloud_at(cloud_frame.last, vec4<f32>(dir, 0.0));
    let q = cloud_pixel(cloud_frame.last, vec4<f32>(dir, 0.0));
    var nearer = 0.0;
    if q.x >= 0 && textureLoad(cloud_light_last, q, 0).w < 1.0 {
        let d = textureLoad(cloud_depth_last, q, 0).w;
        let then = dir * d + cloud_frame.shift.xyz;
        at = cloud_at(cloud_frame.last, vec4<f32>(then, 1.0));
        nearer = length(then) - d;
    }
    if any(at < vec2<f32>(0.0)) || any(at > vec2<f32>(cloud_frame.size.xy)) {
        return out;
    }
    let t = cloud_texels(at);
    var cloudy = 0.0;
    var low = vec4<f32>(1e30);
    var high = vec4<f32>(-1e30);
    for (var k = 0; k < 4; k++) {
        let light = textureLoad(cloud_light_last, t.px[k], 0);
        low = min(low, light);
        high = max(high, light);
        if light.w < 1.0 {
            out.depth += t.w[k] * textureLoad(cloud_depth_last, t.px[k], 0);
            cloudy += t.w[k];
        }
    }
    out.light = clamp(cloud_bicubic(at), low, high);
    if cloudy > 0.0 && out.light.w < 1.0 {
        out.depth = max(out.depth / cloudy - vec4<f32>(nearer), vec4<f32>(0.0));
    } else {
        out.light = vec4<f32>(out.light.rgb, 1.0);
        out.depth = vec4<f32>(1e30);
    }
    out.ok = true;
    return out;
}

// The last image's light at `at` (`cloud_at`) through a Catmull-Rom filter over its 4x4
// nearest pixels: a bilinear read carried over frame after frame would blur the clouds.
fn cloud_bicubic(at: vec2<f32>) -> vec4<f32> {
    let p = at - 0.5;
    let base = vec2<i32>(floor(p)) - 1;
    let f = p - floor(p);
    let f2 = f * f;
    let f3 = f2 * f;
    let wx = array<f32, 4>(
        0.5 * (-f3.x + 2.0 * f2.x - f.x),
        0.5 * (3.0 * f3.x - 5.0 * f2.x + 2.0),
        0.5 * (-3.0 * f3.x + 4.0 * f2.x + f.x),
        0.5 * (f3.x - f2.x),
    );
    let wy = array<f32, 4>(
        0.5 * (-f3.y + 2.0 * f2.y - f.y),
        0.5 * (3.0 * f3.y - 5.0 * f2.y + 2.0),
        0.5 * (-3.0 * f3.y + 4.0 * f2.y + f.y),
        0.5 * (f3.y - f2.y),
    );
    let last = vec2<i32>(cloud_frame.size.xy) - 1;
    var sum = vec4<f32>(0.0);
    for (var j = 0; j < 4; j++) {
        for (var i = 0; i < 4; i++) {
            let q = clamp(base + vec2<i32>(i, j), vec2<i32>(0), last);
            sum += wx[i] * wy[j] * textureLoad(cloud_light_last, q, 0);
        }
    }
    return sum;
}

// Marches the ray through the centre of pixel `px` to where it leaves the layer and stores
// what it found in this frame's image.
fn store_cloud_march(px: vec2<u32>) {
    let dir = cloud_ray(px);
    // A ray going down meets the ground (at or above 0 m) before it can meet the layer, if it
    // comes down to 0 m along the planet's curve as the layer does (`cloud_cross`): the march
    // stops there. A ray that never does may meet the layer beyond the drawn land, in the sky.
    let g = cloud_cross(r.cloud_march.x, dir.y, 0.0);
    let ground = select(1e30, g.x, dir.y < 0.0 && g.x > 0.0);
    let m = cloud_march(r, dir, ground, u32(r.cloud_march.y));
    textureStore(cloud_light_out, px, vec4<f32>(m.seen.light, m.seen.keep));
    textureStore(cloud_depth_out, px, vec4<f32>(m.first, m.half, m.last, m.seen.dist));
}

// One pixel of each 4x4 block (the phase's), or every pixel where the frame has no history.
@compute @workgroup_size(8, 8)
fn march_clouds(@builtin(global_invocation_id) id: vec3<u32>) {
    var px = id.xy;
    if cloud_frame.phase.z == 0u {
        px = id.xy * 4u + cloud_frame.phase.xy;
    }
    if any(px >= cloud_frame.size.xy) {
        return;
    }
    store_cloud_march(px);
}

// Every other pixel: what it carried over, or marched where it carried nothing.
@compute @workgroup_size(8, 8)
fn reproject_clouds(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= cloud_frame.size.xy) || all(id.xy % 4u == cloud_frame.phase.xy) {
        return;
    }
    let c = cloud_carried(cloud_ray(id.xy));
    if !c.ok {
        store_cloud_march(id.xy);
        return;
    }
    textureStore(cloud_light_out, id.xy, c.light);
    textureStore(cloud_depth_out, id.xy, c.depth);
}
