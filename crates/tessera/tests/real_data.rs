//! Techniques on real scans from Debian packages (DESIGN §8), against the CPU references.
//! A missing package skips the test with a visible note; `make test` installs them.

mod common;

use tessera::iso::direct::FrameOptions;

use common::{assert_clean, assert_images_match, gpu, skip, Need, TestGpu};
use std::path::Path;
use tessera::iso::raymarch::Raymarch;
use tessera::shaders;
use tessera::target::Target;
use tessera_data::raw::{load_raw, RawOptions};
use tessera_data::{raycast, OrbitCamera, Volume};

const BRAINSMALL: &str = "/usr/share/doc/libvolpack1-dev/examples/brainsmall.den";
const T1_TEMPLATE: &str = "/usr/share/mricron/templates/ch2.nii.gz";

/// VolPack's MRI head: a 62-byte header, then 128×128×84 bytes.
fn brainsmall() -> Option<Volume> {
    let path = Path::new(BRAINSMALL);
    if !path.exists() {
        skip(
            "",
            &format!("{BRAINSMALL} not found (Debian package libvolpack1-dev)"),
        );
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

/// pyvista's frog tissue labels (`scripts/fetch-frog.sh`): 500×470×136 uint8 labels 0 to 29,
/// spacing 1 × 1 × 1.5.
fn frog() -> Option<Volume> {
    let path = tessera_test::data_file("frog/frog_tissues.vti");
    if !path.exists() {
        skip(
            "",
            &format!("{} not found (scripts/fetch-frog.sh)", path.display()),
        );
        return None;
    }
    let volume = tessera_data::load::load_volume(&path, &RawOptions::default()).expect("frog");
    assert_eq!(
        (volume.dims(), volume.spacing(), volume.value_range()),
        ([500, 470, 136], [1.0, 1.0, 1.5], (0.0, 29.0))
    );
    Some(volume)
}

fn raymarch_matches_reference(volume: &Volume, isos: &[f32], camera: &OrbitCamera) {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let rm = Raymarch::new(&gpu, &compiler, volume.scalar_type()).unwrap();
    let prepared = rm.prepare(&gpu, volume).unwrap();
    let (w, h) = (128, 128);
    let target = Target::new(&gpu, w, h).unwrap();
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
        eye_shift: 0.0,
        eye_rise: 0.0,
        up: Default::default(),
        fov_y_deg: 40.0,
    };
    raymarch_matches_reference(&volume, &[60.0, 100.0], &camera);
}

#[test]
fn raymarch_t1_brain_template_matches_cpu_reference() {
    let path = Path::new(T1_TEMPLATE);
    if !path.exists() {
        skip(
            "",
            &format!("{T1_TEMPLATE} not found (Debian package mricron-data)"),
        );
        return;
    }
    let volume = tessera_data::load::load_volume(path, &RawOptions::default()).expect("ch2 loads");
    assert_eq!(volume.dims(), [181, 217, 181]);
    let camera = OrbitCamera {
        azimuth_deg: 120.0,
        elevation_deg: 20.0,
        distance: 1.8,
        eye_shift: 0.0,
        eye_rise: 0.0,
        up: Default::default(),
        fov_y_deg: 40.0,
    };
    let (lo, hi) = volume.value_range();
    raymarch_matches_reference(
        &volume,
        &[lo + 0.3 * (hi - lo), lo + 0.5 * (hi - lo)],
        &camera,
    );
}

/// Labels, not intensities, on an anisotropic grid: the body (every label above 0) and the
/// tissues labelled 4 and above.
#[test]
fn raymarch_frog_labels_match_cpu_reference() {
    let Some(volume) = frog() else { return };
    let camera = OrbitCamera {
        azimuth_deg: 35.0,
        elevation_deg: 30.0,
        distance: 1.7,
        ..OrbitCamera::default()
    };
    raymarch_matches_reference(&volume, &[0.5, 3.5], &camera);
}

#[test]
fn direct_mri_head_triangles_equal_cpu_marching_cubes() {
    let Some(volume) = brainsmall() else { return };
    mesh_path_triangles_equal_cpu_marching_cubes(&volume, 60.0);
}

/// The same on the frog's labels: the tissues labelled 10 and above, 1.23 M triangles.
#[test]
fn direct_frog_triangles_equal_cpu_marching_cubes() {
    let Some(volume) = frog() else { return };
    mesh_path_triangles_equal_cpu_marching_cubes(&volume, 9.5);
}

fn mesh_path_triangles_equal_cpu_marching_cubes(volume: &Volume, iso: f32) {
    let Some(gpu) = TestGpu::with(&[Need::MeshShaders]) else {
        return;
    };
    let compiler = shaders::compiler();
    let direct = tessera::iso::direct::Direct::new(&gpu, &compiler, volume.scalar_type()).unwrap();
    let prepared = direct.prepare(&gpu, volume).unwrap();
    let target = tessera::iso::direct::RasterTarget::new(&gpu, 96, 96).unwrap();
    let cpu = tessera_data::marching_cubes::marching_cubes(volume, iso);
    let frame = direct
        .render(
            &gpu,
            &prepared,
            &target,
            iso,
            &OrbitCamera::default(),
            &FrameOptions {
                capture_capacity: cpu.triangle_count() as u32 + 64,
                ..Default::default()
            },
        )
        .unwrap();
    assert_eq!(frame.stats.triangles as usize, cpu.triangle_count());
    // Same multiset of triangles: compare sorted, orientation-preserving canonical forms.
    let canon = |t: [glam::Vec3; 3]| {
        let k = (0..3)
            .min_by(|&a, &b| t[a].to_array().partial_cmp(&t[b].to_array()).unwrap())
            .unwrap();
        [t[k], t[(k + 1) % 3], t[(k + 2) % 3]].map(|v| (v * 1024.0).round().as_ivec3().to_array())
    };
    let mut balance: std::collections::HashMap<_, i64> = std::collections::HashMap::new();
    for t in frame.triangles.unwrap() {
        *balance.entry(canon(t)).or_default() += 1;
    }
    for t in &cpu.triangles {
        *balance
            .entry(canon(t.map(|i| cpu.positions[i as usize])))
            .or_default() -= 1;
    }
    let differing: i64 = balance.values().filter(|&&c| c > 0).sum();
    let cpu_tris = &cpu.triangles;
    // u8 data at a half-integer-free isovalue puts vertices at multiples of 1/k; rounding to
    // 1/1024 can still split a rare pair differently, so allow a handful.
    assert!(
        differing <= (cpu_tris.len() / 10_000 + 2) as i64,
        "{differing} of {} triangles differ",
        cpu_tris.len()
    );
    assert_clean(&gpu);
}

/// Paper C's meshlets extracted on the GPU from real scans equal the CPU reference's bit for
/// bit, and welded they are marching cubes' surface (the one `tessera extract` writes).
#[test]
fn meshlets_and_pmb_of_real_scans_equal_the_cpu_reference() {
    use tessera::iso::meshlets::ExtractionPath;
    use tessera::iso::surface::{extract_surface, SurfaceMethod};
    use tessera_data::marching_cubes::{marching_cubes_with, AmbiguityRule};
    use tessera_data::meshlets::extract_meshlets;
    let mut volumes = Vec::new();
    volumes.extend(brainsmall().map(|v| (v, 60.5)));
    volumes.extend(frog().map(|v| (v, 0.5)));
    let path = Path::new(T1_TEMPLATE);
    if path.exists() {
        let ch2 = tessera_data::load::load_volume(path, &RawOptions::default()).unwrap();
        let (lo, hi) = ch2.value_range();
        let iso = (lo + 0.4 * (hi - lo)).floor() + 0.5;
        volumes.push((ch2, iso));
    } else {
        skip(
            "ch2",
            &format!("{T1_TEMPLATE} not found (Debian package mricron-data)"),
        );
    }
    let gpu = gpu();
    let rule = AmbiguityRule::default();
    for (volume, iso) in &volumes {
        let texel = volume.iso_to_texel(tessera_data::IsoValue::Raw(*iso));
        let method = SurfaceMethod::Meshlets(ExtractionPath::Compute);
        let surface = extract_surface(Some(&gpu), volume, texel, rule, method).unwrap();
        let gpu_meshlets = surface.meshlets.unwrap().in_origin_order().unwrap();
        let cpu_meshlets = extract_meshlets(volume, texel, rule).unwrap();
        assert!(cpu_meshlets.meshlets.len() > 1000, "{}", volume.name());
        assert!(
            gpu_meshlets == cpu_meshlets,
            "{}: GPU meshlets differ from the CPU reference",
            volume.name()
        );
        let mc = marching_cubes_with(volume, texel, rule);
        assert_eq!(
            surface.mesh.vertex_count(),
            mc.vertex_count(),
            "{}",
            volume.name()
        );
        assert_eq!(
            surface.mesh.canonical_triangle_multiset(1e-4),
            mc.canonical_triangle_multiset(1e-4),
            "{}",
            volume.name()
        );
        assert!(surface.cost.extract_ms > 0.0 && surface.cost.stored_bytes > 0);
        // PMB, paper C's real-time reference, gives the same welded surface at every block
        // size.
        let mc_triangles = mc.canonical_triangle_multiset(1e-4);
        for size in tessera_data::pmb::PmbBlockSize::ALL {
            let pmb =
                extract_surface(Some(&gpu), volume, texel, rule, SurfaceMethod::Pmb(size)).unwrap();
            let what = format!("{} PMB {}", volume.name(), size.name());
            assert_eq!(pmb.mesh.vertex_count(), mc.vertex_count(), "{what}");
            assert!(
                pmb.mesh.canonical_triangle_multiset(1e-4) == mc_triangles,
                "{what}: triangles differ from marching cubes"
            );
        }
    }
    assert_clean(&gpu);
}

/// `direct`'s compute path through the front door on the MRI head with culling off, on and
/// automatic: every frame of a turning camera draws the same image, whichever way each frame
/// took; the automatic choice culls where the frame's counts say culling pays.
#[test]
fn direct_culling_choices_draw_the_same_mri_head() {
    let Some(volume) = brainsmall() else { return };
    culling_choices_draw_the_same(volume, 60.0, 8);
}

/// The same on the frog's labels (the tissues labelled 10 and above: 1.23 M triangles), 32 M
/// samples on an anisotropic grid.
#[test]
fn direct_culling_choices_draw_the_same_frog() {
    let Some(volume) = frog() else { return };
    culling_choices_draw_the_same(volume, 9.5, 4);
}

/// The frog's whole body, 1,511,860 triangles: a list of them with 96 bytes of attributes each
/// would pass lavapipe's largest storage buffer (128 MiB); with 48 it fits, and the compute
/// path draws it, binding nothing out of range (the validation layer is watching). A device
/// whose lists hold fewer says so, naming the triangles and the limit.
#[test]
fn direct_compute_draws_the_frogs_whole_body_or_says_it_cannot() {
    use tessera::iso::direct::compute::TriangleLists;
    use tessera::path::PathChoice;
    use tessera::renderer::{self, Culling, RendererOptions, Technique};
    use tessera_data::scene::{Appearance, Dataset};
    use tessera_data::IsoValue;
    let Some(volume) = frog() else { return };
    let gpu = gpu();
    let options = RendererOptions {
        path: PathChoice::Compute,
        culling: Culling::Off,
        ..RendererOptions::default()
    };
    let Ok(mut r) = renderer::create(&gpu, Technique::Direct, &options) else {
        skip("", "no compute path for direct");
        return;
    };
    r.set_data(&gpu, &Dataset::Volume(volume)).unwrap();
    let look = Appearance {
        iso: IsoValue::Raw(0.5),
        ..Appearance::default()
    };
    r.set_appearance(&gpu, &look).unwrap();
    let drawn = renderer::render_image(&gpu, r.as_mut(), &OrbitCamera::default(), (64, 48));
    const BODY_TRIANGLES: u32 = 1_511_860;
    if BODY_TRIANGLES > TriangleLists::default_capacity(&gpu) {
        common::assert_refused_for_the_lists(drawn, u64::from(BODY_TRIANGLES));
    } else {
        let image = drawn.unwrap().image;
        assert_eq!(r.stats().triangles, Some(u64::from(BODY_TRIANGLES)));
        assert!(!image.pixels.contains(&u32::MAX));
    }
    assert_clean(&gpu);
}

fn culling_choices_draw_the_same(volume: Volume, iso: f32, frames: usize) {
    use tessera::path::PathChoice;
    use tessera::renderer::{self, Culling, Frame, RendererOptions, Technique};
    use tessera_data::scene::{Appearance, Dataset};
    use tessera_data::IsoValue;
    let gpu = gpu();
    let data = Dataset::Volume(volume);
    let size = (128, 96);
    let mut renderers = Vec::new();
    for culling in [Culling::Off, Culling::On, Culling::Auto] {
        let options = RendererOptions {
            path: PathChoice::Compute,
            culling,
            ..RendererOptions::default()
        };
        let Ok(mut r) = renderer::create(&gpu, Technique::Direct, &options) else {
            skip("", "no compute path for direct");
            return;
        };
        r.set_data(&gpu, &data).unwrap();
        r.set_appearance(
            &gpu,
            &Appearance {
                iso: IsoValue::Raw(iso),
                ..Appearance::default()
            },
        )
        .unwrap();
        renderers.push(r);
    }
    let mut frame = Frame::new(&gpu, size).unwrap();
    let mut auto_culled = 0;
    for k in 0..frames {
        let camera = OrbitCamera {
            azimuth_deg: 20.0 + 25.0 * k as f32,
            elevation_deg: 15.0,
            distance: if k % 2 == 0 { 1.8 } else { 0.9 },
            ..OrbitCamera::default()
        };
        let mut images = Vec::new();
        for r in &mut renderers {
            let view = r.view(&camera, size).unwrap();
            frame.render(&gpu, r.as_mut(), &view).unwrap();
            images.push(frame.target.read(&gpu).unwrap());
        }
        let auto = renderers[2].stats();
        auto_culled += auto.details["culled"];
        assert_eq!(
            auto.details["culled"] == 1,
            auto.blocks_drawn.is_some(),
            "frame {k}"
        );
        assert!(
            !images[0].pixels.contains(&u32::MAX),
            "frame {k}: unwritten pixels"
        );
        assert_eq!(images[1].pixels, images[0].pixels, "frame {k}: culled");
        assert_eq!(images[2].pixels, images[0].pixels, "frame {k}: automatic");
    }
    assert!(auto_culled >= 2, "the first two frames probe culling");
    assert_clean(&gpu);
}
