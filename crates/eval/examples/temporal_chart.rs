//! Draws the chart of `relief bench --world endless --only temporal` from its `temporal.csv`
//! (for a run cut short before it drew one, or to draw it again):
//!
//!     cargo run --example temporal_chart -- docs/results/temporal/temporal.csv docs/results/temporal/temporal

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(csv), Some(stem)) = (args.first(), args.get(1)) else {
        eprintln!("usage: temporal_chart TEMPORAL.csv OUT_STEM");
        return ExitCode::from(2);
    };
    let text = match std::fs::read_to_string(csv) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("temporal_chart: {csv}: {e}");
            return ExitCode::FAILURE;
        }
    };
    let rows = match relief_eval::bench_temporal::parse_still_csv(&text) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("temporal_chart: {csv}: {e}");
            return ExitCode::FAILURE;
        }
    };
    match relief_eval::bench_temporal::chart(&rows, std::path::Path::new(stem)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("temporal_chart: {e}");
            ExitCode::FAILURE
        }
    }
}
