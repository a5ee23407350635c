//! The `tessera` binary end to end: good runs produce files, bad input gives an error that
//! names the file and the problem, never a panic.

mod common;

use common::*;

#[test]
fn renders_procedural_volume_to_png() {
    let dir = scratch("render");
    let out = dir.join("ml.png");
    let o = tessera(&[
        "--validation",
        "render",
        "procedural:marschner-lobb:40",
        "--size",
        "96x64",
        "--camera",
        "-30,20,1.8",
        "--iso-fraction",
        "0.5",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(png_size(&out), (96, 64));
}

#[test]
fn direct_renders_on_both_paths_and_in_stereo() {
    let dir = scratch("direct");
    for (path, stereo, width) in [
        ("graphics", None, 80),
        ("compute", None, 80),
        ("compute", Some("0.1"), 160),
    ] {
        let out = dir.join(format!("{path}-{width}.png"));
        let mut args = vec![
            "--validation",
            "render",
            "procedural:sphere:32",
            "--technique",
            "direct",
            "--path",
            path,
            "--size",
            "80x60",
            "-o",
            out.to_str().unwrap(),
        ];
        if let Some(s) = stereo {
            args.extend(["--stereo", s]);
        }
        let o = tessera(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(String::from_utf8_lossy(&o.stdout).contains(&format!("{path} path")));
        assert_eq!(png_size(&out), (width, 60));
    }
    let o = tessera(&[
        "render",
        "procedural:sphere:16",
        "--technique",
        "direct",
        "--path",
        "warp",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn renders_tet_meshes_with_interval_shading() {
    let dir = scratch("tets");
    let out = dir.join("sphere.png");
    let o = tessera(&[
        "--validation",
        "render",
        "tets:sphere:4",
        "--size",
        "64x48",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(png_size(&out), (64, 48));
    // A mesh file written by the library, read back by the loader the CLI picks by extension.
    let file = dir.join("box.vtu");
    let mesh = tessera_data::tet::procedural::box_mesh(2);
    tessera_data::tet::write_vtu_ascii(&mesh, &file).unwrap();
    let bytes = std::fs::read(&file).unwrap();
    let out = dir.join("box.png");
    let o = tessera(&[
        "--validation",
        "render",
        file.to_str().unwrap(),
        "--size",
        "64x48",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("48 tets"));
    // Cut short, and asked for a volume technique: clear errors naming the file.
    std::fs::write(&file, &bytes[..bytes.len() / 2]).unwrap();
    let o = tessera(&[
        "render",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_fails_with(&o, &["box.vtu"]);
    let o = tessera(&["render", "tets:box:2", "--technique", "raymarch"]);
    assert_fails_with(&o, &["tets:box:2", "interval"]);
    let o = tessera(&["render", "tets:cone:2"]);
    assert_fails_with(&o, &["cone", "sphere"]);
    let out = dir.join("asteroids.png");
    for path in ["graphics", "compute"] {
        let o = tessera(&[
            "--validation",
            "render",
            "tets:asteroids:40",
            "--path",
            path,
            "--size",
            "48x40",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{path}: {}", stderr(&o));
        assert!(String::from_utf8_lossy(&o.stdout).contains("sphere-traced asteroids"));
    }
    // One absorption colour for every tet; a bad colour is refused by the argument parser.
    let o = tessera(&[
        "render",
        "tets:box:2",
        "--absorption",
        "0.5,1,2",
        "--size",
        "32x32",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = tessera(&["render", "tets:box:2", "--absorption", "1,nan,1"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = tessera(&["render", "tets:asteroids:0"]);
    assert_fails_with(&o, &["tets:asteroids:0", "COUNT"]);
}

#[test]
fn integrates_tet_scalars_on_both_paths() {
    let dir = scratch("tet-scalars");
    let out = dir.join("emission.png");
    for path in ["graphics", "compute"] {
        for mode in ["absorption", "emission", "mip"] {
            let o = tessera(&[
                "--validation",
                "render",
                "tets:sphere:3",
                "--integrate",
                mode,
                "--tf",
                "hot",
                "--path",
                path,
                "--size",
                "40x32",
                "-o",
                out.to_str().unwrap(),
            ]);
            assert!(o.status.success(), "{path} {mode}: {}", stderr(&o));
            let stdout = String::from_utf8_lossy(&o.stdout);
            assert!(
                stdout.contains(&format!("{path} path"))
                    && stdout.contains(mode.trim_end_matches("mip")),
                "{stdout}"
            );
        }
    }
    // A mesh without vertex scalars, a bad range and an unknown transfer function.
    let file = dir.join("plain.node");
    let mut mesh = tessera_data::tet::procedural::box_mesh(1);
    mesh.scalars = None;
    tessera_data::tet::write_tetgen(&mesh, &file).unwrap();
    let o = tessera(&["render", file.to_str().unwrap(), "--integrate", "emission"]);
    assert_fails_with(&o, &["plain.node", "scalars"]);
    let o = tessera(&[
        "render",
        "tets:box:2",
        "--integrate",
        "mip",
        "--range",
        "1,0",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = tessera(&[
        "render",
        "tets:box:2",
        "--integrate",
        "mip",
        "--tf",
        "rainbow",
    ]);
    assert_fails_with(&o, &["rainbow", "cool-warm"]);
}

#[test]
fn truncated_raw_names_file_and_problem() {
    let dir = scratch("truncated");
    let file = dir.join("cut_16x16x16_uint8.raw");
    std::fs::write(&file, vec![7u8; 1000]).unwrap();
    let o = tessera(&[
        "render",
        file.to_str().unwrap(),
        "-o",
        dir.join("x.png").to_str().unwrap(),
    ]);
    assert_fails_with(&o, &["cut_16x16x16_uint8.raw", "truncated"]);
}

#[test]
fn explicit_dims_that_disagree_with_the_file_are_refused() {
    let dir = scratch("mismatch");
    let file = dir.join("data.raw");
    std::fs::write(&file, vec![1u8; 512]).unwrap();
    let f = file.to_str().unwrap();
    let o = tessera(&["render", f, "--dims", "8,8,4", "--dtype", "uint8"]);
    assert_fails_with(&o, &["data.raw", "extra bytes"]);
    let o = tessera(&["render", f, "--dims", "8,8,8", "--dtype", "uint16"]);
    assert_fails_with(&o, &["data.raw", "truncated"]);
}

#[test]
fn unknown_dtype_and_zero_dims_are_refused() {
    let dir = scratch("dtype");
    let file = dir.join("data.raw");
    std::fs::write(&file, vec![1u8; 512]).unwrap();
    let f = file.to_str().unwrap();
    let o = tessera(&["render", f, "--dims", "8,8,8", "--dtype", "complex64"]);
    assert_fails_with(&o, &["data.raw", "complex64", "uint8"]);
    let o = tessera(&["render", f, "--dims", "0,8,8", "--dtype", "uint8"]);
    assert_fails_with(&o, &["data.raw"]);
}

#[test]
fn nan_samples_are_refused_unless_filled() {
    let dir = scratch("nan");
    let file = dir.join("field_8x8x8_float32.raw");
    let mut values = vec![0.5f32; 512];
    // Voxel (3, 2, 1): x + 8 * (y + 8 * z).
    values[3 + 8 * (2 + 8)] = f32::NAN;
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(&file, bytes).unwrap();
    let f = file.to_str().unwrap();
    let out = dir.join("filled.png");
    let o = tessera(&["render", f, "-o", out.to_str().unwrap()]);
    assert_fails_with(&o, &["field_8x8x8_float32.raw", "(3, 2, 1)"]);
    let o = tessera(&[
        "--validation",
        "render",
        f,
        "--nan-fill",
        "0",
        "--size",
        "32x32",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.exists());
}

#[test]
fn volume_larger_than_device_memory_is_refused_before_loading() {
    let dir = scratch("huge");
    // The name promises 10^15 bytes; the file is tiny, so only the pre-check can stop it.
    let file = dir.join("huge_100000x100000x100000_uint8.raw");
    std::fs::write(&file, [0u8; 16]).unwrap();
    let o = tessera(&["render", file.to_str().unwrap()]);
    assert_fails_with(
        &o,
        &[
            "huge_100000x100000x100000_uint8.raw",
            "does not fit",
            "1000000000000000 bytes",
        ],
    );
}

#[test]
fn missing_file_is_named() {
    let o = tessera(&["render", "/nonexistent/brain.nrrd"]);
    assert_fails_with(&o, &["/nonexistent/brain.nrrd"]);
}

#[test]
fn bad_arguments_are_explained() {
    let o = tessera(&["render", "procedural:nosuch:32"]);
    assert_fails_with(&o, &["nosuch", "sphere"]);
    let o = tessera(&["render", "procedural:sphere:16", "--size", "0x10"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = tessera(&["render", "procedural:sphere:16", "--camera", "1,2"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn info_lists_capabilities() {
    let o = tessera(&["--validation", "info"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    for needle in [
        "mesh/task shaders",
        "ray-tracing pipeline",
        "subgroup size",
        "raymarch",
    ] {
        assert!(text.contains(needle), "{needle} missing: {text}");
    }
}

#[test]
fn demo_writes_gallery() {
    let dir = scratch("demo");
    let o = tessera(&[
        "--validation",
        "demo",
        "--out",
        dir.to_str().unwrap(),
        "--volume-size",
        "32",
        "--image-size",
        "48",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let pngs = std::fs::read_dir(&dir).unwrap().filter(|e| {
        e.as_ref()
            .is_ok_and(|e| e.path().extension().is_some_and(|x| x == "png"))
    });
    // 7 volume images; the tet sphere absorbing and emitting, and the asteroid field, on both
    // paths; 5 parametric scenes.
    assert_eq!(pngs.count(), 18);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(stdout.matches("ms GPU").count(), 18, "{stdout}");
}

#[test]
fn options_a_technique_ignores_are_warned_about() {
    let dir = scratch("ignored");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let render = |args: &[&str]| {
        let mut all = vec!["render", "--size", "16x16", "-o", out];
        all.extend(args);
        let o = tessera(&all);
        assert!(o.status.success(), "{}", stderr(&o));
        stderr(&o)
    };
    let cases: [(&[&str], &str); 3] = [
        (
            &[
                "procedural:sphere:16",
                "--technique",
                "raymarch",
                "--path",
                "graphics",
            ],
            "warning: raymarch ignores --path",
        ),
        (
            &[
                "procedural:sphere:16",
                "--technique",
                "raymarch",
                "--ambiguity",
                "vtk",
            ],
            "warning: raymarch ignores --ambiguity",
        ),
        (
            &["tets:box:2", "--culling", "off"],
            "warning: interval ignores --culling",
        ),
    ];
    for (args, warning) in cases {
        let err = render(args);
        assert!(err.contains(warning), "{err}");
    }
    let err = render(&["procedural:sphere:16"]);
    assert!(!err.contains("ignores"), "{err}");
    // CPU extraction takes no device: one given is refused rather than ignored.
    let o = tessera(&[
        "--device",
        "7",
        "extract",
        "procedural:sphere:16",
        "--method",
        "cpu",
        "-o",
        &out.replace(".png", ".ply"),
    ]);
    assert_fails_with(&o, &["--method cpu runs on the CPU", "--device"]);
    // A volume technique on tets, or the other way round, names what fits.
    let o = tessera(&["render", "procedural:sphere:16", "--technique", "interval"]);
    assert_fails_with(&o, &["interval", "tet", "raymarch or direct"]);
}

#[test]
fn info_reports_the_path_render_takes() {
    let dir = scratch("info-path");
    let info = tessera(&["info"]);
    assert!(info.status.success(), "{}", stderr(&info));
    let text = String::from_utf8_lossy(&info.stdout).into_owned();
    for (data, technique) in [
        ("tets:box:2", "interval"),
        ("procedural:sphere:16", "direct"),
    ] {
        let out = dir.join(format!("{technique}.png"));
        let o = tessera(&[
            "render",
            data,
            "--technique",
            technique,
            "--size",
            "16x16",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let stdout = String::from_utf8_lossy(&o.stdout);
        let path = ["graphics", "compute"]
            .into_iter()
            .find(|p| stdout.contains(&format!("({p} path")))
            .unwrap_or_else(|| panic!("{stdout}"));
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with(&format!("{technique} ")))
            .unwrap_or_else(|| panic!("{text}"));
        assert!(
            line.contains(&format!("{path} path")),
            "{line} vs render's {path}"
        );
    }
}

#[test]
fn write_failures_are_errors() {
    if !std::path::Path::new("/dev/full").exists() {
        return;
    }
    let o = tessera(&[
        "render",
        "procedural:sphere:16",
        "--size",
        "16x16",
        "-o",
        "/dev/full",
    ]);
    assert_fails_with(&o, &["writing /dev/full"]);
    assert!(
        !String::from_utf8_lossy(&o.stdout).contains("->"),
        "success printed"
    );
    let o = tessera(&["extract", "procedural:sphere:16", "-o", "/dev/full"]);
    assert_fails_with(&o, &["writing /dev/full"]);
    let o = tessera(&[
        "bench",
        "minmax-build",
        "--quick",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--json",
        "/dev/full",
    ]);
    assert_fails_with(&o, &["writing a record to /dev/full"]);
}
