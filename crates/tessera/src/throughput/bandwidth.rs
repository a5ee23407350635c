//! The memory system's streaming rate, for judging passes that only read and reduce (the
//! octree build): a compute shader copying a buffer in 16-byte words. `vkCmdCopyBuffer` is no
//! measure of the limit: drivers may run it on a copy engine far below what the SMs reach.

use crate::builtin_shader;
use crate::error::{Error, Result};
use tessera_gpu::{Binding, Buffer, Gpu, Pipeline, Recorder, ShaderCompiler, Slot};

/// Workgroups of the copy: enough to fill every SM several times over; each invocation then
/// strides through the rest.
const COPY_GROUPS: u32 = 4096;

pub struct ComputeCopy {
    pipeline: Pipeline,
}

impl ComputeCopy {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<ComputeCopy> {
        let spirv = compiler.compile(&builtin_shader!("copy.comp.glsl"), &[])?;
        Ok(ComputeCopy {
            pipeline: gpu.compute_pipeline(
                "compute copy",
                &spirv,
                &[Slot::StorageBuffer, Slot::StorageBuffer],
            )?,
        })
    }

    /// Records copying the first `bytes` of `source` into `destination` (a whole number of
    /// 16-byte words, within both buffers).
    pub fn record(
        &self,
        rec: &Recorder,
        source: &Buffer,
        destination: &Buffer,
        bytes: u64,
    ) -> Result<()> {
        let words = words_of(bytes, source, destination)?;
        let groups = words.div_ceil(256).clamp(1, COPY_GROUPS);
        rec.dispatch_groups(
            &self.pipeline,
            &[Binding::Buffer(source), Binding::Buffer(destination)],
            bytemuck::bytes_of(&words),
            [groups, 1, 1],
        );
        Ok(())
    }
}

/// The 16-byte words of a copy of `bytes` between the buffers, or why it cannot be made.
fn words_of(bytes: u64, source: &Buffer, destination: &Buffer) -> Result<u32> {
    let words = bytes / 16;
    if !bytes.is_multiple_of(16)
        || bytes > source.size.min(destination.size)
        || words > u64::from(u32::MAX)
    {
        return Err(Error::Invalid(format!(
            "compute copy of {bytes} bytes between buffers of {} and {}: whole 16-byte words \
             within both, fewer than 2^32 of them",
            source.size, destination.size
        )));
    }
    Ok(words as u32)
}

#[cfg(test)]
mod tests {
    use super::{words_of, ComputeCopy};
    use tessera_gpu::{vk, MemoryLocation};

    #[test]
    fn the_compute_copy_copies_every_word_and_no_more() {
        let gpu = tessera_test::TestGpu::new();
        let copy = ComputeCopy::new(&gpu, &crate::shaders::compiler()).unwrap();
        // More words than one pass of the grid covers, so the stride loop runs.
        let words: Vec<u32> = (0..4 * 300_000u32)
            .map(|i| i.wrapping_mul(2_654_435_761))
            .collect();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
        let source = gpu
            .upload_buffer("source", bytemuck::cast_slice(&words), usage)
            .unwrap();
        let bytes = source.size;
        let destination = gpu
            .create_buffer(
                "destination",
                bytes + 64,
                usage | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )
            .unwrap();
        let copied = bytes - 32; // all but the last two words
        let mut recorded = Ok(());
        gpu.submit("compute copy test", |rec| {
            rec.fill_buffer(&destination, 0xdead_beef);
            rec.barrier();
            recorded = copy.record(rec, &source, &destination, copied);
        })
        .unwrap();
        recorded.unwrap();
        let got: Vec<u32> = gpu.read_buffer_as(&destination).unwrap();
        let n = (copied / 4) as usize;
        assert!(got[..n] == words[..n], "copied words differ");
        assert!(
            got[n..].iter().all(|&w| w == 0xdead_beef),
            "wrote past the range"
        );
        assert!(words_of(12, &source, &destination).is_err());
        assert!(words_of(bytes + 16, &source, &destination).is_err());
    }
}
