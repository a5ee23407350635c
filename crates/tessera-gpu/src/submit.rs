//! Submitting recorded work: one command buffer per `Gpu::submit`, waited for under the
//! device's time limit (`GpuOptions::timeout`).

use crate::commands::Recorder;
use crate::context::Gpu;
use crate::error::{GpuError, Result, VkContext};
use ash::vk;

impl Gpu {
    /// Records commands with `record`, submits them and waits for their fence. `pass` names the
    /// work in errors (a lost device reports which pass it was in).
    ///
    /// Because it waits, no work is in flight once it returns, so any [`crate::Buffer`],
    /// [`crate::Image`], [`crate::Pipeline`] or [`crate::Timer`] may be dropped afterwards;
    /// objects dropped inside `record` are destroyed once the submission completed.
    pub fn submit(&self, pass: &str, record: impl FnOnce(&Recorder)) -> Result<()> {
        if self.shared.hung.load(std::sync::atomic::Ordering::Acquire) {
            return Err(GpuError::Hung { pass: pass.into() });
        }
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool belongs to this device and only `submit` uses it; `Gpu` is not
        // `Sync`, so no other thread records or submits at the same time.
        let cmd = unsafe { self.device.allocate_command_buffers(&alloc) }
            .call("vkAllocateCommandBuffers")?[0];
        // Objects dropped from here until the guard goes (after the fence wait) are kept.
        let open = self.shared.open_submission();
        let result = self.record_and_run(pass, cmd, record);
        if matches!(result, Err(GpuError::Timeout { .. })) {
            // The work may still run: the command buffer, and everything dropped meanwhile,
            // stay as they are (`DeviceShared::hung`).
            return result;
        }
        // SAFETY: the command buffer came from this pool and is no longer pending:
        // `record_and_run` waited for its fence (or it was never submitted).
        unsafe { self.device.free_command_buffers(self.command_pool, &[cmd]) };
        drop(open);
        result
    }

    fn record_and_run(
        &self,
        pass: &str,
        cmd: vk::CommandBuffer,
        record: impl FnOnce(&Recorder),
    ) -> Result<()> {
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: `cmd` was just allocated and is in the initial state.
        unsafe { self.device.begin_command_buffer(cmd, &begin) }.call("vkBeginCommandBuffer")?;
        record(&Recorder { gpu: self, cmd });
        // SAFETY: `cmd` is recording (begun above).
        unsafe { self.device.end_command_buffer(cmd) }.call("vkEndCommandBuffer")?;
        // SAFETY: a plain fence creation on this device.
        let fence = unsafe {
            self.device
                .create_fence(&vk::FenceCreateInfo::default(), None)
        }
        .call("vkCreateFence")?;
        let cmds = [cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        let lost = |r: vk::Result| match r {
            vk::Result::ERROR_DEVICE_LOST => GpuError::DeviceLost { pass: pass.into() },
            result => GpuError::Vulkan {
                call: "vkQueueSubmit/vkWaitForFences",
                result,
            },
        };
        // SAFETY: `cmd` is executable and `fence` unsignalled; the queue is only used here, and we
        // wait for the fence before returning, so no work outlives this call (which is what
        // lets objects be dropped after any `submit`) — unless the wait times out, after which
        // the device is marked hung and nothing it may use is destroyed.
        let result = unsafe {
            self.device
                .queue_submit(self.queue, &submit, fence)
                .and_then(|_| {
                    self.device
                        .wait_for_fences(&[fence], true, self.shared.timeout_ns)
                })
        };
        if result == Err(vk::Result::TIMEOUT) {
            self.shared
                .hung
                .store(true, std::sync::atomic::Ordering::Release);
            return Err(GpuError::Timeout {
                pass: pass.into(),
                seconds: self.shared.timeout_ns as f64 * 1e-9,
            });
        }
        // SAFETY: the fence is no longer in use: we waited for it, or the submission failed.
        unsafe { self.device.destroy_fence(fence, None) };
        result.map_err(lost)
    }
}
