//! The dispatch that keeps the GPU loaded between benchmark frames: each one runs what it was
//! planned to run (its stored numbers match the CPU's), it is planned from the frame's time,
//! it stays out of the frames' timed scopes, and a target of 0 leaves it out.

mod common;
use common::{assert_clean, fill_target, open};
use tessera_gpu::keep_busy::{last_state, KeepBusy, KEEP_BUSY_WORKGROUPS};
use tessera_gpu::timing::{time_frames, FramePlan};

#[test]
fn each_dispatch_stores_what_the_cpu_computes_and_follows_the_frame_time() {
    let Some(gpu) = open() else { return };
    let mut keep = KeepBusy::new(&gpu, 2.0).unwrap();
    let bytes = u64::from(KEEP_BUSY_WORKGROUPS) * 4;
    let readback = gpu.create_readback("keep busy sink", bytes).unwrap();
    let mut seeds = Vec::new();
    for _ in 0..4 {
        let planned = keep.next_iterations();
        // A frame far shorter than the target: there is always something to fill.
        assert!(planned > 0);
        gpu.submit("frame and dispatch", |rec| {
            keep.record(rec);
            let (_, sink) = keep.last_dispatch().unwrap();
            rec.barrier();
            readback.record_copy(rec, sink, 0, bytes);
        })
        .unwrap();
        let (params, _) = keep.last_dispatch().unwrap();
        assert_eq!(params.iterations, planned);
        seeds.push(params.seed);
        // Every dispatch draws a new seed, so a dispatch that did not run leaves the last
        // one's numbers, which differ.
        let stored: Vec<u32> = bytemuck::pod_collect_to_vec(readback.bytes());
        let expected: Vec<u32> = (0..KEEP_BUSY_WORKGROUPS)
            .map(|g| last_state(params, g))
            .collect();
        assert_eq!(
            stored, expected,
            "seed {} iterations {planned}",
            params.seed
        );
        keep.frame_done(&gpu, 0.1).unwrap();
    }
    seeds.dedup();
    assert_eq!(seeds.len(), 4);
    // A frame that fills the target alone gets no dispatch.
    keep.frame_done(&gpu, 2.5).unwrap();
    assert_eq!(keep.next_iterations(), 0);
    let before = keep.last_dispatch().unwrap().0.seed;
    gpu.submit("frame alone", |rec| keep.record(rec)).unwrap();
    assert_eq!(keep.last_dispatch().unwrap().0.seed, before);
    assert_clean(&gpu);
}

#[test]
fn timed_frames_report_their_own_scopes_only() {
    let Some(gpu) = open() else { return };
    let plan = FramePlan {
        warmup: 2,
        frames: 3,
        max_warmup: 0,
        min_warmup_ms: 0,
        keep_busy_ms: 2.0,
        frames_per_cycle: 1,
    };
    let work = fill_target(&gpu);
    let stages = time_frames(&gpu, plan, 2, |rec, timer| {
        rec.barrier();
        timer.scope(rec, "fill", |rec| rec.fill_buffer(&work, 7));
        rec.barrier();
        timer.scope(rec, "fill again", |rec| rec.fill_buffer(&work, 9));
    })
    .unwrap();
    let names: Vec<&str> = stages.iter().map(|s| s.stage.as_str()).collect();
    assert_eq!(names, ["fill", "fill again"]);
    assert!(stages
        .iter()
        .all(|s| s.median_ms.is_finite() && s.median_ms >= 0.0));
    assert_clean(&gpu);
}

#[test]
fn a_target_of_zero_records_nothing() {
    let Some(gpu) = open() else { return };
    let mut keep = KeepBusy::new(&gpu, 0.0).unwrap();
    gpu.submit("frame alone", |rec| keep.record(rec)).unwrap();
    keep.frame_done(&gpu, 0.1).unwrap();
    assert!(keep.last_dispatch().is_none());
}
