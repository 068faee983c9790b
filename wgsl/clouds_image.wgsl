// instead of: clouds_seen (shader::source_for, where the visibility method keeps the clouds' image)
// The clouds' image (src/gpu/visibility/clouds.rs): where the temporal service runs, the
// visibility and hybrid methods march the clouds along one pixel of each 4x4 block a frame
// (`march_clouds`) and carry the other fifteen over from the last frame's image
// (`reproject_clouds`); the shading then reads each ray's clouds from the image and cuts
// them at its surface. A pixel keeps its ray's whole march, to where the ray leaves the
// layer, and where along the ray the light was taken (`CloudMarch`: first, half, last): a
// surface in front of `first` has no cloud before it, one past `last` all of them, and one
// between takes the light taken up to it, as if it were taken evenly between those points.
// Composed into the visibility and hybrid modules after vis_common.wgsl (`vis`).

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

// The pixel (from the top left) that homogeneous camera-relative `p` falls in through `m`,
// or (-1, -1) where it lies behind the eye or outside the image.
fn cloud_pixel(m: mat4x4<f32>, p: vec4<f32>) -> vec2<i32> {
    let clip = m * p;
    if clip.w <= 0.0 {
        return vec2<i32>(-1);
    }
    let ndc = clip.xy / clip.w;
    let at = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2<f32>(vis.size);
    if any(at < vec2<f32>(0.0)) || any(at >= vec2<f32>(vis.size)) {
        return vec2<i32>(-1);
    }
    return vec2<i32>(at);
}

// The ray through the centre of the image's pixel `px`.
fn cloud_ray(px: vec2<u32>) -> vec3<f32> {
    let at = (vec2<f32>(px) + 0.5) / vec2<f32>(vis.size);
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
// read from the image where the frame keeps one and `dir` is in it; else marched (a ray that
// leaves the image is the water's reflection: a quarter of the steps).
fn clouds_along(r: RenderUniforms, dir: vec3<f32>, far: f32) -> CloudLight {
    let steps = u32(r.cloud_march.y);
    if cloud_frame.phase.w == 0u {
        return cloud_march(r, dir, far, steps).seen;
    }
    let px = cloud_pixel(cloud_frame.now, vec4<f32>(dir, 0.0));
    if px.x < 0 {
        return cloud_march(r, dir, far, max(steps / 4u, 8u)).seen;
    }
    return cloud_cut(textureLoad(cloud_light_now, px, 0), textureLoad(cloud_depth_now, px, 0), far);
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
    var clip = cloud_frame.last * vec4<f32>(dir, 0.0);
    var q = cloud_pixel(cloud_frame.last, vec4<f32>(dir, 0.0));
    var nearer = 0.0;
    if q.x >= 0 && textureLoad(cloud_light_last, q, 0).w < 1.0 {
        let d = textureLoad(cloud_depth_last, q, 0).w;
        let then = dir * d + cloud_frame.shift.xyz;
        clip = cloud_frame.last * vec4<f32>(then, 1.0);
        nearer = length(then) - d;
    }
    if clip.w <= 0.0 {
        return out;
    }
    let ndc = clip.xy / clip.w;
    let at = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2<f32>(vis.size) - 0.5;
    let size = vec2<i32>(vis.size);
    if any(at < vec2<f32>(-0.5)) || any(at > vec2<f32>(size) - 0.5) {
        return out;
    }
    let base = vec2<i32>(floor(at));
    let f = at - floor(at);
    var cloudy = 0.0;
    for (var k = 0; k < 4; k++) {
        let o = vec2<i32>(k & 1, k >> 1);
        let w = mix(1.0 - f.x, f.x, f32(o.x)) * mix(1.0 - f.y, f.y, f32(o.y));
        let p = clamp(base + o, vec2<i32>(0), size - 1);
        let light = textureLoad(cloud_light_last, p, 0);
        out.light += w * light;
        if light.w < 1.0 {
            out.depth += w * textureLoad(cloud_depth_last, p, 0);
            cloudy += w;
        }
    }
    if cloudy > 0.0 && out.light.w < 1.0 {
        out.depth = max(out.depth / cloudy - vec4<f32>(nearer), vec4<f32>(0.0));
    } else {
        out.light = vec4<f32>(out.light.rgb, 1.0);
        out.depth = vec4<f32>(1e30);
    }
    out.ok = true;
    return out;
}

// Marches the ray through the centre of pixel `px` to where it leaves the layer and stores
// what it found in this frame's image.
fn store_cloud_march(px: vec2<u32>) {
    let m = cloud_march(r, cloud_ray(px), 1e30, u32(r.cloud_march.y));
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
    if any(px >= vis.size) {
        return;
    }
    store_cloud_march(px);
}

// Every other pixel: what it carried over, or marched where it carried nothing.
@compute @workgroup_size(8, 8)
fn reproject_clouds(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= vis.size) || all(id.xy % 4u == cloud_frame.phase.xy) {
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
