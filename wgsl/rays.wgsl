// The ray casters' entry points, shared by the tile's (raymarch.wgsl) and the endless world's
// (world_rays.wgsl) casters, composed after either: a compute shader writing storage textures
// and a full-screen fragment shader writing two colour targets. The file before this one
// declares `ray` (with `width`, `height`, `inv_view_proj`, `max_steps`, `march_octaves`,
// `step_factor`, `hit_k`, `relax` and `octaves`), `color_out`, `distance_out`, `cast_pixel(pixel) -> (colour,
// distance)` and `march_height(xz, octaves) -> height` (what the seed's march steps against).

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
    var lo = lo_in;
    var hi = hi_in;
    for (var k = 0; k < 24; k++) {
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

@compute @workgroup_size(8, 8, 1)
fn raymarch_cs(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= ray.width || id.y >= ray.height {
        return;
    }
    let c = cast_pixel(vec2<f32>(id.xy) + 0.5);
    textureStore(color_out, vec2<i32>(id.xy), vec4<f32>(c.rgb, 1.0));
    textureStore(distance_out, vec2<i32>(id.xy), vec4<f32>(c.w, 0.0, 0.0, 0.0));
}

@vertex
fn fullscreen_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // One triangle covering the viewport.
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0);
}

struct FragmentOut {
    @location(0) color: vec4<f32>,
    @location(1) distance: vec4<f32>,
}

@fragment
fn raymarch_fs(@builtin(position) position: vec4<f32>) -> FragmentOut {
    let c = cast_pixel(position.xy);
    var out: FragmentOut;
    out.color = vec4<f32>(c.rgb, 1.0);
    out.distance = vec4<f32>(c.w, 0.0, 0.0, 0.0);
    return out;
}
