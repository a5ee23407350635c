//! Pipeline-throughput scenario: how much slower the graphics stages of a device are than its
//! compute units on the same work (DESIGN §3 measured 32.7× for fragment shading and 7.9× for
//! small-triangle rasterization on an H200 through OpenGL; this repeats it through Vulkan).
//!
//! Two measurements, each timed on the GPU per path:
//! - [`arithmetic`]: the same per-pixel function (`busy_work` in `common/throughput.glsl`) in a
//!   fragment shader over a full-screen triangle versus a compute shader over the same pixels.
//! - [`triangles`]: a grid of small triangles from a mesh-shader pipeline versus a compute
//!   "splat" that writes the pixels each triangle covers.
//!
//! Both paths of a measurement write bit-comparable results (tests hold them to each other), so
//! the times compare equal work.

pub mod arithmetic;
pub mod bandwidth;
pub mod triangles;

use crate::bench::{BenchRecord, FramePlan};
use crate::error::{Error, Result};
use tessera_gpu::{vk, Gpu, Image, MemoryLocation, Recorder, ShaderCompiler};

/// The `scenario` field of every record.
pub const SCENARIO: &str = "pipeline-throughput";

/// Format of the colour targets: four bytes per pixel, storable from compute on every device.
pub const TARGET_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// What to measure and how often.
#[derive(Debug, Clone, Copy)]
pub struct ThroughputOptions {
    pub width: u32,
    pub height: u32,
    /// Loop count of `busy_work` per pixel.
    pub iterations: u32,
    /// Small triangles per frame.
    pub triangles: u32,
    pub plan: FramePlan,
}

impl Default for ThroughputOptions {
    fn default() -> Self {
        ThroughputOptions {
            width: 3840,
            height: 2160,
            iterations: 64,
            triangles: 4_000_000,
            plan: FramePlan::default(),
        }
    }
}

impl ThroughputOptions {
    fn validate(&self) -> Result<()> {
        let cell = triangles::CELL_PX;
        if self.width < cell || self.height < cell {
            return Err(Error::Invalid(format!(
                "target {}x{} is smaller than one {cell}-pixel triangle cell",
                self.width, self.height
            )));
        }
        // busy_work keeps its output off 0 and 255 only from the first iteration on, and the
        // tests rely on that; zero iterations would also measure nothing.
        if self.iterations == 0 || self.triangles == 0 || self.plan.frames == 0 {
            return Err(Error::Invalid(
                "iterations, triangles and frames must be at least 1".into(),
            ));
        }
        Ok(())
    }
}

/// Runs both measurements and returns one record per path: arithmetic on "fragment" and
/// "compute", triangles on "mesh" (only where the device has `VK_EXT_mesh_shader`; see
/// [`notes`]) and "compute". Graphics records carry `slowdown_vs_compute` in their counts.
pub fn run(
    gpu: &Gpu,
    compiler: &ShaderCompiler,
    opts: &ThroughputOptions,
) -> Result<Vec<BenchRecord>> {
    opts.validate()?;
    for note in notes(gpu) {
        log::warn!("{SCENARIO}: {note}");
    }
    let mut records = arithmetic::measure(gpu, compiler, opts)?;
    records.extend(triangles::measure(gpu, compiler, opts)?);
    let ratios = summarize(&records);
    for record in records.iter_mut().filter(|r| r.path != "compute") {
        let key = format!("{} {}/compute", record.technique, record.path);
        if let Some((_, ratio)) = ratios.iter().find(|(k, _)| *k == key) {
            record.counts.insert("slowdown_vs_compute".into(), *ratio);
        }
    }
    Ok(records)
}

/// Paths [`run`] leaves out on this device and why, for the caller to show.
pub fn notes(gpu: &Gpu) -> Vec<String> {
    let caps = gpu.caps();
    if caps.mesh_shader {
        vec![]
    } else {
        vec![format!(
            "'triangles' on the mesh path skipped: {} has no VK_EXT_mesh_shader",
            caps.device_name
        )]
    }
}

/// Median time of each graphics path over its compute twin, keyed
/// "TECHNIQUE GRAPHICS_PATH/compute" (e.g. "arithmetic fragment/compute"). Above 1 means the
/// graphics pipeline is slower. Pairs with a missing or non-positive time are left out.
pub fn summarize(records: &[BenchRecord]) -> Vec<(String, f64)> {
    let median = |r: &BenchRecord| r.stages.first().map(|s| s.median_ms);
    let mut out = Vec::new();
    for graphics in records.iter().filter(|r| r.path != "compute") {
        let compute = records
            .iter()
            .find(|r| r.path == "compute" && r.technique == graphics.technique);
        if let (Some(g), Some(c)) = (median(graphics), compute.and_then(median)) {
            if g > 0.0 && c > 0.0 {
                let key = format!("{} {}/compute", graphics.technique, graphics.path);
                out.push((key, g / c));
            }
        }
    }
    out
}

/// Defines every throughput shader is compiled with: the grid constants of `triangles.rs`,
/// handed over so that no value is copied by hand into GLSL.
pub fn shader_defines() -> Vec<(String, String)> {
    vec![
        ("GRID_CELL_PX".into(), format!("{}u", triangles::CELL_PX)),
        ("GRID_LEG_PX".into(), format!("{:?}", triangles::LEG_PX)),
        (
            "MESH_TRIANGLES".into(),
            format!("{}u", triangles::MESH_TRIANGLES),
        ),
    ]
}

/// An RGBA8 image usable as colour attachment, storage image and copy source.
pub fn create_target(gpu: &Gpu, name: &str, width: u32, height: u32) -> Result<Image> {
    Ok(gpu.create_image(
        name,
        [width, height, 1],
        TARGET_FORMAT,
        vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC,
        false,
    )?)
}

/// Fills a target (already in `GENERAL` layout) with `color` through an empty render pass:
/// the attachment usage the target has anyway suffices, no transfer-destination usage needed.
pub fn clear_target(rec: &Recorder, target: &Image, color: [f32; 4]) {
    rec.begin_rendering(target, color);
    rec.end_rendering();
}

/// Reads a target (in `GENERAL` layout) back as one packed RGBA8 `u32` per pixel, row-major,
/// red in the low byte.
pub fn read_target(gpu: &Gpu, target: &Image) -> Result<Vec<u32>> {
    assert_eq!(target.format, TARGET_FORMAT, "read_target reads RGBA8");
    let bytes = u64::from(target.extent.width) * u64::from(target.extent.height) * 4;
    let buffer = gpu.create_buffer(
        &format!("{} (copy)", target.name),
        bytes,
        vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::GpuOnly,
    )?;
    let result = gpu
        .submit(&format!("copy {}", target.name), |rec| {
            // Orders the copy after whatever wrote the target in earlier submissions.
            rec.barrier();
            rec.copy_image_to_buffer(target, &buffer);
        })
        .and_then(|_| gpu.read_buffer_as(&buffer));
    Ok(result?)
}

/// Workgroup counts for `groups` groups laid out in 2-D, so that counts past the per-axis limit
/// (65 535 is the guaranteed minimum for compute and mesh) still fit. Shaders linearize the id
/// as `x + y * gl_NumWorkGroups.x` and skip ids past the end.
pub(crate) fn spread_groups(groups: u32) -> [u32; 3] {
    const MAX_X: u32 = 65_535;
    let x = groups.clamp(1, MAX_X);
    [x, groups.div_ceil(x).max(1), 1]
}

/// A record of this scenario with the frame plan and size filled in.
pub(crate) fn record(
    gpu: &Gpu,
    opts: &ThroughputOptions,
    technique: &str,
    path: &str,
    dataset: String,
) -> BenchRecord {
    let mut r = BenchRecord::new(gpu, SCENARIO, technique, path, &dataset);
    r.width = opts.width;
    r.height = opts.height;
    r.warmup = opts.plan.warmup;
    r.frames = opts.plan.frames;
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_groups_covers_every_group_within_limits() {
        for groups in [1u32, 64, 65_535, 65_536, 1_000_003, 4_000_000 / 64 + 1] {
            let [x, y, z] = spread_groups(groups);
            assert!(x <= 65_535 && y <= 65_535 && z == 1);
            assert!(u64::from(x) * u64::from(y) >= u64::from(groups));
            assert!(u64::from(x) * (u64::from(y) - 1) < u64::from(groups));
        }
    }

    #[test]
    fn defaults_are_valid_and_degenerate_options_are_refused() {
        assert!(ThroughputOptions::default().validate().is_ok());
        let tiny = ThroughputOptions {
            width: 2,
            ..Default::default()
        };
        assert!(tiny.validate().is_err());
        let idle = ThroughputOptions {
            iterations: 0,
            ..Default::default()
        };
        assert!(idle.validate().is_err());
    }
}
