// import: noise, shade, landscape
// part of: world_rays_io, hybrid (each declares the `r` and `ray` it reads)
// Ray casting of the endless world's continuous surface (src/landscape.rs): no texture, no
// mesh. Composed after noise.wgsl, shade.wgsl and landscape.wgsl, and before march.wgsl and
// rays.wgsl (the entry points); it declares no bindings (`r` and `ray` come from
// world_rays_io.wgsl for the casters, from hybrid.wgsl for the hybrid method). Two methods,
// chosen by `ray.method`, as for the tile (raymarch.wgsl):
//
//   0, the reference: every octave, steps bounded by the surface's slope so that they do not
//      pass through it, bisection to the crossing, normals from the analytic gradient. Stepping
//      is accelerated by adding octaves one at a time: once the clearance of the partial sum
//      exceeds the most the remaining octaves can add (their amplitude bound), the step follows
//      from the partial sum's own (smaller) slope bound, so high above the ground a step costs
//      one or two octaves. The slope bounds are measured (src/landscape.rs, slope_bounds), not
//      proven, and steps under 2 % of a pixel's footprint are not taken: what can be stepped
//      over is a sliver of a fraction of a pixel (a test measures it). The ray is bounded by
//      the region the mesh draws.
//   1, the seed's march: t += step_factor * h, a hit when |h| < hit_k * t, `march_octaves`
//      octaves while stepping and `normal_octaves` for the normal. With `band_limit`, the
//      shading (normal, colour channel, snow line) fades out each octave whose cell is under two
//      pixel footprints (gone at one): detail a pixel cannot show is not aliased into it.
//
// Positions are camera-relative f32 metres from a reference sample (an integer count of
// 2^base_log2-metre samples, the eye's sample): each octave's lattice cell is that integer
// shifted, plus the cell of the small f32 remainder, so rays far from the origin sample the
// same exact lattice as rays near it.

struct WorldRayUniforms {
    // Inverse of the camera-relative projection times view (the eye at the origin).
    inv_view_proj: mat4x4<f32>,
    // xz: the eye less the reference sample's position; y: the eye's height; metres.
    eye: vec4<f32>,
    // The reference sample, in samples of 2^base_log2 metres.
    reference: vec2<i32>,
    base_log2: i32,
    seed: u32,
    octaves: u32,
    // 0: fBm, 1: eroded fBm.
    terrain: u32,
    feature_log2: i32,
    method: u32,
    march_octaves: u32,
    normal_octaves: u32,
    max_steps: u32,
    width: u32,
    height: u32,
    gain: f32,
    // World height of normalised height 1, metres.
    peak: f32,
    // 0.5 / (sum of the octaves' amplitudes * NOISE_MAX_ABS): the normalisation.
    scale: f32,
    step_factor: f32,
    hit_k: f32,
    // Radians per pixel at the image centre: the reference's smallest step is 2 % of a pixel's
    // footprint (plus a millimetre).
    pixel_angle: f32,
    // 1: the march fades octaves finer than the pixel's footprint out of its shading.
    band_limit: u32,
    // The seed's relaxation: steps multiplied by max(relax * t, 1); 0: off.
    relax: f32,
    // The region drawn, relative to the reference sample: x0, z0, x1, z1 in metres.
    bounds: vec4<f32>,
    // Entry k: x, Lipschitz bound (metres per metre) of the height of the first k+1 octaves;
    // y, bound in metres on what the octaves after them add.
    prefix: array<vec4<f32>, 24>,
}

// Octave `o`'s lattice cell and fraction at `p` (metres from the reference sample).
fn ray_split(p: vec2<f32>, o: u32) -> Split {
    let cell_log2 = ray.feature_log2 - i32(o);
    let inv = ldexp(1.0, -cell_log2);
    var out: Split;
    if cell_log2 >= ray.base_log2 {
        // The reference's high bits are whole cells; its low bits (exact in f32) join p.
        let shift = u32(cell_log2 - ray.base_log2);
        let low = vec2<f32>(ray.reference & vec2<i32>((1 << shift) - 1));
        let local = (low * ldexp(1.0, ray.base_log2) + p) * inv;
        let fl = floor(local);
        out.cell = (ray.reference >> vec2<u32>(shift)) + vec2<i32>(fl);
        out.frac = local - fl;
    } else {
        // Cells finer than a reference sample: the reference is a whole number of them
        // (wrapping, as the hash does).
        let local = p * inv;
        let fl = floor(local);
        out.cell = (ray.reference << vec2<u32>(u32(ray.base_log2 - cell_log2))) + vec2<i32>(fl);
        out.frac = local - fl;
    }
    return out;
}

fn octave_noise(p: vec2<f32>, o: u32, channel: u32) -> NoiseD {
    let split = ray_split(p, o);
    return cell_noise_d(split.cell, split.frac, noise_stream(ray.seed, channel, o));
}

fn octave_freq(o: u32) -> f32 {
    return ldexp(1.0, i32(o) - ray.feature_log2);
}

// (normalised value, d/dx, d/dz per metre) of the channel's first `octaves` octaves at `p`,
// each octave faded by a pixel footprint of `footprint` metres (0: no fading).
fn world_channel(p: vec2<f32>, octaves: u32, channel: u32, footprint: f32) -> vec3<f32> {
    let eroded = ray.terrain == 1u && channel == CHANNEL_HEIGHT;
    var st = Octaves();
    var amplitude = 1.0;
    for (var o = 0u; o < octaves; o++) {
        let freq = octave_freq(o);
        // Full where the cell (1 / freq) spans two footprints, gone where it spans one.
        let keep = select(1.0, clamp(1.0 / (freq * footprint) - 1.0, 0.0, 1.0), footprint > 0.0);
        st = add_octave(st, octave_noise(p, o, channel), freq, amplitude * keep, eroded);
        amplitude *= ray.gain;
    }
    return vec3<f32>(0.5 + ray.scale * st.sum, ray.scale * st.grad);
}

fn world_height(p: vec2<f32>, octaves: u32) -> f32 {
    return ray.peak * world_channel(p, octaves, CHANNEL_HEIGHT, 0.0).x;
}

// What the seed's march (rays.wgsl) steps against.
fn march_height(p: vec2<f32>, octaves: u32) -> f32 {
    return world_height(p, octaves);
}

// How far the reference's ray can go from `p` without crossing the surface (> 0), or a value
// <= 0 where `p` is already past it. `slope` is |rd.xz|; `below` says which side the ray
// started on. Octaves are added until the partial sum's clearance c exceeds the bound R on the
// rest: then the full clearance is at least c - R and shrinks no faster than the partial
// sum's Lipschitz bound allows.
fn safe_step(p: vec3<f32>, slope: f32, rd_y: f32, below: bool) -> f32 {
    let eroded = ray.terrain == 1u;
    var st = Octaves();
    var amplitude = 1.0;
    for (var o = 0u; o < ray.octaves; o++) {
        st = add_octave(st, octave_noise(p.xz, o, CHANNEL_HEIGHT), octave_freq(o), amplitude, eroded);
        amplitude *= ray.gain;
        let h = ray.peak * (0.5 + ray.scale * st.sum);
        let c = select(p.y - h, h - p.y, below);
        let bound = ray.prefix[o];
        if c > bound.y || o + 1u == ray.octaves {
            // Above the sheet the clearance y - h falls at most L|rd.xz| - rd.y per unit of t;
            // below, h - y at most L|rd.xz| + rd.y.
            let rate = max(bound.x * slope + select(-rd_y, rd_y, below), 1e-6);
            return (c - bound.y) / rate;
        }
        if c < -bound.y {
            return c;
        }
    }
    return 0.0;
}

// Entry and exit distances of the unit ray through the drawn region, or (1, 0) if none.
fn clip_region(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {
    let lo = vec3<f32>(ray.bounds.x, 0.0, ray.bounds.y);
    let hi = vec3<f32>(ray.bounds.z, ray.peak * 1.0001, ray.bounds.w);
    let inv = 1.0 / rd;
    let a = (lo - ro) * inv;
    let b = (hi - ro) * inv;
    let tmin = min(a, b);
    let tmax = max(a, b);
    return vec2<f32>(max(max(tmin.x, tmin.y), max(tmin.z, 0.0)), min(min(tmax.x, tmax.y), tmax.z));
}

// Distance along the unit ray to the surface, MISS or UNRESOLVED.
fn world_intersect(ro: vec3<f32>, rd: vec3<f32>) -> f32 {
    let span = clip_region(ro, rd);
    if span.x > span.y {
        return MISS;
    }
    var t = span.x;
    if ray.method == 0u {
        // The surface is a sheet: a ray entering the region below it hits where it first
        // crosses it from below.
        let start = ro + t * rd;
        let below = start.y < world_height(start.xz, ray.octaves);
        let slope = length(rd.xz);
        var t_prev = t;
        for (var i = 0u; i < ray.max_steps; i++) {
            let p = ro + t * rd;
            let step = safe_step(p, slope, rd.y, below);
            if step <= 0.0 {
                // A crossing past the drawn square (the last step can overshoot it) is not drawn.
                let hit = bisect(ro, rd, t_prev, t, below);
                return select(hit, MISS, hit > span.y);
            }
            if t > span.y {
                return MISS;
            }
            t_prev = t;
            // A floor keeps grazing rays moving: a step of s can skip only a bump that pokes
            // less than rate * s / 2 above the ray, so a floor of 2% of a pixel's footprint
            // misses at most a hundredth of a pixel per unit of the clearance's rate.
            t += max(step, 1e-3 + 0.02 * ray.pixel_angle * t);
        }
        return UNRESOLVED;
    }
    return seed_march(ro, rd, span);
}

// The terrain's horizon towards the sun from `p` (a point of the surface, `h0` metres high),
// in radians: the light bake's quantity for the mesh (src/light.rs), over the continuous
// surface. Only elevations within the sun's disc matter (lower ones leave it wholly lit,
// higher ones wholly hidden), so the march starts from the disc's lower limb and stops once
// the disc is hidden.
//   0, the reference: horizontal steps that the slope bound makes safe against the line of
//      the steepest rise found so far (no ridge that would raise it is stepped over, bar a
//      floor of a quarter of the disc's angle), every octave, to the drawn square's edge;
//   1, the seed's shadow march: t += clamp(clearance, lo, hi) along the ray at the sun's
//      elevation, `march_octaves` octaves, 64 steps; lo and hi scale with the peak height.
const SHADOW_STEPS: u32 = 64u;

fn world_horizon(p: vec3<f32>, h0: f32) -> f32 {
    let e = r.sun_elevation;
    let flat = length(r.sun_dir.xz);
    if e + SUN_RADIUS <= 0.0 || flat < 1e-6 {
        return -1.5;
    }
    let d = r.sun_dir.xz / flat;
    let hidden = tan(min(e + SUN_RADIUS, 1.5));
    var s = tan(max(e - SUN_RADIUS, -1.5));
    if ray.method == 0u {
        let bound = ray.prefix[ray.octaves - 1u].x;
        var t = 1e-3 + 1e-3 * ray.peak;
        for (var i = 0u; i < ray.max_steps; i++) {
            let q = p.xz + t * d;
            if any(q < ray.bounds.xy) || any(q > ray.bounds.zw) || h0 + s * t > ray.peak || bound <= s {
                break;
            }
            let rise = world_height(q, ray.octaves) - h0;
            s = max(s, rise / t);
            if s >= hidden {
                break;
            }
            t += max((s * t - rise) / (bound - s), 0.25 * SUN_RADIUS * t);
        }
        return atan(s);
    }
    let tan_e = tan(e);
    let lo = 0.002 * ray.peak;
    let hi = 0.1 * ray.peak;
    var least = tan_e - s;
    var t = lo;
    for (var i = 0u; i < SHADOW_STEPS; i++) {
        let q = p.xz + t * d;
        let y = h0 + t * tan_e;
        if any(q < ray.bounds.xy) || any(q > ray.bounds.zw) || y > ray.peak {
            break;
        }
        let c = y - march_height(q, ray.march_octaves);
        least = min(least, c / t);
        if tan_e - least >= hidden {
            break;
        }
        t += clamp(c, lo, hi);
    }
    return atan(tan_e - least);
}

// How far (metres) the point at `xz`, `h0` metres high, lies above the mean height of the ring
// VALLEY_RADIUS around it, from the octaves a grid of an eighth of the radius keeps (the
// level the light bake reads the ring from).
fn world_valley(xz: vec2<f32>, h0: f32) -> f32 {
    let octaves = u32(clamp(ray.feature_log2 - i32(log2(VALLEY_RADIUS * 0.125)), 0, i32(ray.octaves)));
    var sum = 0.0;
    for (var i = 0u; i < 8u; i++) {
        let a = f32(i) * 0.78539816;
        sum += world_height(xz + VALLEY_RADIUS * vec2<f32>(cos(a), sin(a)), octaves);
    }
    return h0 - sum * 0.125;
}

// (colour, distance) for the pixel whose centre is at `pixel` (in pixels from the top left).
fn cast_pixel(pixel: vec2<f32>) -> vec4<f32> {
    // Camera-relative: the eye is at the origin.
    let rd = normalize(pixel_far(pixel));
    let t = world_intersect(ray.eye.xyz, rd);
    if t < 0.0 {
        return vec4<f32>(sky_pixel(r, rd), t);
    }
    return vec4<f32>(shade_cast(rd, t, vec2<f32>(1.0)), t);
}

// The colour of the surface the cast met at distance `t` along the unit ray `rd`, its sun's
// and sky's shares multiplied by `props` (the props' shadow and occlusion there: 1, 1 without
// them; props_reference.wgsl shades again with theirs).
fn shade_cast(rd: vec3<f32>, t: f32, props: vec2<f32>) -> vec3<f32> {
    let p = ray.eye.xyz + t * rd;
    let normal_octaves = select(ray.octaves, ray.normal_octaves, ray.method == 1u);
    let footprint = select(0.0, t * ray.pixel_angle, ray.method == 1u && ray.band_limit == 1u);
    let g = world_channel(p.xz, normal_octaves, CHANNEL_HEIGHT, footprint);
    let n = normalize(vec3<f32>(-g.y * ray.peak, 1.0, -g.z * ray.peak));
    var h = g.x;
    if normal_octaves != ray.octaves {
        h = world_channel(p.xz, ray.octaves, CHANNEL_HEIGHT, footprint).x;
    }
    let tint = world_channel(p.xz, ray.octaves, CHANNEL_COLOR, footprint).x;
    let h0 = h * ray.peak;
    var horizon = -1.5;
    if r.shadows != 0u {
        horizon = world_horizon(p, h0);
    }
    var valley = 0.0;
    if r.palette != PALETTE_BLOG {
        valley = world_valley(p.xz, h0);
    }
    let occl = occlusion(r, h, horizon, valley) * props;
    // The render uniforms put the camera at the origin: shade with the camera-relative point.
    return shade(r, t * rd, n, h, tint, occl);
}
