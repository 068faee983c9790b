//! relief's evaluation: everything that measures the renderer rather than draws with it.
//!
//! - [`metrics`]: accuracy against the CPU f64 twin and the reference (FLIP, height errors).
//! - [`raycast`]: the CPU f64 ray cast of the twin's continuous surface, the check on the GPU
//!   reference renderer.
//! - [`bench`](mod@bench), [`bench_world`], [`bench_look`], [`bench_arrival`]: the benchmarks of the tile
//!   and the endless world, with their charts ([`chart`], [`bench_world_chart`]).
//! - [`stability`]: where each method fails (the stability map).
//!
//! The `relief` program (crates/cli) runs them as `relief bench` and `relief stability`.

#![cfg(not(target_arch = "wasm32"))]

pub mod bench;
pub mod bench_arrival;
pub mod bench_clouds;
pub mod bench_grass;
pub mod bench_look;
pub mod bench_props;
pub mod bench_temporal;
pub mod bench_world;
pub mod bench_world_chart;
pub mod chart;
pub mod metrics;
pub mod raycast;
pub mod stability;
pub mod views;
