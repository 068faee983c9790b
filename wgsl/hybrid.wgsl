// import: shade, world_rays, march, vis_common, props_map
// with: terrain_air_map
// The hybrid method (src/gpu/visibility.rs, the endless world): the clipmap mesh, each level's
// vertices raised by a bound on how far the continuous surface rises above that level's mesh
// (clipmap::level_raise), is rasterised by the visibility method's raster pass. Where a
// sample's ray meets the raised mesh it is in front of the surface, so a short march in compute
// from there finds the continuous surface (every octave): the reference's conservative steps
// (world_rays.wgsl's safe_step), each at least HYBRID_FLOOR of a pixel's footprint, and the
// crossing bisected HYBRID_HALVINGS times and landed by a secant. The silhouettes and the surface are the continuous
// surface's, not the mesh's: a ray that passes through the raised shell without meeting the
// surface shows the sky. Each sample is shaded from the continuous surface's normal and colour
// channel, octaves finer than the sample's footprint faded out (as raymarch-bandlimited does),
// and from the light bake's horizon and valley depth at the raster's point.
//
// Composed after shade.wgsl, noise.wgsl, landscape.wgsl, world_rays.wgsl (without its
// bindings), march.wgsl and vis_common.wgsl: a module of its own, apart from the visibility
// method's (which holds the world's raster pass), with only what its compute pass needs.

@group(0) @binding(0) var<uniform> r: RenderUniforms;
@group(0) @binding(18) var<uniform> ray: WorldRayUniforms;

// Steps a ray may take from the raised mesh; one that has not met the surface by then is drawn
// where it stopped.
const HYBRID_STEPS: u32 = 64u;
// The shortest step, in pixel footprints along the ray, at first: a bump narrower than that
// along the ray can be stepped over. It grows by HYBRID_FLOOR_GROWTH a step, so that a grazing
// ray, which can skim a thick shell for hundreds of footprints, meets the surface within the
// step limit (at the price of coarser steps the longer it skims).
const HYBRID_FLOOR: f32 = 2.0;
const HYBRID_FLOOR_GROWTH: f32 = 1.15;
// Halvings of the last step (a sixteenth of it), before the secant lands the hit.
const HYBRID_HALVINGS: u32 = 4u;

// Height of the point `q` above the continuous surface (every octave).
fn clearance(q: vec3<f32>) -> f32 {
    return q.y - march_height(q.xz, ray.octaves);
}

// The crossing within `span` (lo, hi), the ray above the surface at lo and under it at hi:
// HYBRID_HALVINGS halvings, then the secant through the clearances at the ends of what is
// left. Halvings alone land anywhere within the last interval, and where that interval falls
// depends on where the march started, which moves with the eye: a 1 cm step of the eye moved
// the hybrid's picture 1.2-2.1 times as much as the reference's (docs/results/stability.md,
// distance). The secant lands on the surface to second order where it is smooth across the interval.
fn land_hit(ro: vec3<f32>, dir: vec3<f32>, span: vec2<f32>) -> f32 {
    var lo = span.x;
    var hi = span.y;
    var f_lo = clearance(ro + lo * dir);
    var f_hi = clearance(ro + hi * dir);
    for (var k = 0u; k < HYBRID_HALVINGS; k++) {
        let mid = 0.5 * (lo + hi);
        let f = clearance(ro + mid * dir);
        if f > 0.0 {
            lo = mid;
            f_lo = f;
        } else {
            hi = mid;
            f_hi = f;
        }
    }
    let w = f_lo / max(f_lo - f_hi, 1e-30);
    // A NaN clearance (w != w) keeps the halvings' bracket start rather than a NaN depth.
    return select(mix(lo, hi, clamp(w, 0.0, 1.0)), lo, w != w);
}

// Distance along the unit camera-relative `dir` to the continuous surface, searched from `t0`
// (where the ray meets the raised mesh), or MISS where it leaves the drawn region first. Where
// the raise fell short (the ray is under the surface at `t0`) the mesh's point stands; a ray out
// of steps is drawn where it stopped.
fn refine(dir: vec3<f32>, t0: f32) -> f32 {
    let ro = ray.eye.xyz;
    let span = clip_region(ro, dir);
    let slope = length(dir.xz);
    var t = max(t0, span.x);
    var t_prev = t;
    var crossed = false;
    var floor = HYBRID_FLOOR * ray.pixel_angle;
    for (var i = 0u; i < HYBRID_STEPS; i++) {
        let step = safe_step(ro + t * dir, slope, dir.y, false);
        crossed = step <= 0.0;
        // One exit: with the region's end tested apart, lavapipe (Mesa 22.3) crashed.
        if crossed || t > span.y {
            break;
        }
        t_prev = t;
        t += max(step, floor * t);
        floor *= HYBRID_FLOOR_GROWTH;
    }
    var hit = t;
    if crossed {
        hit = land_hit(ro, dir, vec2<f32>(t_prev, t));
    }
    return select(hit, MISS, hit > span.y);
}

// Depth of the camera-relative point `rel` in the raster pass's (and the host's) depth range.
fn depth_of(rel: vec3<f32>) -> f32 {
    let clip_w = dot(vis.w_row.xyz, rel) + vis.w_row.w;
    return clamp(vis.depth.y / clip_w - vis.depth.x, 0.0, 1.0);
}

// (linear colour, depth) of the sample at `pixel` whose raster depth is `d` (1: no mesh), with
// the light bake's horizon `horizon` and `valley` there; the depth is 1 where it shows the sky.
// `footprint` is the sample's share of a pixel's footprint (1 a sample a pixel, 0.5 at four).
fn hybrid_sample(lin: RenderUniforms, pixel: vec2<f32>, d: f32, horizon: f32, valley: f32, footprint: f32) -> vec4<f32> {
    let dir = sample_ray(pixel);
    var t = MISS;
    if d < 1.0 {
        t = refine(dir, length(point_at(dir, d)));
    }
    var out = vec4<f32>(sky_pixel(lin, dir), 1.0);
    if t >= 0.0 {
        let p = ray.eye.xyz + t * dir;
        let fade = t * ray.pixel_angle * footprint;
        let g = world_channel(p.xz, ray.octaves, CHANNEL_HEIGHT, fade);
        let n = normalize(vec3<f32>(-g.y * ray.peak, 1.0, -g.z * ray.peak));
        let tint = world_channel(p.xz, ray.octaves, CHANNEL_COLOR, fade).x;
        let rel = t * dir;
        let color = shade(lin, rel, n, g.x, tint, occlusion(lin, g.x, horizon, valley) * props_map_at(rel));
        out = vec4<f32>(color, min(depth_of(rel), 0.99999994));
    }
    return out;
}

@compute @workgroup_size(8, 8)
fn hybrid_samples(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let px = vec2<i32>(id.xy);
    let lin = linear_uniforms();
    var sum = vec3<f32>(0.0);
    var covered = 0u;
    var nearest = 1.0;
    for (var i = 0; i < 4; i++) {
        let d = textureLoad(depth_ms, px, i);
        if d >= 1.0 && vis.sky == 0u {
            continue;
        }
        let s = textureLoad(surface_ms, px, i);
        let valley = textureLoad(valley_ms, px, i).x;
        let c = hybrid_sample(lin, vec2<f32>(id.xy) + SAMPLES[i], d, s.w, valley, 0.5);
        if c.w < 1.0 {
            covered += 1u;
            nearest = min(nearest, c.w);
        } else if vis.sky == 0u {
            continue;
        }
        sum += c.rgb;
    }
    store_pixel(px, sum, 4u, covered, nearest);
}

@compute @workgroup_size(8, 8)
fn hybrid_pixels(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let px = vec2<i32>(id.xy);
    hybrid_pixel(px, textureLoad(depth_1, px, 0));
}

// The same from the compute raster's depth (raster.wgsl).
@compute @workgroup_size(8, 8)
fn hybrid_rasterised(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    hybrid_pixel(vec2<i32>(id.xy), rasterised_depth(id.xy));
}

// Refines, shades and stores the pixel `px` whose one sample's raster depth is `d`.
fn hybrid_pixel(px: vec2<i32>, d: f32) {
    var c = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    if d < 1.0 || vis.sky != 0u {
        let s = textureLoad(surface_1, px, 0);
        let valley = textureLoad(valley_1, px, 0).x;
        c = hybrid_sample(linear_uniforms(), vec2<f32>(px) + 0.5, d, s.w, valley, 1.0);
    }
    let covered = u32(c.w < 1.0);
    if covered == 0u && vis.sky == 0u {
        c = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    store_pixel(px, c.rgb, 1u, covered, c.w);
}
