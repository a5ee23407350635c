//! Opening the device and checking what the validation layer saw, for every command that
//! renders.

use anyhow::Result;

/// Opens the device, with a hint when no Vulkan driver is installed.
pub fn open_gpu(options: &tessera_gpu::GpuOptions) -> Result<tessera_gpu::Gpu> {
    use anyhow::Context;
    tessera_gpu::Gpu::new(options).context("opening the Vulkan device")
}

/// Fails when validation is on and reported errors, so scripted runs cannot miss them. Prints
/// the pipelines' statistics first when they were captured (`--pipeline-stats`).
pub fn check_validation(gpu: &tessera_gpu::Gpu) -> Result<()> {
    for line in gpu.pipeline_statistics_report() {
        println!("{line}");
    }
    let errors = gpu.validation_errors();
    if !errors.is_empty() {
        anyhow::bail!("the validation layer reported {} error(s)", errors.len());
    }
    Ok(())
}
