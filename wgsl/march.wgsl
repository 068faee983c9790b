// part of: rays, hybrid (the caster it calls comes from raymarch or world_rays)
// The ray casters' march, shared by the tile's (raymarch.wgsl) and the endless world's
// (world_rays.wgsl) casters and by the hybrid method's refinement (hybrid.wgsl), composed after
// a caster's file. That file declares `ray` (with `width`, `height`, `inv_view_proj`,
// `max_steps`, `march_octaves`, `step_factor`, `hit_k`, `relax` and `octaves`) and
// `march_height(xz, octaves) -> height` (what the seed's march steps against).

// Distance stored for pixels that hit nothing, and for rays that ran out of steps.
const MISS: f32 = -1.0;
const UNRESOLVED: f32 = -2.0;

// The point on the far plane under the centre of `pixel` (pixels from the top left), in the
// space `ray.inv_view_proj` leads to.
fn pixel_far(pixel: vec2<f32>) -> vec3<f32> {
    let size = vec2<f32>(f32(ray.width), f32(ray.height));
    let ndc = vec2<f32>(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y);
    let far = ray.inv_view_proj * vec4<f32>(ndc, 1.0, 1.0);
    return far.xyz / far.w;
}

// The crossing of the surface (every octave) between distances `lo` (on the side the ray
// started: `below` it or above) and `hi` (past it), to 24 halvings: the reference's last step.
fn bisect(ro: vec3<f32>, rd: vec3<f32>, lo_in: f32, hi_in: f32, below: bool) -> f32 {
    return bisect_n(ro, rd, vec2<f32>(lo_in, hi_in), below, 24u);
}

// The same to `halvings` halvings of the interval `span` (lo, hi).
fn bisect_n(ro: vec3<f32>, rd: vec3<f32>, span: vec2<f32>, below: bool, halvings: u32) -> f32 {
    var lo = span.x;
    var hi = span.y;
    for (var k = 0u; k < halvings; k++) {
        let mid = 0.5 * (lo + hi);
        let q = ro + mid * rd;
        if (q.y <= march_height(q.xz, ray.octaves)) == below {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

// The seed's heightfield march from `t = span.x`: t += step_factor * h, a hit when
// |h| < hit_k * t, `march_octaves` octaves; with `relax` (its relaxation variant) each step is
// multiplied by max(relax * t, 1), growing with distance. Distance, MISS or UNRESOLVED.
fn seed_march(ro: vec3<f32>, rd: vec3<f32>, span: vec2<f32>) -> f32 {
    var t = span.x;
    for (var i = 0u; i < ray.max_steps; i++) {
        let p = ro + t * rd;
        let f = p.y - march_height(p.xz, ray.march_octaves);
        if abs(f) < ray.hit_k * t {
            return t;
        }
        t += ray.step_factor * f * max(ray.relax * t, 1.0);
        if t > span.y || t < span.x {
            return MISS;
        }
    }
    return UNRESOLVED;
}
