//! Turning, panning and zooming the orbit camera with the mouse: left drag orbits, right or
//! middle drag (or shift + left drag) pans, the wheel zooms, a double click resets.

use tessera_data::OrbitCamera;

/// Degrees of turn per pixel dragged.
const DEGREES_PER_PIXEL: f32 = 0.4;
/// Distance factor per wheel point (egui's scroll unit).
const ZOOM_PER_POINT: f32 = 0.998;
/// Closest and farthest distances (the data's longest side is 1).
const DISTANCE_RANGE: (f32, f32) = (0.05, 50.0);

/// Turns the camera by a drag of `(dx, dy)` pixels: right turns the object right, down tilts
/// it towards the viewer.
pub fn orbit(camera: &mut OrbitCamera, dx: f32, dy: f32) {
    camera.azimuth_deg = (camera.azimuth_deg - dx * DEGREES_PER_PIXEL).rem_euclid(360.0);
    camera.elevation_deg = (camera.elevation_deg + dy * DEGREES_PER_PIXEL).clamp(-89.0, 89.0);
}

/// Moves the view with a drag of `(dx, dy)` pixels in an image `height` pixels high, so the
/// object follows the pointer at the distance of the orbit's centre.
pub fn pan(camera: &mut OrbitCamera, dx: f32, dy: f32, height: f32) {
    let visible = 2.0 * camera.distance * (camera.fov_y_deg.to_radians() * 0.5).tan();
    let per_pixel = visible / height.max(1.0);
    camera.eye_shift -= dx * per_pixel;
    camera.eye_rise += dy * per_pixel;
}

/// Zooms by a wheel turn of `points` (positive: closer).
pub fn zoom(camera: &mut OrbitCamera, points: f32) {
    camera.distance =
        (camera.distance * ZOOM_PER_POINT.powf(points)).clamp(DISTANCE_RANGE.0, DISTANCE_RANGE.1);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gestures_stay_in_range() {
        let mut c = OrbitCamera::default();
        orbit(&mut c, 10_000.0, 10_000.0);
        assert!((0.0..360.0).contains(&c.azimuth_deg));
        assert_eq!(c.elevation_deg, 89.0);
        zoom(&mut c, 1e6);
        assert_eq!(c.distance, DISTANCE_RANGE.0);
        zoom(&mut c, -1e6);
        assert_eq!(c.distance, DISTANCE_RANGE.1);
        let mut p = OrbitCamera::default();
        pan(&mut p, 100.0, 0.0, 100.0);
        assert!(p.eye_shift < 0.0 && p.eye_rise == 0.0);
    }
}
