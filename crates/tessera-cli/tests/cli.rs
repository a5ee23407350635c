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
fn extract_writes_ply() {
    let dir = scratch("extract");
    let out = dir.join("s.ply");
    let o = tessera(&[
        "extract",
        "procedural:sphere:24",
        "--iso-fraction",
        "0.6",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&out).unwrap();
    let header = String::from_utf8_lossy(&bytes[..400.min(bytes.len())]).into_owned();
    assert!(header.starts_with("ply"), "{header}");
    let faces: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element face "))
        .and_then(|n| n.trim().parse().ok())
        .unwrap();
    assert!(faces > 100, "{faces} faces");
    // The sphere is high inside; its surface must face out, toward lower values, as VTK's
    // does: outward normals and a positive enclosed volume (divergence theorem).
    let vertices: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .and_then(|n| n.trim().parse().ok())
        .unwrap();
    let body = header.find("end_header\n").unwrap() + "end_header\n".len();
    let float = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    let vertex = |i: usize| -> [[f32; 3]; 2] {
        let at = body + 24 * i;
        [
            [0, 1, 2].map(|k| float(at + 4 * k)),
            [3, 4, 5].map(|k| float(at + 4 * k)),
        ]
    };
    let centre = (0..vertices).fold([0.0f32; 3], |c, i| {
        let p = vertex(i)[0];
        [0, 1, 2].map(|k| c[k] + p[k] / vertices as f32)
    });
    let outward = (0..vertices)
        .filter(|&i| {
            let [p, n] = vertex(i);
            (0..3).map(|k| (p[k] - centre[k]) * n[k]).sum::<f32>() > 0.0
        })
        .count();
    assert_eq!(outward, vertices, "normals point out of the sphere");
    let faces_at = body + 24 * vertices;
    let volume: f64 = (0..faces)
        .map(|f| {
            let at = faces_at + 13 * f;
            assert_eq!(bytes[at], 3);
            let [a, b, c] = [0, 1, 2].map(|k| {
                let i =
                    u32::from_le_bytes(bytes[at + 1 + 4 * k..at + 5 + 4 * k].try_into().unwrap());
                vertex(i as usize)[0].map(f64::from)
            });
            let cross = [
                b[1] * c[2] - b[2] * c[1],
                b[2] * c[0] - b[0] * c[2],
                b[0] * c[1] - b[1] * c[0],
            ];
            (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
        })
        .sum();
    assert!(volume > 0.0, "enclosed volume {volume}");
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

/// Writes a 16³ uint8 NRRD: 200 inside a ball of radius 4 around `centre` (grid units), 10
/// elsewhere, with extra header `fields`.
fn ball_nrrd(path: &std::path::Path, centre: [f32; 3], fields: &str) {
    let mut bytes =
        format!("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 16 16 16\nencoding: raw\n{fields}\n")
            .into_bytes();
    for z in 0..16 {
        for y in 0..16 {
            for x in 0..16 {
                let d = [x, y, z]
                    .iter()
                    .zip(centre)
                    .map(|(&i, c)| (i as f32 - c).powi(2))
                    .sum::<f32>()
                    .sqrt();
                bytes.push(if d < 4.0 { 200 } else { 10 });
            }
        }
    }
    std::fs::write(path, bytes).unwrap();
}

/// Bounds (min, max) of the vertices of a binary PLY the CLI wrote.
fn ply_bounds(path: &std::path::Path) -> ([f32; 3], [f32; 3]) {
    let bytes = std::fs::read(path).unwrap();
    let end = b"end_header\n";
    let body = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
    let header = String::from_utf8_lossy(&bytes[..body]).into_owned();
    let vertices: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .and_then(|n| n.trim().parse().ok())
        .unwrap();
    assert!(vertices > 0, "{header}");
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for v in 0..vertices {
        for a in 0..3 {
            let at = body + v * 24 + a * 4;
            let x = f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
            lo[a] = lo[a].min(x);
            hi[a] = hi[a].max(x);
        }
    }
    (lo, hi)
}

/// The area `extract` printed.
fn printed_area(o: &std::process::Output) -> f32 {
    let text = String::from_utf8_lossy(&o.stdout);
    text.split("area ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no area in {text}"))
}

#[test]
fn extract_takes_spacing_from_the_header_and_the_flag_overrides_it() {
    let dir = scratch("spacing");
    let data = dir.join("aniso.nrrd");
    ball_nrrd(&data, [7.5, 7.5, 7.5], "spacings: 1 2 0.5\n");
    let run_on = |data: &std::path::Path, name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "extract",
            data.to_str().unwrap(),
            "--iso",
            "100",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = tessera(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        (o, ply_bounds(&out))
    };
    let run = |name: &str, extra: &[&str]| run_on(&data, name, extra);
    let (header, (hlo, hhi)) = run("header.ply", &[]);
    let (unit, (ulo, uhi)) = run("unit.ply", &["--spacing", "1,1,1"]);
    let (double, (dlo, dhi)) = run("double.ply", &["--spacing", "2,2,2"]);
    assert!(!stderr(&header).contains("note:"), "{}", stderr(&header));
    for o in [&unit, &double] {
        let err = stderr(o);
        assert!(
            err.contains("note: --spacing") && err.contains("replaces the spacing 1,2,0.5"),
            "{err}"
        );
    }
    let spacing = [1.0, 2.0, 0.5];
    for a in 0..3 {
        let (h, u, d) = (hhi[a] - hlo[a], uhi[a] - ulo[a], dhi[a] - dlo[a]);
        assert!(u > 5.0, "axis {a}: unit extent {u}");
        assert!((h - u * spacing[a]).abs() < 1e-3, "axis {a}: {h} vs {u}");
        assert!((d - 2.0 * u).abs() < 1e-3, "axis {a}: {d} vs {u}");
    }
    // Placed by space directions and an origin: vertices at origin + spacing × index.
    let placed = dir.join("placed.nrrd");
    ball_nrrd(
        &placed,
        [7.5, 7.5, 7.5],
        "space dimension: 3\nspace directions: (1,0,0) (0,2,0) (0,0,0.5)\nspace origin: (100,0,-20)\n",
    );
    let (_, (plo, phi)) = run_on(&placed, "placed.ply", &[]);
    let origin = [100.0, 0.0, -20.0];
    for a in 0..3 {
        let expect_lo = origin[a] + (ulo[a] - 0.0) * spacing[a];
        assert!(
            (plo[a] - expect_lo).abs() < 1e-3,
            "axis {a}: {plo:?} vs unit {ulo:?}"
        );
        assert!(
            (phi[a] - plo[a] - (hhi[a] - hlo[a])).abs() < 1e-3,
            "axis {a}"
        );
    }
    // `render` keeps the header's spacing too, and says when the flag replaces it.
    let png = dir.join("aniso.png");
    let png = png.to_str().unwrap();
    let data_arg = data.to_str().unwrap();
    let o = tessera(&["render", data_arg, "--size", "16x16", "-o", png]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("spacing 1,2,0.5)"), "{}", stderr(&o));
    let o = tessera(&[
        "render",
        data_arg,
        "--spacing",
        "1,1,1",
        "--size",
        "16x16",
        "-o",
        png,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("note: --spacing 1,1,1 replaces the spacing 1,2,0.5"),
        "{}",
        stderr(&o)
    );
    let (ha, ua, da) = (
        printed_area(&header),
        printed_area(&unit),
        printed_area(&double),
    );
    assert!((da / ua - 4.0).abs() < 0.01, "areas {da} {ua}");
    // Stretched by 2 along y and squashed by 2 along z: neither unit nor double.
    assert!(
        (ha / ua - 1.0).abs() > 0.05 && ha < da,
        "areas {ha} {ua} {da}"
    );
}

#[test]
fn negative_values_parse_and_isovalues_outside_the_data_warn() {
    let dir = scratch("negative");
    let out = dir.join("s.ply");
    for flags in [
        &["--iso", "-300"][..],
        &["--iso-fraction", "-0.5"],
        &["--iso-fraction", "1.5", "--nan-fill", "-1"],
    ] {
        let mut args = vec![
            "extract",
            "procedural:sphere:16",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(flags);
        let o = tessera(&args);
        assert!(o.status.success(), "{flags:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(
            err.contains("warning: isovalue") && err.contains("outside the values"),
            "{flags:?}: {err}"
        );
        assert!(err.contains("(0..238)"), "{err}");
    }
    let o = tessera(&[
        "extract",
        "procedural:sphere:16",
        "--iso",
        "100",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
}

#[test]
fn default_isovalue_is_otsus_threshold() {
    let dir = scratch("otsu");
    let data = dir.join("ball.nrrd");
    ball_nrrd(&data, [7.5, 7.5, 7.5], "");
    let out = dir.join("ball.ply");
    let o = tessera(&[
        "extract",
        data.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    // Two values, 10 and 200: the threshold lies between them.
    let iso: f32 = err
        .split("isovalue ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{err}"));
    assert!(err.contains("(Otsu threshold of the histogram)"), "{err}");
    assert!(iso > 10.0 && iso < 200.0, "{iso}");
}

/// Mean row of the pixels that differ from the top-left one, as a fraction of the height.
fn drawn_centre_row(path: &std::path::Path) -> f32 {
    let (w, _) = png_size(path);
    let pixels = png_pixels(path);
    let background = pixels[0];
    let rows: Vec<f32> = pixels
        .iter()
        .enumerate()
        .filter(|(_, p)| **p != background)
        .map(|(i, _)| (i / w as usize) as f32)
        .collect();
    assert!(rows.len() > 20, "{} pixels drawn", rows.len());
    rows.iter().sum::<f32>() / rows.len() as f32 / (pixels.len() / w as usize) as f32
}

#[test]
fn view_up_turns_the_named_axis_up() {
    let dir = scratch("up");
    // A ball near the top (high z) of the grid.
    let plain = dir.join("top.nrrd");
    ball_nrrd(&plain, [7.5, 7.5, 11.0], "");
    let lps = dir.join("top-lps.nrrd");
    ball_nrrd(
        &lps,
        [7.5, 7.5, 11.0],
        "space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\n",
    );
    let render = |data: &std::path::Path, up: Option<&str>| {
        let out = dir.join(format!(
            "{}-{}.png",
            data.file_stem().unwrap().to_string_lossy(),
            up.unwrap_or("default")
        ));
        let mut args = vec![
            "render",
            data.to_str().unwrap(),
            "--iso",
            "100",
            "--camera",
            "0,0,1.8",
            "--size",
            "64x64",
            "-o",
            out.to_str().unwrap(),
        ];
        if let Some(up) = up {
            args.extend(["--up", up]);
        }
        let o = tessera(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        (drawn_centre_row(&out), stderr(&o))
    };
    let (up_z, _) = render(&plain, Some("z"));
    let (down_z, _) = render(&plain, Some("-z"));
    let (default, _) = render(&plain, None);
    assert!(up_z < 0.4, "--up z: ball at {up_z} of the height");
    assert!(down_z > 0.6, "--up -z: ball at {down_z} of the height");
    assert!((default - 0.5).abs() < 0.1, "default: ball at {default}");
    // A medical file's orientation puts the head (superior, +z) up without the flag.
    let (medical, err) = render(&lps, None);
    assert!(medical < 0.4, "LPS file: ball at {medical}");
    assert!(err.contains("view up z"), "{err}");
    let o = tessera(&["render", "procedural:sphere:16", "--up", "w"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
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
    // Extraction runs on the CPU: a device is refused rather than ignored.
    let o = tessera(&[
        "--device",
        "7",
        "extract",
        "procedural:sphere:16",
        "-o",
        out,
    ]);
    assert_fails_with(&o, &["extract runs on the CPU", "--device"]);
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

/// `--ambiguity` picks how a face with diagonal above-iso corners is cut: on one cell with 1
/// at corners (0,0,0) and (1,1,0), VTK 9.7.2's vtkMarchingCubes gives area 1.1085 at iso 0.2
/// (the corners kept apart), the asymptotic decider joins them (saddle value 0.5 ≥ 0.2):
/// 1.6628. Bad names are refused.
#[test]
fn extract_cuts_ambiguous_faces_by_the_rule_asked_for() {
    let dir = scratch("ambiguity");
    let data = dir.join("diagonal_2x2x2_float32.raw");
    let mut values = [0f32; 8];
    values[0] = 1.0;
    values[3] = 1.0;
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(&data, bytes).unwrap();
    let area = |rule: &str| -> f64 {
        let out = dir.join(format!("{rule}.ply"));
        let o = tessera(&[
            "extract",
            data.to_str().unwrap(),
            "--iso",
            "0.2",
            "--ambiguity",
            rule,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        text.split("area ")
            .nth(1)
            .and_then(|rest| rest.split_whitespace().next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no area in: {text}"))
    };
    let (vtk, decider) = (area("vtk"), area("decider"));
    assert!((vtk - 1.1085).abs() < 0.06, "vtk rule: area {vtk}");
    assert!((decider - 1.6628).abs() < 0.06, "decider: area {decider}");
    let o = tessera(&["extract", data.to_str().unwrap(), "--ambiguity", "maybe"]);
    let err = stderr(&o);
    assert!(!o.status.success(), "{err}");
    assert!(
        ["maybe", "decider", "vtk"].iter().all(|w| err.contains(w)),
        "{err}"
    );
}
