//! GPU timestamp scopes: named stages timed inside one submission.

use crate::commands::Recorder;
use crate::context::Gpu;
use crate::error::{GpuError, Result, VkContext};
use crate::shared::{DeviceShared, Retired};
use ash::vk;
use std::sync::Arc;

/// Holds a query pool of two timestamps per named scope; dropping it destroys the pool.
pub struct Timer {
    pub(crate) pool: vk::QueryPool,
    names: Vec<String>,
    capacity: u32,
    shared: Arc<DeviceShared>,
}

impl Drop for Timer {
    fn drop(&mut self) {
        self.shared.retire(Retired::QueryPool(self.pool));
    }
}

impl Timer {
    pub fn new(gpu: &Gpu, max_scopes: u32) -> Result<Timer> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(max_scopes * 2);
        // SAFETY: the create info is valid (timestamp queries, which the queue supports).
        let pool =
            unsafe { gpu.device.create_query_pool(&info, None) }.call("vkCreateQueryPool")?;
        Ok(Timer {
            pool,
            names: Vec::new(),
            capacity: max_scopes,
            shared: gpu.shared.clone(),
        })
    }

    /// Forgets earlier scopes; call before recording a new frame.
    pub fn reset(&mut self, gpu: &Gpu) {
        // SAFETY: host query reset is enabled on the device, the range is the whole pool, and
        // no submitted work uses the pool (submissions wait for their fence).
        unsafe { gpu.device.reset_query_pool(self.pool, 0, self.capacity * 2) };
        self.names.clear();
    }

    /// Whether every scope the timer was made for is taken (until the next reset).
    pub fn is_full(&self) -> bool {
        self.names.len() as u32 >= self.capacity
    }

    /// Times everything `body` records as the stage `name`.
    pub fn scope<R>(&mut self, rec: &Recorder, name: &str, body: impl FnOnce(&Recorder) -> R) -> R {
        let index = self.names.len() as u32;
        assert!(
            index < self.capacity,
            "timer holds {} scopes",
            self.capacity
        );
        self.names.push(name.to_string());
        rec.timestamp(self, index * 2);
        let r = body(rec);
        rec.timestamp(self, index * 2 + 1);
        r
    }

    /// Milliseconds per scope of the last submitted frame, in recording order.
    pub fn read_ms(&self, gpu: &Gpu) -> Result<Vec<(String, f64)>> {
        Ok(self.read(gpu)?.scopes)
    }

    /// The last submitted frame's scopes and its span (see [`ScopeTimes`]).
    pub fn read(&self, gpu: &Gpu) -> Result<ScopeTimes> {
        let n = self.names.len();
        if n == 0 {
            return Ok(ScopeTimes::default());
        }
        let mut ticks = vec![0u64; n * 2];
        // No WAIT: submissions wait for their fence, so the results of a submitted frame are
        // there; scopes recorded into a frame that was never submitted would wait forever.
        // SAFETY: `ticks` holds exactly two 64-bit results per scope, queries 0..2n.
        let read = unsafe {
            gpu.device.get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64,
            )
        };
        match read {
            Err(vk::Result::NOT_READY) => {
                return Err(GpuError::TimerNotSubmitted {
                    scopes: self.names.join(", "),
                })
            }
            other => other.call("vkGetQueryPoolResults")?,
        }
        let period = gpu.caps().timestamp_period_ns as f64;
        let ms = |from: u64, to: u64| to.wrapping_sub(from) as f64 * period * 1e-6;
        let scopes = self
            .names
            .iter()
            .enumerate()
            .map(|(i, name)| (name.clone(), ms(ticks[i * 2], ticks[i * 2 + 1])))
            .collect();
        Ok(ScopeTimes {
            scopes,
            span_ms: ms(ticks[0], ticks[n * 2 - 1]),
        })
    }
}

/// What a [`Timer`] measured of one frame: each scope's milliseconds in recording order, and
/// the milliseconds from the first scope's start to the last one's end. Work recorded between
/// scopes, and the GPU's drain from one pass to the next, belong to no scope: the span of a
/// frame of several scopes is its whole time, at least the scopes' sum.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScopeTimes {
    pub scopes: Vec<(String, f64)>,
    pub span_ms: f64,
}
