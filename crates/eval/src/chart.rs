//! What every chart relief draws shares: the font, the size, log-axis ticks and their labels,
//! the legend, and the writing of one chart as SVG and PNG.

use std::path::Path;

use relief::error::{Error, Result};

/// Writes a chart as `stem`.svg and `stem`.png at [`CHART_SIZE`], with the chart font: `svg`
/// and `png` draw the same chart on each backend.
pub(crate) fn write_chart(
    stem: &Path,
    svg: impl FnOnce(plotters::backend::SVGBackend) -> std::result::Result<(), String>,
    png: impl FnOnce(plotters::backend::BitMapBackend) -> std::result::Result<(), String>,
) -> Result<()> {
    register_font()?;
    let (svg_path, png_path) = (stem.with_extension("svg"), stem.with_extension("png"));
    svg(plotters::backend::SVGBackend::new(&svg_path, CHART_SIZE))
        .map_err(|e| Error::io(&svg_path, std::io::Error::other(e)))?;
    png(plotters::backend::BitMapBackend::new(&png_path, CHART_SIZE))
        .map_err(|e| Error::io(&png_path, std::io::Error::other(e)))
}

/// Fonts the chart may use, first found wins (Debian's fonts-dejavu-core, or Liberation);
/// `RELIEF_FONT` names another TrueType file to try first.
pub const FONT_PATHS: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf",
];

/// Makes the chart font (see [`FONT_PATHS`]) plotters' "sans-serif".
fn register_font() -> Result<()> {
    let font = load_font()?;
    plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, font)
        .map_err(|_| Error::Device("could not register the chart font".into()))
}

fn load_font() -> Result<&'static [u8]> {
    let from_env = std::env::var("RELIEF_FONT").ok();
    for p in from_env.as_deref().into_iter().chain(FONT_PATHS) {
        if let Ok(bytes) = std::fs::read(p) {
            return Ok(Box::leak(bytes.into_boxed_slice()));
        }
    }
    Err(no_font())
}

/// Fails, saying what to install, where no chart font ([`FONT_PATHS`], or `RELIEF_FONT`) can
/// be opened: what a command that measures and then charts checks before it measures (a
/// benchmark that ran for minutes should not end on a missing font).
pub fn check_font() -> Result<()> {
    let from_env = std::env::var("RELIEF_FONT").ok();
    let found = from_env
        .as_deref()
        .into_iter()
        .chain(FONT_PATHS)
        .any(|p| std::fs::File::open(p).is_ok());
    if found {
        Ok(())
    } else {
        Err(no_font())
    }
}

fn no_font() -> Error {
    Error::io(
        FONT_PATHS[0],
        std::io::Error::new(
            std::io::ErrorKind::NotFound,
            "no font for the chart: install fonts-dejavu-core",
        ),
    )
}

/// Tick values for a log axis over `lo..hi`: 1-2-5 per decade, or every integer multiple when
/// the range is too short for that to give `min_count` ticks.
pub fn log_ticks(lo: f64, hi: f64, min_count: usize) -> Vec<f64> {
    if !(lo > 0.0 && hi >= lo && hi.is_finite()) {
        return Vec::new();
    }
    let mantissas: [&[f64]; 3] = [
        &[1.0, 2.0, 5.0],
        &[1.0, 2.0, 3.0, 5.0, 7.0],
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
    ];
    let (d0, d1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let mut ticks = Vec::new();
    for m in mantissas {
        ticks = (d0..=d1)
            .flat_map(|d| m.iter().map(move |k| k * 10f64.powi(d)))
            .filter(|v| (lo..=hi).contains(v))
            .collect();
        if ticks.len() >= min_count {
            break;
        }
    }
    ticks
}

/// A tick's label: as few digits as the value needs ("0.05", "2", "100").
pub fn tick_label(v: f64) -> String {
    let decimals = (-v.log10().floor()).max(0.0) as usize;
    format!("{v:.decimals$}")
}

/// The chart's size in pixels (PNG and SVG).
pub const CHART_SIZE: (u32, u32) = (960, 640);

/// The series' legend of a chart or a panel, at `position` (every chart relief draws).
pub(crate) fn legend<'a, DB, X, Y>(
    chart: &mut plotters::prelude::ChartContext<'a, DB, plotters::prelude::Cartesian2d<X, Y>>,
    position: plotters::prelude::SeriesLabelPosition,
) -> std::result::Result<(), String>
where
    DB: plotters::prelude::DrawingBackend + 'a,
    DB::ErrorType: 'static,
    X: plotters::coord::ranged1d::Ranged,
    Y: plotters::coord::ranged1d::Ranged,
{
    use plotters::prelude::*;
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())
}
