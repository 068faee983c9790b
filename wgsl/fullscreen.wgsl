// The full-screen triangle every full-screen pass draws (the blit, the sky, the composite, the
// ray casters' fragment path, the reference's depth): vertex `i` of 0..3, in normalised device
// coordinates, corners (-1, -1), (3, -1) and (-1, 3), so the viewport lies inside it.
fn fullscreen_xy(i: u32) -> vec2<f32> {
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return xy * 2.0 - 1.0;
}
