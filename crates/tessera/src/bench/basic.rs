//! The scenarios that need no technique of their own: graphics against compute throughput,
//! ray marching, the octree build; and what the volume scenarios share (their volumes, image
//! sizes).

use super::frames::{settle_after_upload, time_mono};
use super::{time_frames, BenchConfig, BenchRecord, FramePlan, RecordSink};
use crate::error::Result;
use crate::iso::minmax::{upload_samples, LevelZeroPass, MinMaxBuilder};
use crate::iso::raymarch::Raymarch;
use crate::renderer::{self, RendererOptions, Technique};
use tessera_data::minmax::MinMaxOctree;
use tessera_data::scene::{expected_volume_bytes, load_volume_spec, Appearance, DataKind, Dataset};
use tessera_data::{IsoValue, OrbitCamera, ScalarType, Volume};
use tessera_gpu::{vk, Gpu, MemoryLocation};

pub(super) fn throughput(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let compiler = crate::shaders::compiler();
    let mut opts = crate::throughput::ThroughputOptions {
        plan,
        ..Default::default()
    };
    if config.quick {
        opts.width = 256;
        opts.height = 144;
        opts.triangles = 20_000;
        opts.iterations = 16;
    }
    for note in crate::throughput::notes(gpu) {
        sink.note(&note);
    }
    let records = crate::throughput::run(gpu, &compiler, &opts)?;
    for r in &records {
        sink.emit(r)?;
    }
    for (what, ratio) in crate::throughput::summarize(&records) {
        sink.note(&format!(
            "{what}: graphics path {ratio:.2}x the compute time"
        ));
    }
    Ok(())
}

/// The volumes of the isosurface scenarios: `--data`, or head-like phantoms of DESIGN §6's sizes.
pub(super) fn bench_volumes(config: &BenchConfig) -> Vec<String> {
    if let Some(data) = config
        .data
        .as_ref()
        .filter(|d| DataKind::of_spec(d) == DataKind::Volume)
    {
        return vec![data.clone()];
    }
    let sizes: &[(u32, ScalarType)] = if config.quick {
        &[(64, ScalarType::U8), (96, ScalarType::U16)]
    } else {
        &[
            (256, ScalarType::U8),
            (512, ScalarType::U8),
            (1024, ScalarType::U16),
        ]
    };
    sizes
        .iter()
        .map(|(size, scalar)| format!("procedural:head:{size}:{}", scalar.name()))
        .collect()
}

pub(super) fn bench_sizes(config: &BenchConfig) -> Vec<(u32, u32)> {
    if !config.sizes.is_empty() {
        return config.sizes.clone();
    }
    if config.quick {
        vec![(256, 144)]
    } else {
        vec![(1280, 720), (1920, 1080), (3840, 2160)]
    }
}

pub(super) fn make_volume(gpu: &Gpu, spec: &str, config: &BenchConfig) -> Result<Volume> {
    if let Some(bytes) = expected_volume_bytes(spec, &config.raw) {
        gpu.check_fits(spec, bytes)?;
    }
    Ok(load_volume_spec(spec, &config.raw)?)
}

pub(super) fn raymarch(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let camera = OrbitCamera::default();
    let look = Appearance {
        iso: IsoValue::Normalized(config.iso_fraction),
        ..Appearance::default()
    };
    for spec in bench_volumes(config) {
        let volume = make_volume(gpu, &spec, config)?;
        let iso = volume.iso_to_texel(look.iso);
        let occupied = MinMaxOctree::build(&volume).occupied_fraction(iso);
        let name = volume.name().to_string();
        let data = Dataset::Volume(volume);
        let mut rm = renderer::create(gpu, Technique::Raymarch, &RendererOptions::default())?;
        rm.set_appearance(gpu, &look)?;
        rm.set_data(gpu, &data)?;
        drop(data);
        settle_after_upload(gpu, rm.as_mut(), config.quick)?;
        for (w, h) in bench_sizes(config) {
            let view = rm.view(&camera, (w, h))?;
            let stages = time_mono(gpu, rm.as_mut(), &view, plan, 1, None)?;
            let mut r = BenchRecord::new(gpu, "raymarch", "raymarch", "compute", &name);
            (r.width, r.height, r.warmup, r.frames, r.stages) =
                (w, h, plan.warmup, plan.frames, stages);
            r.counts.insert("iso".into(), iso as f64);
            r.counts.insert("occupied_block_fraction".into(), occupied);
            if let Some(ms) = r.median_ms("raymarch") {
                r.counts
                    .insert("mrays_per_s".into(), (w * h) as f64 / ms / 1e3);
            }
            sink.emit(&r)?;
        }
    }
    Ok(())
}

/// Keeps the first failure of the recordings of a frame.
fn keep_first_error(first: &mut Result<()>, next: Result<()>) {
    if first.is_ok() {
        *first = next;
    }
}

/// The octree build reads the volume once (a workgroup per block, and per 2×2×2 blocks); a
/// buffer copy of the same bytes (`vkCmdCopyBuffer`, and a compute shader's) shows what the
/// memory system allows.
pub(super) fn minmax_build(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let compiler = crate::shaders::compiler();
    let copy = crate::throughput::bandwidth::ComputeCopy::new(gpu, &compiler)?;
    for spec in bench_volumes(config) {
        let volume = make_volume(gpu, &spec, config)?;
        let scalar = volume.scalar_type();
        let name = volume.name().to_string();
        let bytes = volume.size_bytes();
        let rm = Raymarch::new(gpu, &compiler, scalar)?;
        let prepared = rm.prepare(gpu, &volume)?;
        let usage = vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::STORAGE_BUFFER;
        // The octree's row pass reads the same buffer.
        let src = upload_samples(gpu, &volume, usage)?;
        let dims = volume.dims();
        let dst = gpu.create_buffer("copy destination", bytes, usage, MemoryLocation::GpuOnly)?;
        drop(volume);
        // The compute copy moves whole 16-byte words: the volume's bytes rounded down.
        let compute_bytes = bytes / 16 * 16;
        let mut recorded = Ok(());
        let grouped = MinMaxBuilder::with_pass(gpu, &compiler, scalar, LevelZeroPass::Grouped)?;
        let stages = time_frames(gpu, plan, 6, |rec, timer| {
            timer.scope(rec, "octree-build", |rec| rm.record_build(rec, &prepared));
            rec.barrier();
            timer.scope(rec, "octree-build-grouped", |rec| {
                grouped.record(rec, &prepared.volume, &prepared.octree)
            });
            rec.barrier();
            let from_samples = timer.scope(rec, "octree-build-rows", |rec| {
                rm.builder()
                    .record_from_samples(rec, &src, dims, &prepared.octree)
            });
            keep_first_error(&mut recorded, from_samples);
            rec.barrier();
            let level_zero = timer.scope(rec, "octree-rows-level0", |rec| {
                rm.builder()
                    .record_level_zero_from_samples(rec, &src, dims, &prepared.octree)
            });
            keep_first_error(&mut recorded, level_zero);
            rec.barrier();
            timer.scope(rec, "copy", |rec| rec.copy_buffer(&src, &dst, bytes));
            rec.barrier();
            let copied = timer.scope(rec, "compute-copy", |rec| {
                copy.record(rec, &src, &dst, compute_bytes)
            });
            keep_first_error(&mut recorded, copied);
        })?;
        recorded?;
        let mut r = BenchRecord::new(gpu, "minmax-build", "minmax-octree", "compute", &name);
        (r.warmup, r.frames, r.stages) = (plan.warmup, plan.frames, stages);
        r.counts.insert("volume_bytes".into(), bytes as f64);
        r.counts
            .insert("octree_nodes".into(), prepared.octree.node_count() as f64);
        if let (Some(build), Some(copy)) = (r.median_ms("octree-build"), r.median_ms("copy")) {
            r.counts
                .insert("build_read_gb_per_s".into(), bytes as f64 / build / 1e6);
            r.counts.insert(
                "copy_read_write_gb_per_s".into(),
                2.0 * bytes as f64 / copy / 1e6,
            );
            r.counts.insert("build_over_copy".into(), build / copy);
        }
        if let (Some(rows), Some(copy)) = (
            r.median_ms("octree-build-rows"),
            r.median_ms("compute-copy"),
        ) {
            r.counts
                .insert("rows_build_read_gb_per_s".into(), bytes as f64 / rows / 1e6);
            r.counts
                .insert("rows_build_rate_of_compute_copy".into(), copy / rows);
        }
        if let Some(grouped) = r.median_ms("octree-build-grouped") {
            r.counts.insert(
                "grouped_build_read_gb_per_s".into(),
                bytes as f64 / grouped / 1e6,
            );
        }
        if let (Some(build), Some(copy)) =
            (r.median_ms("octree-build"), r.median_ms("compute-copy"))
        {
            r.counts.insert(
                "compute_copy_read_write_gb_per_s".into(),
                2.0 * compute_bytes as f64 / copy / 1e6,
            );
            // The build's read rate as a fraction of the rate the compute copy moves the same
            // bytes at.
            r.counts
                .insert("build_rate_of_compute_copy".into(), copy / build);
        }
        sink.emit(&r)?;
    }
    Ok(())
}
