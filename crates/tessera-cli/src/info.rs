//! `tessera info`: what the device can do and which path each technique takes on it.

use anyhow::Result;
use clap::Args;
use tessera::path::PathChoice;
use tessera::renderer::{self, Technique};
use tessera_gpu::GpuOptions;

#[derive(Args)]
pub struct InfoArgs {
    /// Print the capabilities as one JSON object.
    #[arg(long)]
    json: bool,
}

pub fn run(options: &GpuOptions, args: &InfoArgs) -> Result<()> {
    let devices = tessera_gpu::list_devices()?;
    let gpu = crate::gpu::open_gpu(options)?;
    let caps = gpu.caps();
    if args.json {
        println!("{}", serde_json::to_string_pretty(caps)?);
        return Ok(());
    }
    println!("devices:");
    for d in &devices {
        let mark = if d.name == caps.device_name { "*" } else { " " };
        println!(" {mark} [{}] {} ({})", d.index, d.name, d.device_type);
    }
    println!("device      {} ({})", caps.device_name, caps.device_type);
    println!("driver      {} — {}", caps.driver_name, caps.driver_info);
    println!("api         Vulkan {}", caps.api_version);
    println!(
        "memory      {:.1} GiB device-local",
        caps.device_local_bytes as f64 / (1u64 << 30) as f64
    );
    let yes = |b: bool| if b { "yes" } else { "no" };
    let flag = |label: &str, has: bool| println!("  {label:<24} {}", yes(has));
    println!("capabilities:");
    println!(
        "  mesh/task shaders        {} / {} (max {} vertices, {} primitives, payload {} B, preferred {} invocations, multiview {})",
        yes(caps.mesh_shader),
        yes(caps.task_shader),
        caps.mesh_max_output_vertices,
        caps.mesh_max_output_primitives,
        caps.mesh_max_payload_bytes,
        caps.mesh_preferred_invocations,
        yes(caps.mesh_multiview)
    );
    flag("ray-tracing pipeline", caps.ray_tracing_pipeline);
    flag("acceleration structures", caps.acceleration_structure);
    flag("ray query", caps.ray_query);
    println!(
        "  tessellation             {} (max level {})",
        yes(caps.tessellation),
        caps.max_tessellation_level
    );
    println!(
        "  64-bit atomics           buffer {} / image {}",
        yes(caps.buffer_int64_atomics),
        yes(caps.image_int64_atomics)
    );
    println!(
        "  float32 atomic add       buffer {} / image {}",
        yes(caps.buffer_float32_atomic_add),
        yes(caps.image_float32_atomic_add)
    );
    println!(
        "  subgroup size            {} (arithmetic {}, ballot and shuffle {})",
        caps.subgroup_size,
        yes(caps.subgroup_arithmetic),
        yes(caps.subgroup_ballot_and_shuffle)
    );
    flag("representative fragment", caps.representative_fragment_test);
    flag("fragment barycentric", caps.fragment_barycentric);
    flag("fragment interlock", caps.fragment_shader_interlock);
    println!(
        "  max 3-D image            {} per axis",
        caps.max_image_dimension_3d
    );
    println!(
        "  pipeline statistics      {} (--pipeline-stats)",
        yes(caps.pipeline_executable_info)
    );
    println!("techniques (the path `--path auto` takes):");
    let measured = tessera::path::remembered(caps).is_some();
    for technique in Technique::ALL {
        let path = match renderer::path_for(caps, technique, PathChoice::Auto) {
            Ok(path) if technique.reads_options().contains(&"path") => format!(
                "{} path ({})",
                path.name(),
                if measured {
                    "from this device's pipeline-throughput measurement"
                } else {
                    "from capabilities; run `tessera bench pipeline-throughput` to measure"
                }
            ),
            Ok(path) => format!("{} path (its only one)", path.name()),
            Err(e) => format!("unavailable: {e}"),
        };
        println!("  {:<24} {path}", technique.name());
    }
    crate::gpu::check_validation(&gpu)
}
