//! The precision axis on the CPU twin: heights stored in 8, 16 and 32 bits and normals stored
//! as the seed blog stores them, against f64 ([`storage`] and its CSV, table and chart).

use super::*;

/// One storage format on the precision axis: heights stored in it (the error is in the normals
/// their differences give) or normals stored in it.
#[derive(Clone, Debug, PartialEq)]
pub struct StorageRow {
    /// `heights` or `normals`.
    pub stored: &'static str,
    /// The format, as WebGPU names it (the blog's marked).
    pub format: &'static str,
    /// Bits a value.
    pub bits: u32,
    /// Angle between the normal from the stored values and the normal from f64, degrees: mean,
    /// 99th percentile, largest.
    pub angle_mean_deg: f64,
    pub angle_p99_deg: f64,
    pub angle_max_deg: f64,
    /// Heights only: texels drawn flat (no difference either way) where the true surface tilts
    /// by more than 1 degree: the terraces.
    pub flat_fraction: Option<f64>,
}

/// A storage format on the storage axis: its name, bits a value, and what storing a value in it
/// and reading it back gives.
pub(super) type Format = (&'static str, u32, fn(f64) -> f64);

/// A texel side for the storage axis: the default tile's texture side.
pub const STORAGE_SIZE: u32 = 1024;

pub(crate) fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let la = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let lb = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
    (d / (la * lb)).clamp(-1.0, 1.0).acos().to_degrees()
}

pub(crate) fn summary(mut angles: Vec<f64>) -> (f64, f64, f64) {
    angles.sort_by(f64::total_cmp);
    let n = angles.len().max(1);
    let mean = angles.iter().sum::<f64>() / n as f64;
    let p99 = angles.get(n * 99 / 100).copied().unwrap_or(0.0);
    (mean, p99, angles.last().copied().unwrap_or(0.0))
}

/// The storage-precision axis on the CPU twin for `params` at `size` texels a side: the tile's
/// heights stored in 8 bits (the seed blog's rgba8unorm), 16-bit and 32-bit floats, each
/// turned into normals by the normal pass's central differences and compared with the normals
/// of the f64 heights; and the f64 normals stored in rgba8unorm as the blog stores them
/// (negative components clamped to 0), rgba8snorm, rgba16float and rgba32float.
pub fn storage(params: &TerrainParams, size: u32) -> Result<Vec<StorageRow>> {
    use relief::noise::{central_difference_normal, Channel, Fbm};
    params.validate()?;
    let fbm = Fbm::from_params(params);
    let exact = fbm.bake(Channel::Height, size);
    let hs = f64::from(params.height_scale);
    let normal = |h: &[f64], i: usize| {
        central_difference_normal(h, size, hs, (i as u32) % size, (i as u32) / size)
    };
    let truth: Vec<[f64; 3]> = (0..exact.len()).map(|i| normal(&exact, i)).collect();
    let mut rows = Vec::new();
    let heights: [Format; 3] = [
        ("r8unorm (blog)", 8, |h| {
            (h.clamp(0.0, 1.0) * 255.0).round() / 255.0
        }),
        ("r16float", 16, |h| half::f16::from_f64(h).to_f64()),
        ("r32float", 32, |h| f64::from(h as f32)),
    ];
    for (format, bits, store) in heights {
        let stored: Vec<f64> = exact.iter().map(|&h| store(h)).collect();
        let mut flat = 0usize;
        let angles: Vec<f64> = (0..stored.len())
            .map(|i| {
                let n = normal(&stored, i);
                if n[1] == 1.0 && angle_deg(truth[i], [0.0, 1.0, 0.0]) > 1.0 {
                    flat += 1;
                }
                angle_deg(n, truth[i])
            })
            .collect();
        let (angle_mean_deg, angle_p99_deg, angle_max_deg) = summary(angles);
        rows.push(StorageRow {
            stored: "heights",
            format,
            bits,
            angle_mean_deg,
            angle_p99_deg,
            angle_max_deg,
            flat_fraction: Some(flat as f64 / stored.len() as f64),
        });
    }
    let normals: [Format; 4] = [
        // The blog writes the signed normal into rgba8unorm: below 0 is stored as 0.
        ("rgba8unorm (blog)", 8, |c| {
            (c.clamp(0.0, 1.0) * 255.0).round() / 255.0
        }),
        ("rgba8snorm", 8, |c| {
            (c.clamp(-1.0, 1.0) * 127.0).round() / 127.0
        }),
        ("rgba16float", 16, |c| half::f16::from_f64(c).to_f64()),
        ("rgba32float", 32, |c| f64::from(c as f32)),
    ];
    for (format, bits, store) in normals {
        let angles: Vec<f64> = truth.iter().map(|n| angle_deg(n.map(store), *n)).collect();
        let (angle_mean_deg, angle_p99_deg, angle_max_deg) = summary(angles);
        rows.push(StorageRow {
            stored: "normals",
            format,
            bits,
            angle_mean_deg,
            angle_p99_deg,
            angle_max_deg,
            flat_fraction: None,
        });
    }
    Ok(rows)
}

/// The storage axis's CSV.
pub fn storage_csv(rows: &[StorageRow], params: &TerrainParams, size: u32) -> String {
    let mut out = String::from(
        "axis,stored,format,bits,size,height_scale,angle_mean_deg,angle_p99_deg,angle_max_deg,flat_fraction\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "storage,{},\"{}\",{},{size},{},{:.6},{:.6},{:.6},{}",
            r.stored,
            r.format,
            r.bits,
            params.height_scale,
            r.angle_mean_deg,
            r.angle_p99_deg,
            r.angle_max_deg,
            r.flat_fraction.map_or(String::new(), |f| format!("{f:.6}")),
        );
    }
    out
}

/// The storage axis's table.
pub fn storage_table(rows: &[StorageRow]) -> String {
    let mut out = format!(
        "{:<8} {:<18} {:>10} {:>10} {:>10} {:>8}\n",
        "stored", "format", "mean °", "p99 °", "max °", "flat"
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{:<8} {:<18} {:>10.4} {:>10.4} {:>10.4} {:>8}",
            r.stored,
            r.format,
            r.angle_mean_deg,
            r.angle_p99_deg,
            r.angle_max_deg,
            r.flat_fraction
                .map_or("-".to_owned(), |f| format!("{f:.4}")),
        );
    }
    out
}

/// The storage axis's chart: the 99th-percentile normal error (log) against bits a value, a
/// line for heights and one for normals, the blog's formats ringed.
pub fn storage_chart(rows: &[StorageRow], title: &str, stem: &std::path::Path) -> Result<()> {
    crate::chart::write_chart(
        stem,
        |b| draw_storage(b, rows, title),
        |b| draw_storage(b, rows, title),
    )
}

pub(super) fn draw_storage<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[StorageRow],
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let err = |r: &StorageRow| r.angle_p99_deg.max(1e-6);
    let (lo, hi) = log_span(rows.iter().map(err), 2.0);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(
            (6.0..40.0f64)
                .log_scale()
                .with_key_points(vec![8.0, 16.0, 32.0]),
            (lo..hi)
                .log_scale()
                .with_key_points(crate::chart::log_ticks(lo, hi, 5)),
        )
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| crate::chart::tick_label(*v))
        .x_desc("bits a stored value (log)")
        .y_desc("normal error, 99th percentile, degrees (log)")
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    let series = [
        (
            "heights",
            "heights, then differenced",
            RGBColor(31, 119, 180),
        ),
        ("normals", "normals", RGBColor(214, 39, 40)),
    ];
    for (stored, label, color) in series {
        // The signed formats on the line; the blog's unsigned normal map as its own point.
        let line: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.stored == stored && r.format != "rgba8unorm (blog)")
            .map(|r| (f64::from(r.bits), err(r)))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| e.to_string())?;
    }
    for r in rows.iter().filter(|r| r.format.ends_with("(blog)")) {
        let p = (f64::from(r.bits), err(r));
        let color = series
            .iter()
            .find(|s| s.0 == r.stored)
            .map_or(BLACK, |s| s.2);
        chart
            .draw_series([
                Circle::new(p, 4, color.filled()),
                Circle::new(p, 9, BLACK.stroke_width(1)),
            ])
            .map_err(|e| e.to_string())?;
        chart
            .draw_series([Text::new(
                format!("the blog's {}", r.format.trim_end_matches(" (blog)")),
                (p.0 * 1.06, p.1),
                ("sans-serif", 15),
            )])
            .map_err(|e| e.to_string())?;
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    root.present().map_err(|e| e.to_string())
}
