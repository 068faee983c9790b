//! Compares two PNGs with FLIP (the perceptual image metric the tests use) and prints the mean
//! and 99th percentile; with `--max-mean X` exits 1 when the mean is above X. The browser
//! test uses it to compare the page's screenshot with `relief render`.
//!
//!     cargo run --example flip -- reference.png test.png [--max-mean 0.05] [--diff out.png]

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
    };
    let (Some(reference), Some(test)) = (args.first(), args.get(1)) else {
        eprintln!("usage: flip REFERENCE.png TEST.png [--max-mean X] [--diff OUT.png]");
        return ExitCode::from(2);
    };
    let load = |p: &str| {
        image::open(p)
            .map(|i| i.into_rgb8())
            .map_err(|e| format!("{p}: {e}"))
    };
    let (a, b) = match (load(reference), load(test)) {
        (Ok(a), Ok(b)) => (a, b),
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    if a.dimensions() != b.dimensions() {
        eprintln!("sizes differ: {:?} vs {:?}", a.dimensions(), b.dimensions());
        return ExitCode::from(1);
    }
    let (w, h) = a.dimensions();
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, a.as_raw()),
        nv_flip::FlipImageRgb8::with_data(w, h, b.as_raw()),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mut pool = nv_flip::FlipPool::from_image(&error);
    let (mean, p99) = (pool.mean(), pool.get_percentile(0.99, true));
    println!("FLIP {reference} vs {test}: mean {mean:.4}, p99 {p99:.4}");
    if let Some(out) = value("--diff") {
        let diff = error.apply_color_lut(&nv_flip::magma_lut());
        if let Err(e) = image::save_buffer(out, &diff.to_vec(), w, h, image::ColorType::Rgb8) {
            eprintln!("{out}: {e}");
        }
    }
    match value("--max-mean").map(|v| v.parse::<f32>()) {
        Some(Ok(max)) if mean > max => {
            eprintln!("FLIP mean {mean:.4} exceeds {max}");
            ExitCode::from(1)
        }
        Some(Err(_)) => {
            eprintln!("--max-mean needs a number");
            ExitCode::from(2)
        }
        _ => ExitCode::SUCCESS,
    }
}
