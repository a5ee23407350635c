//! Vulkan plumbing for Tessera: device and capabilities, memory, run-time shader compilation,
//! pipelines, command recording and GPU timing. It knows nothing about volumes, meshes or
//! glyphs; techniques in the `tessera` crate build on it.
//!
//! GPU objects ([`Buffer`], [`Image`], [`Pipeline`], [`RayTracingPipeline`],
//! [`AccelerationStructure`], [`Timer`]) free themselves when dropped and
//! keep the device alive while they exist, so they may be dropped in any order, before or after
//! the [`Gpu`] they were made from.
#![warn(unsafe_op_in_unsafe_fn)]

pub mod accel;
pub mod caps;
pub mod commands;
pub mod context;
mod device_features;
pub mod error;
pub mod keep_busy;
pub mod memory;
pub mod pipeline;
pub mod ray_tracing;
pub mod shader;
mod shared;
pub mod spirv;
pub mod statistics;
mod submit;
#[cfg(feature = "window")]
pub mod swapchain;
pub mod timer;
pub mod timing;
mod transfer;
pub mod validation;

pub use accel::AccelerationStructure;
pub use ash::vk;
pub use caps::Capabilities;
pub use commands::{Binding, IndexedDraws, Recorder, INDEXED_COMMAND_BYTES};
pub use context::{list_devices, DeviceListing, Gpu, GpuOptions};
pub use error::{GpuError, Result};
pub use memory::{Buffer, Image, MemoryLocation, MemoryReport, Readback};
pub use pipeline::{spread_groups, Blend, Pipeline, RenderTargets, Slot, PUSH_CONSTANT_BYTES};
pub use ray_tracing::{ProceduralHitGroup, RayTracingPipeline, RayTracingShaders};
pub use shader::{ShaderCompiler, Source, Spirv, Stage};
pub use statistics::PipelineStatistics;
#[cfg(feature = "window")]
pub use swapchain::{SwapImage, Swapchain};
pub use timer::{ScopeTimes, Timer};
