//! `tessera extract` on the GPU (meshlets, both pipelines) against the CPU extraction: the
//! same welded surface in PLY and OBJ, the meshlet file, and clear refusals.

mod common;

use common::*;
use std::path::Path;
use tessera_data::mesh::TriangleMesh;
use tessera_data::mesh_read::read_mesh_file;
use tessera_data::meshlets::{read_meshlet_file, MeshletUnits};

/// A procedural volume with a non-unit spacing and an isovalue no sample equals (so welding
/// by position and marching cubes' one vertex per edge agree).
const DATA: [&str; 6] = [
    "procedural:marschner-lobb:29:f32",
    "--iso",
    "0.5013",
    "--spacing",
    "0.5,1,2",
    "--ambiguity",
];

fn extract(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["extract"];
    args.extend(DATA);
    args.push("decider");
    args.extend(["-o", out.to_str().unwrap()]);
    args.extend(extra);
    let o = tessera(&args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    o
}

fn printed(o: &std::process::Output, before: &str) -> f64 {
    let text = String::from_utf8_lossy(&o.stdout);
    text.split(before)
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.trim_end_matches([',', ';']).parse().ok())
        .unwrap_or_else(|| panic!("no '{before}' in {text}"))
}

fn same_surface(a: &TriangleMesh, b: &TriangleMesh, what: &str) {
    assert!(a.triangle_count() > 500, "{what}: too little surface");
    assert_eq!(
        a.vertex_count(),
        b.vertex_count(),
        "{what}: welded vertices"
    );
    assert!(
        a.canonical_triangle_multiset(1e-4) == b.canonical_triangle_multiset(1e-4),
        "{what}: triangles differ"
    );
}

#[test]
fn gpu_extraction_writes_the_cpu_surface_as_ply_obj_and_meshlets() {
    let dir = scratch("extract-gpu");
    let cpu_ply = dir.join("cpu.ply");
    let cpu = extract(&cpu_ply, &["--method", "cpu"]);
    let reference = read_mesh_file(&cpu_ply).unwrap();

    let obj = dir.join("gpu.obj");
    let tsm = dir.join("gpu.tsm");
    let gpu = extract(&obj, &["--meshlets", tsm.to_str().unwrap()]);
    let ours = read_mesh_file(&obj).unwrap();
    same_surface(&ours, &reference, "meshlets (OBJ) vs cpu (PLY)");
    assert_eq!(
        printed(&gpu, "iso 0.5013: ") as usize,
        reference.triangle_count()
    );
    let (a, b) = (printed(&gpu, "area "), printed(&cpu, "area "));
    assert!((a - b).abs() <= 1e-4 * b, "areas {a} and {b}");
    // Physical units: the surface reaches across x and y, whose 28 cells are 0.5 and 1 wide,
    // and stays within z's 2 × 28.
    let (lo, hi) = ours.bounds().unwrap();
    let extent = hi - lo;
    assert!(
        (13.0..=14.0).contains(&extent.x) && (27.0..=28.0).contains(&extent.y),
        "{lo} {hi}"
    );
    assert!(lo.z >= 0.0 && hi.z <= 56.0, "{lo} {hi}");

    let file = read_meshlet_file(&tsm, &std::fs::read(&tsm).unwrap()).unwrap();
    assert_eq!(file.units, MeshletUnits::Physical);
    assert_eq!(file.isovalue, 0.5013);
    assert_eq!(
        printed(&gpu, "; ") as usize,
        file.mesh.meshlets.len(),
        "printed meshlet count"
    );
    file.mesh.validate().unwrap();
    same_surface(&file.mesh.welded(), &reference, "meshlet file vs cpu");

    // PMB of every block size writes the same welded surface.
    for size in ["4x4x4", "8x4x4", "8x8x4", "8x8x8"] {
        let ply = dir.join(format!("pmb-{size}.ply"));
        let o = extract(&ply, &["--method", &format!("pmb:{size}")]);
        same_surface(
            &read_mesh_file(&ply).unwrap(),
            &reference,
            &format!("pmb {size}"),
        );
        assert!(
            String::from_utf8_lossy(&o.stdout).contains(&format!("GPU PMB ({size} blocks)")),
            "{}",
            String::from_utf8_lossy(&o.stdout)
        );
    }

    // The paper's task/mesh pipeline, where the device has it, writes the same surface.
    let mesh_ply = dir.join("mesh.ply");
    let mut args = vec!["extract"];
    args.extend(DATA);
    args.extend([
        "decider",
        "--path",
        "mesh",
        "-o",
        mesh_ply.to_str().unwrap(),
    ]);
    let o = tessera(&args);
    if o.status.success() {
        same_surface(
            &read_mesh_file(&mesh_ply).unwrap(),
            &reference,
            "task/mesh path",
        );
    } else {
        assert_fails_with(&o, &["task and mesh shaders"]);
        eprintln!("skipped: task/mesh extraction (the device has no VK_EXT_mesh_shader)");
    }
}

#[test]
fn extract_refuses_what_it_cannot_do_and_says_why() {
    let dir = scratch("extract-bad");
    let out = dir.join("s.ply");
    let out = out.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["extract", "procedural:sphere:12"];
        args.extend(extra);
        if !extra.contains(&"-o") {
            args.extend(["-o", out]);
        }
        tessera(&args)
    };
    let cases: [(&[&str], &[&str]); 7] = [
        (
            &["--method", "pmbx"],
            &["method 'pmbx'", "meshlets, pmb[:XxYxZ] or cpu"],
        ),
        (&["--method", "pmb:4x4x2"], &["block size '4x4x2'", "8x8x8"]),
        (
            &["--method", "pmb", "--path", "mesh"],
            &["pmb method has no 'mesh' path"],
        ),
        (
            &["--method", "cpu", "--meshlets", "m.tsm"],
            &["--meshlets needs --method meshlets"],
        ),
        (
            &["--method", "cpu", "--path", "mesh"],
            &["cpu method has no 'mesh' path"],
        ),
        (
            &["--path", "fragment"],
            &["path 'fragment'", "compute, mesh or auto"],
        ),
        (&["-o", "surface.stl"], &["surface.stl", ".ply or .obj"]),
    ];
    for (extra, needles) in cases {
        assert_fails_with(&run(extra), needles);
    }
    assert!(!Path::new(out).exists(), "a refused run wrote {out}");
}

#[test]
fn pipeline_stats_are_printed_or_their_absence_said() {
    let dir = scratch("extract-stats");
    let out = dir.join("s.ply");
    let o = tessera(&[
        "--pipeline-stats",
        "extract",
        "procedural:sphere:16",
        "--iso",
        "100.5",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    let info = String::from_utf8_lossy(&tessera(&["info"]).stdout).into_owned();
    if info.contains("pipeline statistics      yes") {
        assert!(
            stdout.contains("pipeline meshlet extraction /"),
            "no statistics of the extraction pipeline:\n{stdout}"
        );
    } else {
        assert!(info.contains("pipeline statistics      no"), "{info}");
        assert!(
            stdout.contains("does not report them"),
            "the missing statistics went unmentioned:\n{stdout}"
        );
    }
}
