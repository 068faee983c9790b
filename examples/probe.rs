use relief::noise::*;
fn main() {
    let p = relief::TerrainParams { seed: 3, height_scale: 0.6, frequency: 2, octaves: 3, ..Default::default() };
    let fbm = Fbm::from_params(&p);
    for size in [64u32, 128, 256, 512] {
        let h = fbm.bake(Channel::Height, size);
        let mut sum = 0.0;
        for (x, y) in [(10u32, 20u32), (30, 5), (50, 50)] {
            let (x, y) = (x * size / 64, y * size / 64);
            let c = central_difference_normal(&h, size, 0.6, x, y);
            let u = [(x as f64 + 0.5) / size as f64, (y as f64 + 0.5) / size as f64];
            let a = analytic_normal(&fbm, 0.6, u);
            let d: f64 = (0..3).map(|i| c[i] * a[i]).sum();
            sum += d.min(1.0).acos().to_degrees();
            if size == 512 { println!("{c:?} {a:?}"); }
        }
        println!("{size}: {}", sum / 3.0);
    }
}
