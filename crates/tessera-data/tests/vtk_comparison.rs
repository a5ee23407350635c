//! Marching cubes against VTK on real scans from Debian packages: with VTK's ambiguity rule
//! the surface must match `vtkMarchingCubes` (area within 0.5 %, the same non-degenerate
//! triangle count); the asymptotic decider's numbers are printed beside them. A missing
//! package skips the test with a visible note.
//!
//! The VTK numbers come from VTK 9.7.2 (PyPI `vtk`), `vtkMarchingCubes` with spacing 1:
//!   python3 scripts/vtk-marching-cubes.py \
//!       /usr/share/doc/libvolpack1-dev/examples/brainsmall.den 30.5 60.5 100.5 140.5
//!   python3 scripts/vtk-marching-cubes.py /usr/share/mricron/templates/ch2.nii.gz \
//!       40.5 80.5 120.5 160.5
//! (`vtkFlyingEdges3D` gives the same areas and counts.) Isovalues sit between the integer
//! sample values so no vertex lands on a sample and no triangle degenerates.

use std::collections::HashMap;
use std::path::Path;
use tessera_data::marching_cubes::{marching_cubes_with, AmbiguityRule};
use tessera_data::mesh::TriangleMesh;
use tessera_data::raw::{load_raw, RawOptions};
use tessera_data::Volume;
use tessera_test::skip;

const BRAINSMALL: &str = "/usr/share/doc/libvolpack1-dev/examples/brainsmall.den";
const T1_TEMPLATE: &str = "/usr/share/mricron/templates/ch2.nii.gz";

/// `(iso, VTK area, VTK non-degenerate triangles)`.
type VtkRow = (f32, f64, usize);

const BRAINSMALL_VTK: [VtkRow; 4] = [
    (30.5, 67606.32, 209814),
    (60.5, 85538.71, 263296),
    (100.5, 13363.16, 42704),
    (140.5, 1124.966, 4736),
];

const T1_TEMPLATE_VTK: [VtkRow; 4] = [
    (40.5, 426687.5, 1283266),
    (80.5, 665459.7, 2017886),
    (120.5, 207076.9, 625208),
    (160.5, 77830.5, 247384),
];

fn available(path: &str, package: &str) -> bool {
    let found = Path::new(path).exists();
    if !found {
        skip("", &format!("{path} not found (Debian package {package})"));
    }
    found
}

fn non_degenerate(mesh: &TriangleMesh) -> usize {
    mesh.triangles
        .iter()
        .filter(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            (b - a).cross(c - a) != glam::Vec3::ZERO
        })
        .count()
}

/// Asserts `mesh` is a closed manifold, consistently oriented: each edge used once in each
/// direction, except where the volume's boundary cuts the surface.
fn assert_closed(name: &str, mesh: &TriangleMesh, dims: [u32; 3]) {
    let on_boundary = |a: u32, b: u32| {
        let (p, q) = (mesh.positions[a as usize], mesh.positions[b as usize]);
        (0..3).any(|i| {
            let last = (dims[i] - 1) as f32;
            (p[i] == 0.0 && q[i] == 0.0) || (p[i] == last && q[i] == last)
        })
    };
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for &[a, b, c] in &mesh.triangles {
        for e in [(a, b), (b, c), (c, a)] {
            *directed.entry(e).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &directed {
        let back = directed.contains_key(&(b, a));
        assert!(
            n == 1 && (back || on_boundary(a, b)),
            "{name}: edge {a}-{b} used {n} times, reverse {back}"
        );
    }
}

fn compare(volume: &Volume, rows: &[VtkRow]) {
    for &(iso, vtk_area, vtk_tris) in rows {
        let [decider, vtk_rule] = [AmbiguityRule::AsymptoticDecider, AmbiguityRule::Vtk]
            .map(|rule| marching_cubes_with(volume, iso, rule));
        let area = |m: &TriangleMesh| f64::from(m.surface_area_with_spacing(volume.spacing()));
        let (a_vtk_rule, a_decider) = (area(&vtk_rule), area(&decider));
        println!(
            "{} iso {iso}: VTK {vtk_area:.1} / {vtk_tris}; VTK rule {a_vtk_rule:.1} ({:+.3} %) / {}; \
             decider {a_decider:.1} ({:+.3} %) / {}",
            volume.name(),
            100.0 * (a_vtk_rule / vtk_area - 1.0),
            non_degenerate(&vtk_rule),
            100.0 * (a_decider / vtk_area - 1.0),
            non_degenerate(&decider),
        );
        assert!(
            (a_vtk_rule / vtk_area - 1.0).abs() < 0.005,
            "{} iso {iso}: area {a_vtk_rule} vs VTK {vtk_area}",
            volume.name()
        );
        assert_eq!(
            non_degenerate(&vtk_rule),
            vtk_tris,
            "{} iso {iso}",
            volume.name()
        );
        // Closed surfaces around tissue face out of it: positive enclosed volume.
        let name = format!("{} iso {iso}", volume.name());
        for mesh in [&decider, &vtk_rule] {
            assert_closed(&name, mesh, volume.dims());
        }
        assert!(vtk_rule.enclosed_volume() > 0.0 && decider.enclosed_volume() > 0.0);
    }
}

#[test]
fn mri_head_matches_vtk_marching_cubes() {
    if !available(BRAINSMALL, "libvolpack1-dev") {
        return;
    }
    let opts = RawOptions {
        dims: Some([128, 128, 84]),
        dtype: Some("uint8".into()),
        header_bytes: 62,
        ..RawOptions::default()
    };
    let volume = load_raw(Path::new(BRAINSMALL), &opts).expect("brainsmall.den loads");
    compare(&volume, &BRAINSMALL_VTK);
}

#[test]
fn t1_template_matches_vtk_marching_cubes() {
    if !available(T1_TEMPLATE, "mricron-data") {
        return;
    }
    let volume = tessera_data::load::load_volume(Path::new(T1_TEMPLATE), &RawOptions::default())
        .expect("ch2 loads");
    assert_eq!(
        (volume.dims(), volume.spacing()),
        ([181, 217, 181], [1.0; 3])
    );
    compare(&volume, &T1_TEMPLATE_VTK);
}
