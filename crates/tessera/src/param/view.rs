//! The camera of a parametric frame: `tessera_data::Projection`'s view and projection, with the
//! depth range fitted to the scene's bounding spheres instead of the unit box, and the raster
//! size (image size times the supersampling factor) that every pass works in.

use crate::error::{check_image_size, Error, Result};
use glam::{Mat4, Vec2, Vec3, Vec4};
use tessera_data::param::reference::ReferenceView;
use tessera_data::OrbitCamera;

/// Smallest near plane, as a fraction of the far plane (keeps f32 depth usable).
const MIN_NEAR_FRACTION: f32 = 1e-4;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamView {
    pub world_to_clip: Mat4,
    pub eye: Vec3,
    /// Unit direction towards the light: above, right and behind the eye, as the volume
    /// techniques' `GridCamera` puts it.
    pub light: Vec3,
    pub near: f32,
    pub far: f32,
    /// Image size in pixels.
    pub size: (u32, u32),
    /// Raster samples per image pixel along each axis.
    pub supersample: u32,
}

impl ParamView {
    /// The view of `camera` onto a scene with these bounding spheres (centre, radius).
    pub fn new(
        bounds: &[(Vec3, f32)],
        camera: &OrbitCamera,
        size: (u32, u32),
        supersample: u32,
    ) -> Result<ParamView> {
        check_image_size(size.0, size.1)?;
        if supersample == 0 || supersample > 8 {
            return Err(Error::Invalid(format!(
                "supersampling must be 1 to 8 samples per axis, got {supersample}"
            )));
        }
        let (forward, right, up) = camera.basis();
        let eye = camera.eye();
        if !(eye.is_finite() && camera.fov_y_deg > 0.0 && camera.fov_y_deg < 180.0) {
            return Err(Error::Invalid(format!("unusable camera {camera:?}")));
        }
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for &(centre, radius) in bounds {
            let d = forward.dot(centre - eye);
            lo = lo.min(d - radius);
            hi = hi.max(d + radius);
        }
        if !hi.is_finite() || !lo.is_finite() {
            return Err(Error::Invalid(
                "the scene has no finite bounds to fit the depth range to".into(),
            ));
        }
        // Everything behind the eye: any range will do, nothing is drawn.
        let far = (hi * 1.001).max(1e-3);
        let near = (lo * 0.999).max(far * MIN_NEAR_FRACTION);
        let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
        let tan_x = tan_y * size.0 as f32 / size.1 as f32;
        let view = Mat4::from_cols(
            Vec4::new(right.x, up.x, forward.x, 0.0),
            Vec4::new(right.y, up.y, forward.y, 0.0),
            Vec4::new(right.z, up.z, forward.z, 0.0),
            Vec4::new(-right.dot(eye), -up.dot(eye), -forward.dot(eye), 1.0),
        );
        let a = far / (far - near);
        let proj = Mat4::from_cols(
            Vec4::new(1.0 / tan_x, 0.0, 0.0, 0.0),
            Vec4::new(0.0, -1.0 / tan_y, 0.0, 0.0),
            Vec4::new(0.0, 0.0, a, 1.0),
            Vec4::new(0.0, 0.0, -a * near, 0.0),
        );
        Ok(ParamView {
            world_to_clip: proj * view,
            eye,
            light: (-forward + 0.6 * up + 0.4 * right).normalize(),
            near,
            far,
            size,
            supersample,
        })
    }

    /// The raster the passes draw into: `k` times the image size.
    pub fn raster_size(&self) -> (u32, u32) {
        (
            self.size.0 * self.supersample,
            self.size.1 * self.supersample,
        )
    }

    pub fn viewport(&self) -> Vec2 {
        let (w, h) = self.raster_size();
        Vec2::new(w as f32, h as f32)
    }

    /// Raster position and NDC depth of `p`, `None` when not in front of the eye: the
    /// arithmetic of `param_project` in `view.glsl`, operation for operation.
    pub fn project(&self, p: Vec3) -> Option<(Vec2, f32)> {
        let m = self.world_to_clip;
        let clip = ((m.x_axis * p.x + m.y_axis * p.y) + m.z_axis * p.z) + m.w_axis;
        let viewport = self.viewport();
        let pixel = Vec2::new(
            (clip.x / clip.w * 0.5 + 0.5) * viewport.x,
            (clip.y / clip.w * 0.5 + 0.5) * viewport.y,
        );
        (clip.w > 0.0 && !pixel.is_nan()).then_some((pixel, clip.z / clip.w))
    }

    /// The same view for `tessera_data::param::reference`.
    pub fn reference(&self) -> ReferenceView {
        ReferenceView {
            world_to_clip: self.world_to_clip,
            eye: self.eye,
            light: self.light,
            width: self.size.0,
            height: self.size.1,
            supersample: self.supersample,
        }
    }
}
