//! GPU bake against the CPU f64 twin: heights, colour channel, normals, seams, scrolling.

#[path = "../../../tests/common/mod.rs"]
mod common;

use relief::noise::{analytic_normal, central_difference_normal, Channel, Fbm};
use relief::TerrainParams;

/// Allowed |GPU - twin| for normalised heights, as a fraction of the [0, 1] range.
///
/// The shader's lattice arithmetic is exact (integer cell, fraction with one rounding); what
/// remains is f32 rounding in the fade, the dot products, the mixes and the octave sum, a few
/// ulps of values below 1 (~1e-7 each), plus the f32 rounding of the scroll offset (2^-25
/// tiles) times the finest period and its small amplitude. Measured errors are ~1e-6; 1e-5
/// leaves room for other GPUs' fused multiply-adds while still catching any real mismatch (a
/// wrong hash, gradient or octave changes values by ~1e-2).
const HEIGHT_TOL: f64 = 1e-5;

fn max_error(gpu: &[f32], twin: &[f64]) -> (f64, usize) {
    gpu.iter()
        .zip(twin)
        .enumerate()
        .map(|(i, (&g, &t))| ((f64::from(g) - t).abs(), i))
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
}

#[test]
fn heights_and_colors_match_twin() {
    let gpu = common::gpu();
    let cases = [
        (1, 1, 3, 0.5, [0.0, 0.0]),
        (7, 8, 4, 0.5, [0.0, 0.0]),
        // Baked by 2x2 quads of texels: each octave's cells span an even number of texels.
        (9, 6, 4, 0.5, [0.0, 0.0]),
        (123_456, 12, 2, 0.6, [0.3, 0.71]),
        (u32::MAX, 5, 7, 0.45, [1e6 + 0.25, -1e6 - 0.125]),
        (42, 16, 1, 0.5, [-3.75, 2.5]),
    ];
    for (seed, octaves, frequency, gain, offset) in cases {
        let params = TerrainParams {
            seed,
            octaves,
            frequency,
            gain,
            offset,
            size: 256,
            ..Default::default()
        };
        let (_, baked) = common::bake(&gpu, params);
        let fbm = Fbm::from_params(&params);
        for (channel, values) in [
            (Channel::Height, &baked.heights),
            (Channel::Color, &baked.colors),
        ] {
            let twin = fbm.bake(channel, params.size);
            let (err, at) = max_error(values, &twin);
            eprintln!("seed {seed} octaves {octaves} freq {frequency} offset {offset:?} {channel:?}: max error {err:.2e}");
            assert!(
                err <= HEIGHT_TOL,
                "{channel:?} seed {seed}: max |gpu - twin| = {err:e} at texel {at} (gpu {}, twin {}); tolerance {HEIGHT_TOL}",
                values[at],
                twin[at]
            );
            // The bake must use the range, not collapse to a constant.
            let (lo, hi) = twin
                .iter()
                .fold((1.0f64, 0.0f64), |(lo, hi), &v| (lo.min(v), hi.max(v)));
            assert!(hi - lo > 0.2, "degenerate terrain: {lo}..{hi}");
        }
    }
}

/// (max component error vs the twin's central differences, mean and max angle in degrees to
/// the analytic normal) for one bake.
fn normal_errors(gpu: &relief::gpu::headless::Gpu, params: TerrainParams) -> (f64, f64, f64) {
    let (_, baked) = common::bake(gpu, params);
    let fbm = Fbm::from_params(&params);
    let twin_h = fbm.bake(Channel::Height, params.size);
    let hs = f64::from(params.height_scale);
    let n = params.size;
    let (mut max_comp, mut sum_angle, mut max_angle) = (0.0f64, 0.0f64, 0.0f64);
    for y in 0..n {
        for x in 0..n {
            let g = baked.normals[(y * n + x) as usize];
            let t = central_difference_normal(&twin_h, n, hs, x, y);
            for i in 0..3 {
                max_comp = max_comp.max((f64::from(g[i]) - t[i]).abs());
            }
            let u = [
                (f64::from(x) + 0.5) / f64::from(n),
                (f64::from(y) + 0.5) / f64::from(n),
            ];
            let a = analytic_normal(&fbm, hs, u);
            // Stored normals are unit length only to f16 precision; renormalise before the
            // angle, or acos near 1 turns a 3e-4 length error into a 1.3 degree angle.
            let len = g.iter().map(|&c| f64::from(c).powi(2)).sum::<f64>().sqrt();
            let dot = (0..3)
                .map(|i| f64::from(g[i]) / len * a[i])
                .sum::<f64>()
                .clamp(-1.0, 1.0);
            let angle = dot.acos().to_degrees();
            sum_angle += angle;
            max_angle = max_angle.max(angle);
        }
    }
    let mean_angle = sum_angle / f64::from(n * n);
    eprintln!(
        "normals size {} octaves {} freq {}: max component error vs twin differences {max_comp:.2e}; \
         vs analytic gradient mean {mean_angle:.3} deg, max {max_angle:.3} deg",
        params.size, params.octaves, params.frequency
    );
    (max_comp, mean_angle, max_angle)
}

#[test]
fn normals_match_twin_and_analytic_gradient() {
    let gpu = common::gpu();
    let base = TerrainParams {
        seed: 3,
        height_scale: 0.6,
        ..Default::default()
    };
    // The default noise at test size: the finest octave (period 512 cells) is far below the
    // texel spacing, so central differences cannot see its slope. Reported, and checked only
    // against the twin's own differences.
    let coarse = normal_errors(&gpu, TerrainParams { size: 256, ..base });
    // A resolved case: finest period 8 cells, 16 and 32 texels per cell.
    let resolved = TerrainParams {
        frequency: 2,
        octaves: 3,
        ..base
    };
    let r128 = normal_errors(
        &gpu,
        TerrainParams {
            size: 128,
            ..resolved
        },
    );
    let r256 = normal_errors(
        &gpu,
        TerrainParams {
            size: 256,
            ..resolved
        },
    );
    for (max_comp, _, _) in [coarse, r128, r256] {
        // rgba16float keeps 11 significant bits: components in [-1, 1] round by at most
        // 2^-11 (4.9e-4); height errors (<= 1e-5) amplified by height_scale / (2 texel
        // spacing) add < 1e-4 at these sizes.
        assert!(
            max_comp <= 1e-3,
            "normal component error {max_comp:e} exceeds 1e-3"
        );
    }
    // Central differences are second order: doubling the resolution should cut the angle
    // error about fourfold. A wrong sign, axis swap or scale would not converge at all.
    assert!(r256.1 < 1.0, "resolved mean angle {} deg", r256.1);
    assert!(
        r128.1 / r256.1 > 2.5,
        "no second-order convergence: {} -> {} deg",
        r128.1,
        r256.1
    );

    // The analytic method matches the analytic normals whatever the resolution, up to f16
    // storage and f32 evaluation: even for the unresolved default noise.
    let analytic = TerrainParams {
        size: 256,
        normals: relief::NormalMethod::Analytic,
        ..base
    };
    let (_, baked) = common::bake(&gpu, analytic);
    let e = relief_eval::metrics::normal_error(&analytic, &baked.normals);
    eprintln!(
        "analytic normals: mean {:.4} deg, p99 {:.4} deg",
        e.mean_deg, e.p99_deg
    );
    assert!(e.p99_deg < 0.2, "analytic normal map off by {e:?}");
}

#[test]
fn tiles_without_seams() {
    let gpu = common::gpu();
    let params = TerrainParams {
        size: 256,
        octaves: 8,
        ..Default::default()
    };
    let (_, baked) = common::bake(&gpu, params);
    let n = params.size as usize;
    let h = |x: usize, y: usize| f64::from(baked.heights[y * n + x]);
    // Neighbour differences across the wrap edge (column n-1 to column 0, row n-1 to row 0)
    // against those between interior neighbours.
    let mut edge = Vec::new();
    let mut interior = Vec::new();
    for i in 0..n {
        edge.push((h(0, i) - h(n - 1, i)).abs());
        edge.push((h(i, 0) - h(i, n - 1)).abs());
        interior.push((h(n / 2, i) - h(n / 2 - 1, i)).abs());
        interior.push((h(i, n / 2) - h(i, n / 2 - 1)).abs());
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let max = |v: &[f64]| v.iter().cloned().fold(0.0, f64::max);
    eprintln!(
        "seams: edge mean {:.2e} max {:.2e}; interior mean {:.2e} max {:.2e}",
        mean(&edge),
        max(&edge),
        mean(&interior),
        max(&interior)
    );
    assert!(
        mean(&edge) < 2.0 * mean(&interior),
        "wrap edge is rougher than the interior"
    );
    assert!(max(&edge) < 3.0 * max(&interior), "a step at the wrap edge");
    // A non-periodic noise would give a jump of the order of the height range's spread.
    assert!(max(&edge) < 0.05);
}

#[test]
fn whole_tile_scroll_and_same_seed_give_same_bytes() {
    let gpu = common::gpu();
    let base = TerrainParams {
        size: 128,
        offset: [0.375, 0.25],
        ..Default::default()
    };
    let (_, a) = common::bake(&gpu, base);
    let (_, b) = common::bake(&gpu, base);
    let (_, c) = common::bake(
        &gpu,
        TerrainParams {
            offset: [5.375, -2.75],
            ..base
        },
    );
    let (_, d) = common::bake(
        &gpu,
        TerrainParams {
            offset: [0.5, 0.25],
            ..base
        },
    );
    let bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.heights), bits(&b.heights), "same seed, same bytes");
    assert_eq!(bits(&a.colors), bits(&b.colors));
    assert_eq!(
        bits(&a.heights),
        bits(&c.heights),
        "whole-tile scroll must reproduce the texture"
    );
    assert_ne!(
        bits(&a.heights),
        bits(&d.heights),
        "a part-tile scroll must move the terrain"
    );
    // Scrolling by exactly 16 texels (16/128 tile) shifts the texture by 16 columns.
    let n = 128;
    for y in 0..n {
        for x in 0..n - 16 {
            let moved = d.heights[y * n + x];
            let orig = a.heights[y * n + x + 16];
            assert!(
                (moved - orig).abs() < 1e-5,
                "scroll by 16 texels at ({x},{y}): {moved} vs {orig}"
            );
        }
    }
}

#[test]
fn rebakes_only_what_changed_and_height_at_agrees() {
    let gpu = common::gpu();
    let params = TerrainParams {
        size: 64,
        ..Default::default()
    };
    let (mut terrain, baked) = common::bake(&gpu, params);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(
        terrain.encode_textures(&mut encoder, None) == 0,
        "nothing changed: nothing to record"
    );
    let dirty = terrain
        .set_params(
            &gpu.device,
            &gpu.queue,
            TerrainParams {
                snow_height: 0.2,
                ..params
            },
        )
        .unwrap();
    assert!(
        !dirty.any_gpu_work() && terrain.encode_textures(&mut encoder, None) == 0,
        "snow is shading only"
    );
    let dirty = terrain
        .set_params(
            &gpu.device,
            &gpu.queue,
            TerrainParams {
                height_scale: 1.0,
                ..params
            },
        )
        .unwrap();
    assert!(
        dirty.normals && !dirty.bake,
        "height scale re-runs only the normal pass"
    );
    assert!(terrain.encode_textures(&mut encoder, None) > 0);
    // A refused change keeps the old parameters.
    let before = *terrain.params();
    assert!(terrain
        .set_params(&gpu.device, &gpu.queue, TerrainParams { grid: 1, ..params })
        .is_err());
    assert_eq!(*terrain.params(), before);

    // height_at at texel centres equals the baked height times the height scale.
    let n = params.size;
    for (x, y) in [(0, 0), (5, 40), (63, 63), (31, 2)] {
        let wx = ((f64::from(x) + 0.5) / f64::from(n) - 0.5) * relief::WORLD_SIZE;
        let wz = ((f64::from(y) + 0.5) / f64::from(n) - 0.5) * relief::WORLD_SIZE;
        let cpu = relief::height_at(&params, f64::from(wx as f32), f64::from(wz as f32)) as f32;
        let gpu_h = baked.heights[(y * n + x) as usize] * params.height_scale;
        assert!(
            (cpu - gpu_h).abs() < 1e-5,
            "({x},{y}): height_at {cpu} vs baked {gpu_h}"
        );
    }
}
