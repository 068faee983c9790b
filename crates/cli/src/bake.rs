//! `relief bake`: the tile's textures or a region of the endless world, written as PNGs.

use super::*;

/// `relief bake --world endless`: a region's heights, normals and colour as PNGs, and the
/// parameters with the region in scene.toml.
pub(super) fn bake_endless(
    params: &WorldParams,
    region: &Region,
    dir: &Path,
    timings: bool,
) -> Result<()> {
    check_out_dir(dir)?;
    let gpu = Gpu::new()?;
    let timer = timer_if(timings, &gpu);
    let land = params.land;
    let size = region.size;
    let texels = size as usize * size as usize;
    let shading = Shading::default();
    let (mut heights, mut normal, mut color) = (
        Vec::with_capacity(texels),
        Vec::with_capacity(texels * 3),
        Vec::with_capacity(texels * 3),
    );
    let peak = land.peak_height as f32;
    let ms = headless::bake_region(
        &gpu,
        &land,
        region.origin,
        size,
        region.spacing_log2,
        timer.as_ref(),
        |_, band| {
            for t in band {
                heights.push(t[0] * peak);
                let n = glam::Vec3::new(-t[1] * peak, 1.0, -t[2] * peak).normalize();
                normal.extend(
                    n.to_array()
                        .map(|c| ((c * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8),
                );
                color.extend(albedo_srgb8(&shading, t[3]));
            }
        },
    )?;
    if timings {
        match ms {
            Some(ms) => println!(
                "timings on {}: bake {ms:.3} ms ({:.1} G octave-samples/s, counting height and colour; \
                 each band's median of {} bakes after {} ms of warm-up)",
                gpu.describe(),
                2.0 * texels as f64 * f64::from(land.octaves_for_level(region.spacing_log2))
                    / (ms * 1e6),
                headless::BAKE_RUNS,
                headless::BAKE_WARM_UP.as_millis(),
            ),
            None => println!("timings: {} has no timestamp queries", gpu.describe()),
        }
    }
    let (height, lo, hi) = heights_16(&heights);
    drop(heights);
    let mut scene = String::from(
        "# relief endless-world bake: the world's parameters and the region baked.\n\
         # `relief render --scene FILE` draws this world (the [bake] record changes nothing).\n\
         world = \"endless\"\n",
    );
    for row in &WORLD_PARAMS {
        scene.push_str(&format!(
            "{} = {}\n",
            row.key,
            crate::scene::toml_value((row.get)(params))
        ));
    }
    let spacing = 2f64.powi(region.spacing_log2);
    scene.push_str(&format!(
        "\n# The square baked (metres), its samples per side and spacing, the octaves the spacing \
         keeps, and the heights in metres that 0 and 65535 in height.png stand for.\n[bake]\n\
         region = [{}]\nsize = {size}\nspacing = {spacing:?}\noctaves_kept = {}\n\
         height_min = {:?}\nheight_max = {:?}\n",
        region
            .text
            .split(',')
            .map(str::trim)
            .collect::<Vec<_>>()
            .join(", "),
        land.octaves_for_level(region.spacing_log2),
        f64::from(lo),
        f64::from(hi),
    ));
    write_bake(dir, size, &height, &normal, &color, &scene)?;
    println!(
        "baked {size}x{size} samples every {} m of region {} into {}: heights {lo:.3}..{hi:.3} m map to 0..65535",
        relief::table::number(spacing),
        region.text,
        dir.display()
    );
    Ok(())
}

/// The albedo `color.png` shows for a colour-channel value: the two albedos mixed in linear
/// light, as the renderer mixes them, then encoded to sRGB.
pub fn albedo_srgb8(shading: &Shading, channel: f32) -> [u8; 3] {
    let t = smoothstep(0.2, 0.8, channel);
    [0, 1, 2].map(|i| {
        let a = srgb_to_linear(shading.color_a[i]);
        let b = srgb_to_linear(shading.color_b[i]);
        (linear_to_srgb(a + (b - a) * t) * 255.0).round() as u8
    })
}

/// Linear component to sRGB-encoded, as the shader's `srgb_encode`.
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Heights as 16-bit PNG samples spanning their range, with the range. A flat bake has no range
/// to spread over 0..65535: every sample is 0, and the scene file's min = max says so.
pub(super) fn heights_16(heights: &[f32]) -> (Vec<u8>, f32, f32) {
    let (lo, hi) = heights
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    let span = hi - lo;
    let bytes = heights
        .iter()
        .flat_map(|&h| {
            let v = if span > 0.0 {
                ((h - lo) / span * 65535.0).round() as u16
            } else {
                0
            };
            v.to_ne_bytes()
        })
        .collect();
    (bytes, lo, hi)
}

/// Writes a bake's four files into `dir`, all or none.
pub(super) fn write_bake(
    dir: &Path,
    size: u32,
    height: &[u8],
    normal: &[u8],
    color: &[u8],
    scene: &str,
) -> Result<()> {
    let files: [(&str, FileWriter); 4] = [
        (
            "height.png",
            Box::new(|p| encode_png(p, size, size, image::ColorType::L16, height)),
        ),
        (
            "normal.png",
            Box::new(|p| encode_png(p, size, size, image::ColorType::Rgb8, normal)),
        ),
        (
            "color.png",
            Box::new(|p| encode_png(p, size, size, image::ColorType::Rgb8, color)),
        ),
        (
            "scene.toml",
            Box::new(|p| std::fs::write(p, scene.as_bytes()).map_err(|e| Error::io(p, e))),
        ),
    ];
    write_all(dir, &files)
}

pub(super) fn bake(params: &TerrainParams, dir: &Path, timings: bool) -> Result<()> {
    check_out_dir(dir)?;
    let gpu = Gpu::new()?;
    let mut terrain = Terrain::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
    let timer = timer_if(timings, &gpu);
    headless::bake_blocking(&gpu, &mut terrain, None)?;
    if let Some(timer) = &timer {
        // Timed as the region bake is: re-baked after a warm-up, the median of several.
        let t = headless::warm_median(timer, |t| {
            terrain.invalidate();
            headless::bake_blocking(&gpu, &mut terrain, t)
        })?;
        print_timings(&gpu, Some(t));
        println!(
            "(each the median of {} bakes after {} ms of warm-up)",
            headless::BAKE_RUNS,
            headless::BAKE_WARM_UP.as_millis()
        );
    } else if timings {
        print_timings(&gpu, None);
    }
    let size = params.size;
    let texels = size as usize * size as usize;
    let shading = Shading::default();

    // Read back in bands, converting each band at once: a 16384² bake is 4 GiB on the GPU,
    // and only the heights (needed twice, for their range) are kept as floats.
    let mut heights = Vec::with_capacity(texels);
    let mut color = Vec::with_capacity(texels * 3);
    let textures = terrain.textures();
    headless::read_texture_bands(
        &gpu.device,
        &gpu.queue,
        &textures.terrain,
        headless::MAX_READBACK_BYTES,
        |_, rows| {
            for rg in rows.chunks_exact(8) {
                let f = |i: usize| f32::from_ne_bytes([rg[i], rg[i + 1], rg[i + 2], rg[i + 3]]);
                heights.push(f(0));
                color.extend(albedo_srgb8(&shading, f(4)));
            }
        },
    )?;
    let mut normal = Vec::with_capacity(texels * 3);
    headless::read_texture_bands(
        &gpu.device,
        &gpu.queue,
        &textures.normals,
        headless::MAX_READBACK_BYTES,
        |_, rows| {
            for n in rows.chunks_exact(8) {
                normal.extend([0, 1, 2].map(|i| {
                    let bits = u16::from_ne_bytes([n[2 * i], n[2 * i + 1]]);
                    let c = half::f16::from_bits(bits).to_f32();
                    ((c * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8
                }));
            }
        },
    )?;
    drop(terrain);

    let (height, lo, hi) = heights_16(&heights);
    let span = hi - lo;
    drop(heights);
    let scene = params.to_scene_string(Some(BakeInfo {
        height_min: f64::from(lo),
        height_max: f64::from(hi),
    }));

    write_bake(dir, size, &height, &normal, &color, &scene)?;
    if span > 0.0 {
        println!(
            "baked {size}x{size} into {}: heights {lo:.6}..{hi:.6} map to 0..65535",
            dir.display()
        );
    } else {
        println!(
            "baked {size}x{size} into {}: flat, every height is {lo:.6}; height.png is all 0 \
             and the scene file's height_min = height_max",
            dir.display()
        );
    }
    Ok(())
}

/// Writes every file under a temporary name in `dir` (created if missing), then renames them
/// all; on any failure removes what it wrote, and the folders it created.
pub(super) fn write_all(dir: &Path, files: &[(&str, FileWriter)]) -> Result<()> {
    let created = create_dirs(dir)?;
    let cleanup = |written: &[(PathBuf, PathBuf)]| {
        for (t, _) in written {
            let _ = std::fs::remove_file(t);
        }
        if let Some(c) = &created {
            let _ = std::fs::remove_dir_all(c);
        }
    };
    let mut written = Vec::new();
    for (name, write) in files {
        let tmp = temp_name(&dir.join(name));
        if let Err(e) = write(&tmp) {
            let _ = std::fs::remove_file(&tmp);
            cleanup(&written);
            return Err(e);
        }
        written.push((tmp, dir.join(name)));
    }
    for (tmp, fin) in &written {
        if let Err(e) = std::fs::rename(tmp, fin) {
            cleanup(&written);
            return Err(Error::io(fin, e));
        }
    }
    Ok(())
}

pub(super) fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}
