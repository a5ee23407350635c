//! Acceleration structures for ray-tracing pipelines: a bottom level over axis-aligned boxes
//! (procedural primitives, each tested by the pipeline's intersection shader, so the caller
//! decides exactly what a hit is) under a top level holding one instance of it.

use crate::context::Gpu;
use crate::error::{GpuError, Result, VkContext};
use crate::memory::{Buffer, MemoryLocation};
use crate::shared::{DeviceShared, Retired};
use ash::vk;
use std::sync::Arc;

/// Bytes of one `VkAabbPositionsKHR`.
const BOX_BYTES: u64 = 24;

/// A built acceleration structure with the buffer holding it. A top level also holds the
/// bottom level it instances. Dropping it destroys the structure (after any submission that
/// may use it) and then frees its buffer.
pub struct AccelerationStructure {
    pub(crate) handle: vk::AccelerationStructureKHR,
    /// The memory the structure lives in; `Drop` retires the structure before this field
    /// is dropped, so the structure is destroyed first.
    storage: Buffer,
    bottom: Option<Box<AccelerationStructure>>,
    shared: Arc<DeviceShared>,
}

impl AccelerationStructure {
    /// Bytes the structure (and a top level's bottom level) occupies on the device.
    pub fn bytes(&self) -> u64 {
        self.storage.size + self.bottom.as_ref().map_or(0, |b| b.bytes())
    }
}

impl Drop for AccelerationStructure {
    fn drop(&mut self) {
        self.shared
            .retire(Retired::AccelerationStructure(self.handle));
    }
}

impl Gpu {
    fn acceleration(&self) -> Result<&ash::khr::acceleration_structure::Device> {
        self.shared
            .acceleration
            .as_ref()
            .ok_or_else(|| GpuError::Unsupported {
                device: self.caps().device_name.clone(),
                what: "VK_KHR_acceleration_structure".into(),
            })
    }

    /// The device address of `buffer` (made with `SHADER_DEVICE_ADDRESS`, as every buffer is).
    pub fn buffer_address(&self, buffer: &Buffer) -> u64 {
        let info = vk::BufferDeviceAddressInfo::default().buffer(buffer.handle);
        // SAFETY: the buffer is live and was created with SHADER_DEVICE_ADDRESS usage on a
        // device with the bufferDeviceAddress feature enabled.
        unsafe { self.device.get_buffer_device_address(&info) }
    }

    /// A top-level acceleration structure over one instance (identity transform, mask 0xff,
    /// hit group offset 0) of a bottom level whose primitive `i` is the box `boxes[i]`
    /// (`[min x, min y, min z, max x, max y, max z]`). The boxes are not opaque: any-hit
    /// shaders see every intersection the intersection shader reports.
    pub fn build_box_acceleration(
        &self,
        name: &str,
        boxes: &[[f32; 6]],
    ) -> Result<AccelerationStructure> {
        if boxes.is_empty() || boxes.len() > u32::MAX as usize {
            return Err(GpuError::Invalid(format!(
                "acceleration structure '{name}' of {} boxes",
                boxes.len()
            )));
        }
        let input = vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR;
        let box_buffer =
            self.upload_buffer(&format!("{name} boxes"), bytemuck::cast_slice(boxes), input)?;
        let aabbs = vk::AccelerationStructureGeometryAabbsDataKHR::default()
            .data(vk::DeviceOrHostAddressConstKHR {
                device_address: self.buffer_address(&box_buffer),
            })
            .stride(BOX_BYTES);
        let geometry = vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::AABBS)
            .geometry(vk::AccelerationStructureGeometryDataKHR { aabbs });
        let bottom = self.build_level(
            &format!("{name} bottom level"),
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            geometry,
            boxes.len() as u32,
        )?;

        let acceleration = self.acceleration()?;
        let address_info = vk::AccelerationStructureDeviceAddressInfoKHR::default()
            .acceleration_structure(bottom.handle);
        // SAFETY: the bottom level is a live structure of this device.
        let bottom_address =
            unsafe { acceleration.get_acceleration_structure_device_address(&address_info) };
        let instance = vk::AccelerationStructureInstanceKHR {
            transform: vk::TransformMatrixKHR {
                matrix: [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0],
            },
            instance_custom_index_and_mask: vk::Packed24_8::new(0, 0xff),
            instance_shader_binding_table_record_offset_and_flags: vk::Packed24_8::new(
                0,
                vk::GeometryInstanceFlagsKHR::FORCE_NO_OPAQUE.as_raw() as u8,
            ),
            acceleration_structure_reference: vk::AccelerationStructureReferenceKHR {
                device_handle: bottom_address,
            },
        };
        // SAFETY: `AccelerationStructureInstanceKHR` is a plain `repr(C)` struct of 64 bytes
        // without padding (a 48-byte matrix, two packed words, an 8-byte address); its bytes
        // are what the build reads from the instance buffer.
        let instance_bytes = unsafe {
            std::slice::from_raw_parts(
                (&instance as *const vk::AccelerationStructureInstanceKHR).cast::<u8>(),
                std::mem::size_of::<vk::AccelerationStructureInstanceKHR>(),
            )
        };
        let instances = self.upload_buffer(&format!("{name} instance"), instance_bytes, input)?;
        let geometry = vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::INSTANCES)
            .geometry(vk::AccelerationStructureGeometryDataKHR {
                instances: vk::AccelerationStructureGeometryInstancesDataKHR::default().data(
                    vk::DeviceOrHostAddressConstKHR {
                        device_address: self.buffer_address(&instances),
                    },
                ),
            });
        let mut top = self.build_level(
            &format!("{name} top level"),
            vk::AccelerationStructureTypeKHR::TOP_LEVEL,
            geometry,
            1,
        )?;
        top.bottom = Some(Box::new(bottom));
        Ok(top)
    }

    /// Creates a structure of `kind` sized for `count` primitives of `geometry` and builds it
    /// on the device (waiting for the build).
    fn build_level(
        &self,
        name: &str,
        kind: vk::AccelerationStructureTypeKHR,
        geometry: vk::AccelerationStructureGeometryKHR<'_>,
        count: u32,
    ) -> Result<AccelerationStructure> {
        let acceleration = self.acceleration()?;
        let geometries = [geometry];
        let mut build = vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(kind)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .geometries(&geometries);
        let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
        // SAFETY: the build info names one geometry whose input buffer is live; `count` is
        // that geometry's primitive count.
        unsafe {
            acceleration.get_acceleration_structure_build_sizes(
                vk::AccelerationStructureBuildTypeKHR::DEVICE,
                &build,
                &[count],
                &mut sizes,
            )
        };
        let storage = self.create_buffer(
            name,
            sizes.acceleration_structure_size,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR,
            MemoryLocation::GpuOnly,
        )?;
        let info = vk::AccelerationStructureCreateInfoKHR::default()
            .buffer(storage.handle)
            .size(sizes.acceleration_structure_size)
            .ty(kind);
        // SAFETY: the storage buffer is live, made with ACCELERATION_STRUCTURE_STORAGE usage
        // and at least `size` bytes long.
        let handle = unsafe { acceleration.create_acceleration_structure(&info, None) }
            .call("vkCreateAccelerationStructureKHR")?;
        let structure = AccelerationStructure {
            handle,
            storage,
            bottom: None,
            shared: self.shared.clone(),
        };
        self.set_name(handle, name);
        let alignment = u64::from(self.scratch_alignment()).max(1);
        let scratch = self.create_buffer(
            &format!("{name} scratch"),
            sizes.build_scratch_size + alignment,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        let scratch_address = self.buffer_address(&scratch).next_multiple_of(alignment);
        build = build
            .dst_acceleration_structure(handle)
            .scratch_data(vk::DeviceOrHostAddressKHR {
                device_address: scratch_address,
            });
        let ranges = [vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(count)];
        self.submit(&format!("build {name}"), |rec| {
            // SAFETY: `rec.cmd` is recording; the destination structure, its input and the
            // aligned scratch range are live and sized by the query above; `submit` waits for
            // the build before the scratch buffer is dropped.
            unsafe {
                acceleration.cmd_build_acceleration_structures(rec.cmd, &[build], &[&ranges])
            };
        })?;
        Ok(structure)
    }

    /// `minAccelerationStructureScratchOffsetAlignment` of the device.
    fn scratch_alignment(&self) -> u32 {
        let mut accel = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
        self.chained_properties(&mut accel);
        accel.min_acceleration_structure_scratch_offset_alignment
    }
}
