//! Techniques on real scans from Debian packages (DESIGN §8), against the CPU references.
//! A missing package skips the test with a visible note; `make test` installs them.

mod common;

use common::{assert_clean, assert_images_match, gpu};
use std::path::Path;
use tessera::iso::raymarch::{Raymarch, RenderTarget};
use tessera::shaders;
use tessera_data::raw::{load_raw, RawOptions};
use tessera_data::{raycast, OrbitCamera, Volume};

const BRAINSMALL: &str = "/usr/share/doc/libvolpack1-dev/examples/brainsmall.den";

/// VolPack's MRI head: a 62-byte header, then 128×128×84 bytes.
fn brainsmall() -> Option<Volume> {
    let path = Path::new(BRAINSMALL);
    if !path.exists() {
        eprintln!("skipped: {BRAINSMALL} not found (Debian package libvolpack1-dev)");
        return None;
    }
    let opts = RawOptions {
        dims: Some([128, 128, 84]),
        dtype: Some("uint8".into()),
        header_bytes: 62,
        ..RawOptions::default()
    };
    Some(load_raw(path, &opts).expect("brainsmall.den loads"))
}

fn raymarch_matches_reference(volume: &Volume, isos: &[f32], camera: &OrbitCamera) {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let rm = Raymarch::new(&gpu, &compiler, volume.scalar_type()).unwrap();
    let prepared = rm.prepare(&gpu, volume).unwrap();
    let (w, h) = (128, 128);
    let target = RenderTarget::new(&gpu, w, h).unwrap();
    let background = tessera_data::shading::pack_rgba8(tessera_data::shading::BACKGROUND);
    for &iso in isos {
        target.poison(&gpu, u32::MAX).unwrap();
        let (image, _) = rm.render(&gpu, &prepared, &target, iso, camera).unwrap();
        let reference = raycast::render(volume, iso, camera, w, h);
        assert_images_match(
            &format!("real-{}-{iso}", volume.name()),
            &image,
            &reference,
            2,
            0.99,
        );
        let hits = image.pixels.iter().filter(|&&p| p != background).count();
        assert!(
            hits > (w * h / 50) as usize,
            "iso {iso}: only {hits} surface pixels"
        );
    }
    target.destroy(&gpu);
    prepared.destroy(&gpu);
    rm.destroy(&gpu);
    assert_clean(&gpu);
}

#[test]
fn raymarch_mri_head_matches_cpu_reference() {
    let Some(volume) = brainsmall() else { return };
    assert_eq!(volume.value_range(), (0.0, 202.0));
    // Skin (60) and a denser inner surface (100), seen from the face.
    let camera = OrbitCamera {
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
        distance: 1.8,
        fov_y_deg: 40.0,
    };
    raymarch_matches_reference(&volume, &[60.0, 100.0], &camera);
}
