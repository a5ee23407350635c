//! A volume on the GPU: a 3-D texture of the raw samples.

use crate::error::Result;
use tessera_data::{ScalarType, Volume};
use tessera_gpu::{vk, Gpu, Image};

pub struct GpuVolume {
    pub texture: Image,
    pub dims: [u32; 3],
    pub scalar: ScalarType,
}

fn format_of(scalar: ScalarType) -> vk::Format {
    match scalar {
        // Integer formats keep samples exact; shaders convert with float().
        ScalarType::U8 => vk::Format::R8_UINT,
        ScalarType::U16 => vk::Format::R16_UINT,
        ScalarType::F32 => vk::Format::R32_SFLOAT,
    }
}

impl GpuVolume {
    pub fn upload(gpu: &Gpu, volume: &Volume) -> Result<GpuVolume> {
        let texture = gpu.upload_image_3d(
            &format!("volume {}", volume.name()),
            volume.dims(),
            format_of(volume.scalar_type()),
            volume.bytes(),
        )?;
        Ok(GpuVolume {
            texture,
            dims: volume.dims(),
            scalar: volume.scalar_type(),
        })
    }
}
