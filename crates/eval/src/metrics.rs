//! Accuracy metrics: how far what relief draws is from the ground truth (the continuous fBm
//! surface of the CPU twin, and the reference ray caster's image).

use glam::DVec3;
use relief::camera::View;
use relief::noise::{analytic_normal, Channel, Fbm, NOISE_MAX_ABS};
use relief::params::TerrainParams;

/// Vertical error of the displaced grid mesh against the continuous surface.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshError {
    /// RMS vertical error in world units.
    pub rms: f64,
    /// Largest vertical error found in world units.
    pub max: f64,
    /// RMS of the same errors projected to screen pixels (visible samples only).
    pub rms_px: f64,
    /// Largest projected error in pixels.
    pub max_px: f64,
    /// Points sampled.
    pub samples: usize,
}

/// Running sums of vertical errors, in world units and (where on screen) pixels.
#[derive(Default)]
struct ErrorSums {
    sum2: f64,
    max: f64,
    sum2_px: f64,
    max_px: f64,
    visible: usize,
}

impl ErrorSums {
    fn add(&mut self, e: f64, px: Option<f64>) {
        self.sum2 += e * e;
        self.max = self.max.max(e);
        if let Some(px) = px {
            self.sum2_px += px * px;
            self.max_px = self.max_px.max(px);
            self.visible += 1;
        }
    }

    /// The summary over `samples` points.
    fn finish(self, samples: usize) -> MeshError {
        let rms = |sum2: f64, n: usize| {
            if n > 0 {
                (sum2 / n as f64).sqrt()
            } else {
                0.0
            }
        };
        MeshError {
            rms: rms(self.sum2, samples),
            max: self.max,
            rms_px: rms(self.sum2_px, self.visible),
            max_px: self.max_px,
            samples,
        }
    }
}

/// Normalised height of the mesh as the GPU rasterises it at tile position (u, v): vertices
/// take the baked texels bilinearly (wrapping), triangles interpolate linearly, split along the
/// diagonal from (i, j+1) to (i+1, j) as the triangle strips are.
pub fn mesh_height(texels: &[f64], size: u32, grid: u32, u: f64, v: f64) -> f64 {
    let cells = f64::from(grid - 1);
    let (gu, gv) = (u * cells, v * cells);
    let (i, j) = (
        gu.floor().clamp(0.0, cells - 1.0),
        gv.floor().clamp(0.0, cells - 1.0),
    );
    let (s, t) = (gu - i, gv - j);
    let vertex = |a: f64, b: f64| bilinear_wrap(texels, size, a / cells, b / cells);
    let (h00, h10, h01, h11) = (
        vertex(i, j),
        vertex(i + 1.0, j),
        vertex(i, j + 1.0),
        vertex(i + 1.0, j + 1.0),
    );
    if s + t <= 1.0 {
        h00 + s * (h10 - h00) + t * (h01 - h00)
    } else {
        h11 + (1.0 - s) * (h01 - h11) + (1.0 - t) * (h10 - h11)
    }
}

/// Bilinear, wrap-around read of a `size` x `size` texel grid at tile position (u, v), with
/// texel centres at (i + 0.5) / size, as the tile's bake writes them.
pub fn bilinear_wrap(texels: &[f64], size: u32, u: f64, v: f64) -> f64 {
    let n = i64::from(size);
    let (x, y) = (u * n as f64 - 0.5, v * n as f64 - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: i64, j: i64| texels[(j.rem_euclid(n) * n + i.rem_euclid(n)) as usize];
    let (i, j) = (x0 as i64, y0 as i64);
    let top = at(i, j) + fx * (at(i + 1, j) - at(i, j));
    let bottom = at(i, j + 1) + fx * (at(i + 1, j + 1) - at(i, j + 1));
    top + fy * (bottom - top)
}

/// Mesh vertical error at up to `max_samples` pseudo-random points of the tile (deterministic),
/// against the twin's surface. `texels` are the baked normalised heights (the twin's bake or a
/// GPU readback); with `camera` = (view, width, height) the errors are also projected to pixels.
pub fn mesh_error(
    params: &TerrainParams,
    texels: &[f64],
    camera: Option<(&View, u32, u32)>,
    max_samples: usize,
) -> MeshError {
    let fbm = Fbm::from_params(params);
    let hs = f64::from(params.height_scale);
    let mut sums = ErrorSums::default();
    for k in 0..max_samples {
        let (u, v) = (unit(2 * k as u32), unit(2 * k as u32 + 1));
        let truth = hs * fbm.sample(Channel::Height, [u, v]).0;
        let drawn = hs * mesh_height(texels, params.size, params.grid, u, v);
        let px = camera.and_then(|(view, w, h)| {
            let world = DVec3::new(
                (u - 0.5) * relief::WORLD_SIZE,
                truth,
                (v - 0.5) * relief::WORLD_SIZE,
            );
            vertical_pixels(view, w, h, world, drawn - truth)
        });
        sums.add((drawn - truth).abs(), px);
    }
    sums.finish(max_samples)
}

/// The drawn mesh's vertical error against the twin's surface, measured where it was drawn:
/// each pixel of a single-sampled `depth` buffer (`width` x `height`, cleared to 1.0) of
/// `view` is turned back into the point drawn there, and that point's height is compared with
/// the continuous surface's at its x, z; at most `max_samples` pixels, evenly strided. Whatever
/// renderer drew it (the clipmap's levels of detail included), this is what is on screen. The
/// depth buffer's own precision (32-bit float) adds under 1e-4 world units at the tile's
/// distances.
pub fn drawn_mesh_error(
    params: &TerrainParams,
    view: &View,
    (width, height): (u32, u32),
    depth: &[f32],
    max_samples: usize,
) -> MeshError {
    let fbm = Fbm::from_params(params);
    let hs = f64::from(params.height_scale);
    let vp = view.view_proj.as_dmat4();
    let drawn: Vec<usize> = (0..depth.len()).filter(|&i| depth[i] < 1.0).collect();
    let stride = drawn.len().div_ceil(max_samples.max(1)).max(1);
    let (mut sums, mut n) = (ErrorSums::default(), 0);
    for &i in drawn.iter().step_by(stride) {
        let (x, y) = (i as u32 % width, i as u32 / width);
        let p = crate::raycast::unproject(vp, width, height, x, y, f64::from(depth[i]));
        let (u, v) = (
            p.x / relief::WORLD_SIZE + 0.5,
            p.z / relief::WORLD_SIZE + 0.5,
        );
        let truth = hs * fbm.sample(Channel::Height, [u, v]).0;
        let at = DVec3::new(p.x, truth, p.z);
        let px = vertical_pixels(view, width, height, at, p.y - truth);
        sums.add((p.y - truth).abs(), px);
        n += 1;
    }
    sums.finish(n)
}

/// Length in pixels of the vertical segment from `world` to `world + dy` on screen, or `None`
/// when `world` is outside the view.
fn vertical_pixels(view: &View, w: u32, h: u32, world: DVec3, dy: f64) -> Option<f64> {
    let m = view.view_proj.as_dmat4();
    let project = |p: DVec3| {
        let c = m * p.extend(1.0);
        (c.w > 0.0).then(|| (c.x / c.w, c.y / c.w, c.z / c.w))
    };
    let a = project(world)?;
    let b = project(world + DVec3::new(0.0, dy, 0.0))?;
    if a.0.abs() > 1.0 || a.1.abs() > 1.0 || !(0.0..=1.0).contains(&a.2) {
        return None;
    }
    let dx = (b.0 - a.0) * 0.5 * f64::from(w);
    let dyp = (b.1 - a.1) * 0.5 * f64::from(h);
    Some((dx * dx + dyp * dyp).sqrt())
}

/// The k-th number of a deterministic low-discrepancy-ish sequence in [0, 1).
fn unit(k: u32) -> f64 {
    f64::from(relief::noise::pcg(k ^ 0x5bd1_e995)) / 4_294_967_296.0
}

/// Angle statistics of a normal map against the analytic normals, in degrees.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NormalError {
    /// Mean angle.
    pub mean_deg: f64,
    /// 99th percentile.
    pub p99_deg: f64,
}

/// The angle between each texel's normal (any length; renormalised) and the analytic normal at
/// the texel centre.
pub fn normal_error(params: &TerrainParams, normals: &[[f32; 3]]) -> NormalError {
    let fbm = Fbm::from_params(params);
    let hs = f64::from(params.height_scale);
    let n = params.size;
    let mut angles: Vec<f64> = normals
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let (x, y) = (i as u32 % n, i as u32 / n);
            let u = [
                (f64::from(x) + 0.5) / f64::from(n),
                (f64::from(y) + 0.5) / f64::from(n),
            ];
            let a = analytic_normal(&fbm, hs, u);
            let len = g
                .iter()
                .map(|&c| f64::from(c).powi(2))
                .sum::<f64>()
                .sqrt()
                .max(1e-30);
            let dot = (0..3)
                .map(|k| f64::from(g[k]) / len * a[k])
                .sum::<f64>()
                .clamp(-1.0, 1.0);
            dot.acos().to_degrees()
        })
        .collect();
    if angles.is_empty() {
        return NormalError::default();
    }
    let mean = angles.iter().sum::<f64>() / angles.len() as f64;
    angles.sort_by(f64::total_cmp);
    let p99 = angles[((angles.len() - 1) as f64 * 0.99).round() as usize];
    NormalError {
        mean_deg: mean,
        p99_deg: p99,
    }
}

/// Where a test image's terrain is against the reference's, per pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Coverage {
    /// Fraction of pixels where the reference sees terrain and the test sees sky (holes,
    /// rays that tunnelled through).
    pub missed: f64,
    /// Fraction where the test draws terrain over the reference's sky.
    pub extra: f64,
    /// Fraction where both hit but at distances differing by more than the tolerance.
    pub wrong_depth: f64,
}

/// Compares distance images (negative = no terrain) with a relative depth tolerance.
pub fn coverage(reference: &[f32], test: &[f32], relative_tolerance: f64) -> Coverage {
    let n = reference.len().min(test.len()).max(1) as f64;
    let (mut missed, mut extra, mut wrong) = (0usize, 0usize, 0usize);
    for (&r, &t) in reference.iter().zip(test) {
        match (r >= 0.0, t >= 0.0) {
            (true, false) => missed += 1,
            (false, true) => extra += 1,
            (true, true) if f64::from((r - t).abs()) > relative_tolerance * f64::from(r) => {
                wrong += 1
            }
            _ => {}
        }
    }
    Coverage {
        missed: missed as f64 / n,
        extra: extra as f64 / n,
        wrong_depth: wrong as f64 / n,
    }
}

/// FLIP mean and 99th percentile of `test` against `reference` (tightly packed RGB8, sRGB).
#[cfg(not(target_arch = "wasm32"))]
pub fn image_error(reference: &[u8], test: &[u8], width: u32, height: u32) -> (f64, f64) {
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(width, height, reference),
        nv_flip::FlipImageRgb8::with_data(width, height, test),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mut pool = nv_flip::FlipPool::from_image(&error);
    (
        f64::from(pool.mean()),
        f64::from(pool.get_percentile(0.99, true)),
    )
}

/// FLIP of each pixel of `test` against `reference` (tightly packed RGB8, sRGB), row by row.
#[cfg(not(target_arch = "wasm32"))]
pub fn flip_map(reference: &[u8], test: &[u8], width: u32, height: u32) -> Vec<f32> {
    nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(width, height, reference),
        nv_flip::FlipImageRgb8::with_data(width, height, test),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    )
    .to_vec()
}

/// RGBA8 to RGB8.
pub fn rgb(rgba: &[u8]) -> Vec<u8> {
    rgba.chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect()
}

pub use relief::gpu::downsample_srgb;

/// Each pixel's `distance` along its centre's ray through `view` (as a ray cast gives it;
/// negative where it found none) as a horizontal distance from the eye: what the grass's draw
/// distance is measured in.
pub fn horizontal_distance(view: &relief::WorldView, distance: &[f32]) -> Vec<f32> {
    let inverse = relief::gpu::world_rays::ray_matrix(view).inverse();
    let (w, h) = (view.size.0.max(1), view.size.1.max(1));
    distance
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            if d < 0.0 {
                return d;
            }
            let (x, y) = ((i as u32 % w) as f32 + 0.5, (i as u32 / w) as f32 + 0.5);
            let ndc = glam::Vec2::new(2.0 * x / w as f32 - 1.0, 1.0 - 2.0 * y / h as f32);
            let near = inverse.project_point3(ndc.extend(0.0));
            let far = inverse.project_point3(ndc.extend(1.0));
            let dir = (far - near).normalize_or_zero();
            d * dir.x.hypot(dir.z)
        })
        .collect()
}

/// The colour difference (CIE76 ΔE) between the mean linear colours of two sRGB RGBA8 images
/// over the pixels whose `distance` (metres, [`horizontal_distance`] for the grass) lies
/// within `band`, and how many pixels that is; `None` where none does. What a seam at a
/// distance shows, whatever the noise of single pixels.
pub fn band_delta_e(
    a: &[u8],
    b: &[u8],
    distance: &[f32],
    band: (f32, f32),
) -> Option<(f64, usize)> {
    let linear = |c: u8| f64::from(relief::params::srgb_to_linear(f32::from(c) / 255.0));
    let mut sums = [[0.0; 3]; 2];
    let mut n = 0;
    for (i, &d) in distance.iter().enumerate() {
        if d < band.0 || d > band.1 {
            continue;
        }
        n += 1;
        for (sum, image) in sums.iter_mut().zip([a, b]) {
            for (c, s) in sum.iter_mut().enumerate() {
                *s += linear(image[4 * i + c]);
            }
        }
    }
    let mean = |s: [f64; 3]| s.map(|v| v / n as f64);
    (n > 0).then(|| (relief::palette::delta_e(mean(sums[0]), mean(sums[1])), n))
}

/// Bound on the Hessian's spectral norm of one octave of the noise, in lattice units.
pub const NOISE_MAX_HESSIAN: f64 = 12.0;

/// Bound on the second derivatives of the normalised fBm (per unit tile coordinate), from the
/// noise's own: used by tests to state the interpolation error a grid should have.
pub fn second_derivative_bound(fbm: &Fbm) -> f64 {
    // The Hessian of one octave of this noise (quintic fade, unit gradients) has a spectral
    // norm of at most 9.07 over every combination of corner gradients on a 13 x 13 grid of
    // cell positions (found by an exhaustive numeric search); 12 adds a margin. Per octave it
    // scales with period^2.
    let mut norm = 0.0;
    let mut bound = 0.0;
    let mut amplitude = 1.0;
    for o in 0..fbm.octaves {
        let p = f64::from(fbm.frequency << o);
        bound += amplitude * p * p * NOISE_MAX_HESSIAN;
        norm += amplitude;
        amplitude *= fbm.gain;
    }
    0.5 / (norm * NOISE_MAX_ABS) * bound
}

/// The middle of `values` (the upper middle of an even count): every benchmark's statistic.
/// `None` when there are none.
pub(crate) fn median<T: Copy + PartialOrd>(values: impl IntoIterator<Item = T>) -> Option<T> {
    // NaN (a value not comparable with itself) is left out: the rest sorts totally.
    let mut v: Vec<T> = values
        .into_iter()
        .filter(|x| x.partial_cmp(x).is_some())
        .collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    v.get(v.len() / 2).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hessian_bound_holds_on_samples() {
        let fbm = Fbm {
            seed: 3,
            frequency: 16,
            octaves: 1,
            gain: 0.5,
            offset: [0.0, 0.0],
        };
        let scale = 0.5 / NOISE_MAX_ABS; // normalisation of a single octave
        let e = 1e-6;
        let mut max: f64 = 0.0;
        for k in 0..20_000u32 {
            let u = [unit(2 * k), unit(2 * k + 1)];
            let g = |du: f64, dv: f64| fbm.sample(Channel::Height, [u[0] + du, u[1] + dv]).1;
            let (gx1, gx0, gy1, gy0) = (g(e, 0.0), g(-e, 0.0), g(0.0, e), g(0.0, -e));
            let hxx = (gx1[0] - gx0[0]) / (2.0 * e);
            let hyy = (gy1[1] - gy0[1]) / (2.0 * e);
            let hxy = 0.5 * ((gx1[1] - gx0[1]) + (gy1[0] - gy0[0])) / (2.0 * e);
            let (tr, r) = (
                (hxx + hyy) / 2.0,
                (((hxx - hyy) / 2.0).powi(2) + hxy * hxy).sqrt(),
            );
            max = max.max((tr.abs() + r) / (scale * 16.0 * 16.0));
        }
        assert!(
            max > 4.0 && max <= NOISE_MAX_HESSIAN,
            "largest Hessian norm per octave {max}"
        );
    }

    #[test]
    fn flat_terrain_has_no_mesh_error() {
        let p = TerrainParams {
            size: 32,
            grid: 9,
            height_scale: 0.0,
            ..Default::default()
        };
        let texels = Fbm::from_params(&p).bake(Channel::Height, p.size);
        let e = mesh_error(&p, &texels, None, 1000);
        assert_eq!((e.rms, e.max), (0.0, 0.0));
    }

    #[test]
    fn mesh_error_stays_within_the_interpolation_bound_and_converges() {
        let base = TerrainParams {
            size: 512,
            octaves: 1,
            frequency: 2,
            height_scale: 1.0,
            ..Default::default()
        };
        let fbm = Fbm::from_params(&base);
        let texels = fbm.bake(Channel::Height, base.size);
        let m2 = second_derivative_bound(&fbm);
        let mut last = f64::INFINITY;
        for grid in [17, 33, 65] {
            let p = TerrainParams { grid, ..base };
            let e = mesh_error(&p, &texels, None, 20_000);
            // Linear interpolation over a right triangle of legs d: |e| <= d^2 * M2 (with the
            // diagonal, d^2/2 * 2); the texture's bilinear read adds (texel^2 / 4) * M2.
            let d = 1.0 / f64::from(grid - 1);
            let texel = 1.0 / f64::from(base.size);
            let bound = (d * d + texel * texel / 4.0) * m2;
            assert!(
                e.max <= bound,
                "grid {grid}: max {} above bound {bound}",
                e.max
            );
            assert!(
                e.max > bound / 100.0,
                "grid {grid}: suspiciously small error {}",
                e.max
            );
            assert!(
                e.rms < last / 3.0,
                "grid {grid}: rms {} did not converge (previous {last})",
                e.rms
            );
            last = e.rms;
        }
    }

    #[test]
    fn exact_normals_have_no_error_and_tilted_ones_do() {
        let p = TerrainParams {
            size: 16,
            ..Default::default()
        };
        let fbm = Fbm::from_params(&p);
        let hs = f64::from(p.height_scale);
        let exact: Vec<[f32; 3]> = (0..256)
            .map(|i| {
                let u = [
                    (f64::from(i % 16) + 0.5) / 16.0,
                    (f64::from(i / 16) + 0.5) / 16.0,
                ];
                analytic_normal(&fbm, hs, u).map(|c| c as f32)
            })
            .collect();
        let e = normal_error(&p, &exact);
        assert!(e.mean_deg < 0.01 && e.p99_deg < 0.01, "{e:?}");
        let up = vec![[0.0, 1.0, 0.0]; 256];
        assert!(normal_error(&p, &up).mean_deg > 1.0);
    }

    #[test]
    fn coverage_counts_holes_extra_and_depth() {
        let r = [1.0, 1.0, -1.0, 2.0];
        let t = [1.0, -1.0, 3.0, 2.5];
        let c = coverage(&r, &t, 0.01);
        assert_eq!((c.missed, c.extra, c.wrong_depth), (0.25, 0.25, 0.25));
    }

    #[test]
    fn image_error_of_identical_images_is_zero() {
        let img = vec![128u8; 32 * 32 * 3];
        assert_eq!(image_error(&img, &img, 32, 32).0, 0.0);
        let other = vec![10u8; 32 * 32 * 3];
        assert!(image_error(&img, &other, 32, 32).0 > 0.1);
    }

    #[test]
    fn downsampling_averages_in_linear_light() {
        // Black and white average to linear 0.5, which is sRGB 188.
        let img = [
            0, 0, 0, 255, 255, 255, 255, 255, 0, 0, 0, 255, 255, 255, 255, 255,
        ];
        let out = downsample_srgb(&img, 2, 2, 2);
        assert_eq!(out, [188, 188, 188, 255]);
    }
}
