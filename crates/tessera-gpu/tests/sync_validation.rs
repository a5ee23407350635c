//! With validation on, synchronization validation is on too: a copy that reads a buffer a
//! dispatch wrote, with no barrier between them, is reported; with the barrier it is not.

use tessera_gpu::{vk, Binding, Gpu, GpuOptions, MemoryLocation, ShaderCompiler, Slot, Source};

const WRITE: &str = r#"
#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Out { uint words[]; };
void main() { words[gl_GlobalInvocationID.x] = gl_GlobalInvocationID.x; }
"#;

fn copy_after_dispatch(barrier: bool) -> Vec<String> {
    let gpu = match Gpu::new(&GpuOptions {
        device_index: None,
        validation: true,
        ..GpuOptions::default()
    }) {
        Ok(gpu) => gpu,
        Err(e) => {
            tessera_test::skip("", &format!("no Vulkan device ({e})"));
            return Vec::new();
        }
    };
    let spirv = ShaderCompiler::new()
        .without_disk_cache()
        .compile(&Source::new("write.comp.glsl", WRITE), &[])
        .unwrap();
    let pipeline = gpu
        .compute_pipeline("write", &spirv, &[Slot::StorageBuffer])
        .unwrap();
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER
        | vk::BufferUsageFlags::TRANSFER_SRC
        | vk::BufferUsageFlags::TRANSFER_DST;
    let written = gpu
        .create_buffer("written", 256, usage, MemoryLocation::GpuOnly)
        .unwrap();
    let copy = gpu
        .create_buffer("copy", 256, usage, MemoryLocation::GpuOnly)
        .unwrap();
    gpu.submit("write, then copy", |rec| {
        rec.dispatch(&pipeline, &[Binding::Buffer(&written)], &[], [64, 1, 1]);
        if barrier {
            rec.barrier();
        }
        rec.copy_buffer(&written, &copy, 256);
    })
    .unwrap();
    gpu.validation_errors()
}

#[test]
fn a_missing_barrier_is_reported_and_a_barrier_silences_it() {
    let unsynchronized = copy_after_dispatch(false);
    let synchronized = copy_after_dispatch(true);
    if unsynchronized.is_empty() && synchronized.is_empty() {
        // Either no device (reported as skipped above) or a layer without the check.
        assert!(
            Gpu::new(&GpuOptions {
                device_index: None,
                validation: true,
                ..GpuOptions::default()
            })
            .is_err(),
            "validation on, yet the missing barrier went unreported"
        );
        return;
    }
    assert!(
        unsynchronized.iter().any(|e| e.contains("SYNC-HAZARD")),
        "{unsynchronized:?}"
    );
    assert!(synchronized.is_empty(), "{synchronized:?}");
}
