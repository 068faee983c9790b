//! A CPU ray cast of the twin's continuous surface in f64: the check on the GPU reference
//! renderer (the verifier's verifier). Same method as `wgsl/raymarch.wgsl`'s reference:
//! conservative steps from the Lipschitz bound, then bisection.

use crate::camera::View;
use crate::noise::{lipschitz_world, Channel, Fbm};
use crate::params::TerrainParams;
use glam::{DMat4, DVec3, DVec4};

/// The terrain surface a ray can hit: the twin's fBm over one tile, scaled.
pub struct Surface {
    fbm: Fbm,
    height_scale: f64,
    lipschitz: f64,
}

impl Surface {
    /// The surface of a validated parameter set.
    pub fn new(params: &TerrainParams) -> Self {
        let fbm = Fbm::from_params(params);
        let height_scale = f64::from(params.height_scale);
        Self {
            lipschitz: lipschitz_world(&fbm, fbm.octaves, height_scale),
            fbm,
            height_scale,
        }
    }

    /// World height at world (x, z).
    pub fn height(&self, x: f64, z: f64) -> f64 {
        let u = [x / crate::WORLD_SIZE + 0.5, z / crate::WORLD_SIZE + 0.5];
        self.height_scale * self.fbm.sample(Channel::Height, u).0
    }

    /// Distance along the unit ray `rd` from `ro` to the surface within the tile's bounding box,
    /// or `None` if it leaves the box without hitting.
    pub fn intersect(&self, ro: DVec3, rd: DVec3) -> Option<f64> {
        let half = 0.5 * crate::WORLD_SIZE;
        let lo = DVec3::new(-half, 0.0, -half);
        let hi = DVec3::new(half, self.height_scale + 1e-4, half);
        let inv = rd.recip();
        let (a, b) = ((lo - ro) * inv, (hi - ro) * inv);
        let (tmin, tmax) = (a.min(b), a.max(b));
        let t0 = tmin.max_element().max(0.0);
        let t1 = tmax.min_element();
        if t0 > t1 {
            return None;
        }
        let clearance = |t: f64| {
            let p = ro + t * rd;
            p.y - self.height(p.x, p.z)
        };
        // A sheet, as the mesh is: a ray entering below it hits where it first crosses it.
        let below = clearance(t0) < 0.0;
        let slope = self.lipschitz * rd.truncate_y_len();
        let rate = if below {
            slope + rd.y.abs()
        } else {
            (slope - rd.y).max(1e-9)
        };
        let (mut t, mut t_prev) = (t0, t0);
        for _ in 0..1_000_000 {
            let f = clearance(t);
            if (f <= 0.0) != below {
                let (mut lo, mut hi) = (t_prev, t);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if (clearance(mid) <= 0.0) == below {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return Some(0.5 * (lo + hi));
            }
            if t > t1 {
                return None;
            }
            t_prev = t;
            t += (f.abs() / rate).max(1e-9);
        }
        None
    }
}

trait XzLen {
    fn truncate_y_len(&self) -> f64;
}

impl XzLen for DVec3 {
    fn truncate_y_len(&self) -> f64 {
        (self.x * self.x + self.z * self.z).sqrt()
    }
}

/// The view ray through the centre of pixel (x, y) of a `width` x `height` image, as the GPU
/// ray casters form it: from the eye towards the far-plane point under the pixel.
pub fn pixel_ray(view: &View, width: u32, height: u32, x: u32, y: u32) -> (DVec3, DVec3) {
    let inv = view.view_proj.as_dmat4().inverse();
    let ndc_x = 2.0 * (f64::from(x) + 0.5) / f64::from(width) - 1.0;
    let ndc_y = 1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(height);
    let far = inv * DVec4::new(ndc_x, ndc_y, 1.0, 1.0);
    let ro = view.eye.as_dvec3();
    (ro, (far.truncate() / far.w - ro).normalize())
}

/// World position of pixel (x, y) at depth-buffer value `depth` (wgpu's 0..1), for reading
/// back what a rasteriser drew.
pub fn unproject(view_proj: DMat4, width: u32, height: u32, x: u32, y: u32, depth: f64) -> DVec3 {
    let ndc_x = 2.0 * (f64::from(x) + 0.5) / f64::from(width) - 1.0;
    let ndc_y = 1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(height);
    let p = view_proj.inverse() * DVec4::new(ndc_x, ndc_y, depth, 1.0);
    p.truncate() / p.w
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::OrbitCamera;

    #[test]
    fn ray_down_the_middle_hits_the_height_there() {
        let params = TerrainParams::default();
        let s = Surface::new(&params);
        let ro = DVec3::new(0.1, 5.0, -0.3);
        let t = s.intersect(ro, DVec3::NEG_Y).unwrap();
        assert!((5.0 - t - s.height(0.1, -0.3)).abs() < 1e-9);
        assert!(
            s.intersect(ro, DVec3::Y).is_none(),
            "straight up never hits"
        );
    }

    #[test]
    fn centre_pixel_ray_points_at_the_target() {
        let cam = OrbitCamera::default();
        let view = cam.view(1.0);
        let (ro, rd) = pixel_ray(&view, 101, 101, 50, 50);
        let to_target = (cam.target.as_dvec3() - ro).normalize();
        assert!(rd.dot(to_target) > 1.0 - 1e-9);
    }
}
