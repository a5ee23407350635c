//! GPU objects free themselves when dropped and keep the device alive while they exist; a
//! readback holds what the last submission copied into it.

mod common;
use common::open;
use tessera_gpu::{vk, Binding, Gpu, MemoryLocation, ShaderCompiler, Slot, Source, Timer};

const FILL: &str = r#"
#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Out { uint words[]; };
layout(binding = 1, rgba8) uniform writeonly image2D picture;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < 64u) {
        words[i] = i * 3u;
        imageStore(picture, ivec2(int(i % 8u), int(i / 8u)), vec4(1.0));
    }
}
"#;

/// The fill shader compiled, and the 8 × 8 storage image it writes.
fn fill_shader_and_picture(gpu: &Gpu) -> (tessera_gpu::Spirv, tessera_gpu::Image) {
    let compiler = ShaderCompiler::new().without_disk_cache();
    let spirv = compiler
        .compile(&Source::new("fill.comp.glsl", FILL), &[])
        .unwrap();
    let image = gpu
        .create_image(
            "picture",
            [8, 8, 1],
            vk::Format::R8G8B8A8_UNORM,
            vk::ImageUsageFlags::STORAGE,
            false,
        )
        .unwrap();
    (spirv, image)
}

/// Objects dropped after the `Gpu` that made them still free themselves: the last one takes
/// the device down, and the validation layer (which reports every object still alive when the
/// device is destroyed) sees nothing wrong.
#[test]
fn objects_outlive_the_gpu_handle() {
    let Some(gpu) = open() else {
        return;
    };
    let log = gpu.validation_log();
    let (spirv, image) = fill_shader_and_picture(&gpu);
    let pipeline = gpu
        .compute_pipeline("fill", &spirv, &[Slot::StorageBuffer, Slot::StorageImage])
        .unwrap();
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
    let buffer = gpu
        .create_buffer("words", 256, usage, MemoryLocation::GpuOnly)
        .unwrap();
    let mut timer = Timer::new(&gpu, 1).unwrap();
    timer.reset(&gpu);
    gpu.submit("fill", |rec| {
        rec.discard_to_general(&image);
        timer.scope(rec, "fill", |rec| {
            let bindings = [Binding::Buffer(&buffer), Binding::StorageImage(&image)];
            rec.dispatch(&pipeline, &bindings, &[], [64, 1, 1]);
        });
    })
    .unwrap();
    assert_eq!(timer.read_ms(&gpu).unwrap().len(), 1);
    let words: Vec<u32> = gpu.read_buffer_as(&buffer).unwrap();
    assert_eq!(words[..4], [0, 3, 6, 9]);
    assert!(gpu.validation_errors().is_empty());

    drop(gpu);
    // The device lives on in the objects; each one freed here uses it.
    drop(buffer);
    drop(image);
    drop(timer);
    drop(pipeline);
    // The last object took the device (and the log's other owner) with it.
    assert_eq!(
        std::sync::Arc::strong_count(&log),
        1,
        "the device is still alive"
    );
    let errors = log.errors();
    assert!(
        errors.is_empty(),
        "{} validation error(s):\n{}",
        errors.len(),
        errors.join("\n")
    );
}

/// 200 buffers of 64 MiB made and dropped one after another: a leak would hold 12.5 GiB, more
/// than lavapipe's heap on small machines, and shows in the allocator's bookkeeping anyway.
#[test]
fn dropped_buffers_give_their_memory_back() {
    let Some(gpu) = open() else {
        return;
    };
    const SIZE: u64 = 64 << 20;
    let baseline = gpu.allocated_bytes();
    eprintln!(
        "device-local heap {} MiB; 200 buffers of 64 MiB would need {} MiB",
        gpu.caps().device_local_bytes >> 20,
        (200 * SIZE) >> 20
    );
    for i in 0..200 {
        let buffer = gpu
            .create_buffer(
                "big",
                SIZE,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )
            .unwrap_or_else(|e| panic!("buffer {i}: {e}"));
        if i % 50 == 0 {
            // Touch it, so that a driver allocating lazily still backs it.
            gpu.submit("touch", |rec| rec.fill_buffer(&buffer, i))
                .unwrap();
        }
        assert!(gpu.allocated_bytes() >= baseline + SIZE);
        drop(buffer);
        assert_eq!(gpu.allocated_bytes(), baseline, "buffer {i} was not freed");
    }
    let errors = gpu.validation_errors();
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

/// A buffer and a pipeline dropped inside the submission that recorded them are destroyed only
/// after it completed: the validation layer reports a command buffer naming a destroyed object
/// otherwise, and the work they recorded still lands.
#[test]
fn objects_dropped_while_recording_wait_for_the_submission() {
    let Some(gpu) = open() else {
        return;
    };
    let (spirv, image) = fill_shader_and_picture(&gpu);
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER
        | vk::BufferUsageFlags::TRANSFER_SRC
        | vk::BufferUsageFlags::TRANSFER_DST;
    let kept = gpu
        .create_buffer("kept", 256, usage, MemoryLocation::GpuOnly)
        .unwrap();
    let baseline = gpu.allocated_bytes();
    gpu.submit("fill, then copy from a buffer dropped at once", |rec| {
        let pipeline = gpu
            .compute_pipeline("fill", &spirv, &[Slot::StorageBuffer, Slot::StorageImage])
            .unwrap();
        let scratch = gpu
            .create_buffer("scratch", 256, usage, MemoryLocation::GpuOnly)
            .unwrap();
        rec.discard_to_general(&image);
        let bindings = [Binding::Buffer(&scratch), Binding::StorageImage(&image)];
        rec.dispatch(&pipeline, &bindings, &[], [64, 1, 1]);
        rec.barrier();
        rec.copy_buffer(&scratch, &kept, 256);
        drop(scratch);
        drop(pipeline);
        // Still held: the copy above has not run yet.
        assert!(gpu.allocated_bytes() > baseline);
    })
    .unwrap();
    assert_eq!(
        gpu.allocated_bytes(),
        baseline,
        "the scratch buffer was kept"
    );
    let words: Vec<u32> = gpu.read_buffer_as(&kept).unwrap();
    assert_eq!(words[..4], [0, 3, 6, 9]);
    let errors = gpu.validation_errors();
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

/// Reading a timer whose scopes were recorded but never submitted is an error, not a wait
/// without end.
#[test]
fn a_timer_never_submitted_is_an_error() {
    let Some(gpu) = open() else {
        return;
    };
    let mut timer = Timer::new(&gpu, 2).unwrap();
    timer.reset(&gpu);
    let buffer = gpu
        .create_buffer(
            "words",
            256,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )
        .unwrap();
    // Recorded into a submission whose recording is thrown away by a panic: never submitted.
    let recorded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        gpu.submit("abandoned", |rec| {
            timer.scope(rec, "fill", |rec| rec.fill_buffer(&buffer, 1));
            panic!("abandon the recording");
        })
    }));
    assert!(recorded.is_err());
    let error = timer.read_ms(&gpu).unwrap_err().to_string();
    assert!(
        error.contains("fill") && error.contains("never submitted"),
        "{error}"
    );
}

#[test]
fn a_readback_holds_what_the_last_submission_copied() {
    let Some(gpu) = open() else { return };
    let source = gpu
        .create_buffer(
            "counters",
            16,
            vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )
        .unwrap();
    let readback = gpu.create_readback("counters (host)", 24).unwrap();
    assert_eq!(readback.bytes(), [0u8; 24], "zero before any copy");
    for round in 1..=2u32 {
        let words = [round, 2 * round, 3 * round, 4 * round];
        gpu.submit("copy", |rec| {
            rec.update_buffer(&source, bytemuck::cast_slice(&words));
            rec.barrier();
            readback.record_copy(rec, &source, 8, 16);
        })
        .unwrap();
        let held: Vec<u32> = bytemuck::pod_collect_to_vec(readback.bytes());
        assert_eq!(
            held,
            [0, 0, round, 2 * round, 3 * round, 4 * round],
            "round {round}"
        );
    }
    // Several copies behind one barrier: each lands at its own offset.
    gpu.submit("copies", |rec| {
        rec.update_buffer(&source, bytemuck::cast_slice(&[7u32, 8, 9, 10]));
        rec.barrier();
        readback.record_copies(rec, &[(&source, 0, 8), (&source, 16, 8)]);
    })
    .unwrap();
    let held: Vec<u32> = bytemuck::pod_collect_to_vec(readback.bytes());
    assert_eq!(held, [7, 8, 2, 4, 7, 8]);
    assert!(
        gpu.validation_errors().is_empty(),
        "{:?}",
        gpu.validation_errors()
    );
}
