//! `tessera render --technique pmb`: Parallel Marching Blocks meshes drawn end to end on each
//! path the device has, with a chosen block size; a bad block size is refused.

mod common;

use common::*;

/// Renders the sphere with `extra` flags into `out`; the output on success.
fn render(out: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "--validation",
        "render",
        "procedural:sphere:32",
        "--size",
        "80x60",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    tessera(&args)
}

#[test]
fn pmb_renders_the_sphere_as_direct_does_on_each_path() {
    let dir = scratch("pmb");
    let reference = dir.join("direct.png");
    let o = render(&reference, &["--technique", "direct", "--path", "compute"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let expected = png_pixels(&reference);
    let background = expected[0];
    for (path, block) in [
        ("auto", "8x8x4"),
        ("compute", "4x4x4"),
        ("graphics", "8x8x8"),
    ] {
        let out = dir.join(format!("pmb-{path}-{block}.png"));
        let o = render(
            &out,
            &["--technique", "pmb", "--path", path, "--pmb-block", block],
        );
        let err = stderr(&o);
        if !o.status.success() && err.contains("path needs features") {
            eprintln!("SKIPPED pmb {path} path: {err}");
            continue;
        }
        assert!(o.status.success(), "{path}: {err}");
        assert!(!err.contains("ignores"), "{path}: {err}");
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(stdout.contains(&format!("{block} blocks")), "{stdout}");
        if path != "auto" {
            assert!(stdout.contains(&format!("{path} path")), "{stdout}");
        }
        assert_eq!(png_size(&out), (80, 60));
        let pixels = png_pixels(&out);
        let covered = pixels.iter().filter(|&&p| p != background).count();
        assert!(covered > 80 * 60 / 10, "{path}: {covered} pixels drawn");
        // The same surface as direct's, up to rounding at silhouettes and in the shading.
        let off = pixels
            .iter()
            .zip(&expected)
            .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 2))
            .count();
        assert!(
            off * 100 < pixels.len(),
            "{path}: {off} pixels differ from direct"
        );
    }
}

#[test]
fn a_bad_pmb_block_size_is_refused_and_other_techniques_ignore_it() {
    let dir = scratch("pmb-flags");
    let out = dir.join("x.png");
    let o = render(&out, &["--technique", "pmb", "--pmb-block", "3x3x3"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("8x8x4"), "{}", stderr(&o));
    let o = render(&out, &["--technique", "raymarch", "--pmb-block", "4x4x4"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: raymarch ignores --pmb-block"),
        "{}",
        stderr(&o)
    );
}
