//! The pipeline-throughput scenario on lavapipe or a GPU: the graphics and compute path of each
//! measurement must produce the same pixels (so their times compare equal work), and `run` must
//! time every path without validation errors.

mod common;

use common::{assert_clean, gpu};
use tessera::bench::FramePlan;
use tessera::shaders;
use tessera::throughput::arithmetic::Arithmetic;
use tessera::throughput::triangles::{
    create_splat_buffer, read_splat, reference_coverage, Triangles, COVERED,
};
use tessera::throughput::{
    clear_target, create_target, read_target, run, summarize, ThroughputOptions,
};

const W: u32 = 64;
const H: u32 = 48;

/// busy_work never yields the bytes 0 or 255, so both of these mean "never written".
const POISON_FRAGMENT: u32 = 0;
const POISON_COMPUTE: u32 = u32::MAX;

fn max_channel_diff(a: u32, b: u32) -> u8 {
    let (a, b) = (a.to_le_bytes(), b.to_le_bytes());
    (0..4).map(|i| a[i].abs_diff(b[i])).max().unwrap_or(0)
}

#[test]
fn fragment_and_compute_arithmetic_write_the_same_pixels() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let arithmetic = Arithmetic::new(&gpu, &compiler).unwrap();
    let frag_img = create_target(&gpu, "test busy fragment", W, H).unwrap();
    let comp_img = create_target(&gpu, "test busy compute", W, H).unwrap();
    for iterations in [1u32, 7] {
        gpu.submit("busy both paths", |rec| {
            rec.discard_to_general(&frag_img);
            rec.discard_to_general(&comp_img);
            // The fragment path clears to 0 itself; the compute target gets its own poison.
            clear_target(rec, &comp_img, [1.0; 4]);
            rec.barrier();
            arithmetic.record_fragment(rec, &frag_img, iterations);
            arithmetic.record_compute(rec, &comp_img, iterations);
        })
        .unwrap();
        let frag = read_target(&gpu, &frag_img).unwrap();
        let comp = read_target(&gpu, &comp_img).unwrap();
        assert_eq!(frag.len(), (W * H) as usize);
        assert!(!frag.contains(&POISON_FRAGMENT), "unshaded fragment pixels");
        assert!(!comp.contains(&POISON_COMPUTE), "unwritten compute pixels");
        let mut distinct = frag.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert!(
            distinct.len() > (W * H / 8) as usize,
            "only {} distinct values: the output hardly depends on the pixel",
            distinct.len()
        );
        let (mut worst, mut differing) = (0u8, 0usize);
        for (&f, &c) in frag.iter().zip(&comp) {
            let d = max_channel_diff(f, c);
            worst = worst.max(d);
            differing += usize::from(d > 0);
        }
        eprintln!("iterations {iterations}: {differing} pixel(s) differ, max {worst}/255");
        assert!(worst <= 1, "fragment and compute differ by {worst}/255");
        // Rounding may flip a byte now and then, a systematic difference (e.g. another sample
        // point) moves most pixels.
        assert!(
            differing * 100 <= frag.len(),
            "{differing} of {} pixels differ",
            frag.len()
        );
    }
    assert_clean(&gpu);
}

#[test]
fn mesh_and_splat_cover_exactly_the_reference_pixels() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let triangles = Triangles::new(&gpu, &compiler).unwrap();
    let pixels = create_splat_buffer(&gpu, W, H).unwrap();
    let target = create_target(&gpu, "test grid mesh", W, H).unwrap();
    // 21x16 cells hold 672 triangles: a part of one layer (ending on an odd triangle and a
    // partial workgroup), and several wrapped layers.
    for n in [1u32, 301, 4001] {
        let reference = reference_coverage(W, H, n);
        let expected: Vec<u32> = reference
            .iter()
            .map(|&c| if c { COVERED } else { 0 })
            .collect();
        let covered = reference.iter().filter(|&&c| c).count();
        assert!(covered >= 3 && covered < (W * H) as usize);
        // Poison the splat output: a splat that never ran would leave this, not 0.
        gpu.write_buffer(&pixels, &vec![0x5au8; (W * H * 4) as usize])
            .unwrap();
        gpu.submit("splat", |rec| {
            triangles.record_splat(rec, &pixels, [W, H], n)
        })
        .unwrap();
        let splat = read_splat(&gpu, &pixels).unwrap();
        let wrong = splat.iter().zip(&expected).filter(|(a, b)| a != b).count();
        assert_eq!(
            wrong, 0,
            "{n} triangles: splat differs from the reference in {wrong} px"
        );
        if !triangles.has_mesh() {
            eprintln!("SKIPPED mesh half: device has no VK_EXT_mesh_shader");
            continue;
        }
        let mut drawn = Ok(());
        gpu.submit("mesh", |rec| {
            rec.discard_to_general(&target);
            drawn = triangles.record_mesh(rec, &target, n);
        })
        .unwrap();
        drawn.unwrap();
        let mesh = read_target(&gpu, &target).unwrap();
        let wrong = mesh.iter().zip(&expected).filter(|(a, b)| a != b).count();
        assert_eq!(
            wrong, 0,
            "{n} triangles: mesh differs from the reference in {wrong} px"
        );
        assert_eq!(mesh, splat);
    }
    assert_clean(&gpu);
}

#[test]
fn run_times_every_path() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let opts = ThroughputOptions {
        width: W,
        height: H,
        iterations: 4,
        triangles: 3000,
        plan: FramePlan {
            warmup: 1,
            frames: 2,
            max_warmup: 0,
            min_warmup_ms: 0,
            keep_busy_ms: 0.0,
            frames_per_cycle: 1,
        },
    };
    let records = run(&gpu, &compiler, &opts).unwrap();
    let paths: Vec<_> = records
        .iter()
        .map(|r| format!("{} {}", r.technique, r.path))
        .collect();
    let mut expected = vec!["arithmetic fragment", "arithmetic compute"];
    if gpu.caps().mesh_shader {
        expected.push("triangles mesh");
    }
    expected.push("triangles compute");
    assert_eq!(paths, expected);
    for r in &records {
        assert_eq!(r.scenario, "pipeline-throughput");
        assert_eq!((r.width, r.height, r.frames), (W, H, 2));
        assert_eq!(r.stages.len(), 1, "{} {}", r.technique, r.path);
        let s = &r.stages[0];
        assert!(s.median_ms > 0.0 && s.median_ms.is_finite(), "{s:?}");
        let rate = if r.technique == "arithmetic" {
            "gpix_per_s"
        } else {
            "mtri_per_s"
        };
        assert!(r.counts[rate] > 0.0, "{} {}: {rate}", r.technique, r.path);
    }
    let ratios = summarize(&records);
    assert_eq!(ratios.len(), expected.len() - 2, "{ratios:?}");
    assert!(ratios.iter().all(|(_, r)| *r > 0.0 && r.is_finite()));
    eprintln!("{ratios:?}");
    let bad = ThroughputOptions {
        iterations: 0,
        ..opts
    };
    assert!(run(&gpu, &compiler, &bad).is_err());
    assert_clean(&gpu);
}
