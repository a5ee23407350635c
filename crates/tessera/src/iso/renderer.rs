//! One front door to the isosurface techniques, for tools that pick one by name.

use crate::error::{Error, Result};
use crate::iso::direct::cull::CullState;
use crate::iso::direct::{Direct, FrameOptions, RasterTarget};
use crate::iso::raymarch::Raymarch;
use crate::iso::PreparedVolume;
use crate::target::PixelTarget;
use tessera_data::{OrbitCamera, RgbaImage, ScalarType, Volume};
use tessera_gpu::{Gpu, ShaderCompiler};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IsoTechnique {
    /// Min-max octree ray marching (compute).
    Raymarch,
    /// Task/mesh-shader marching cubes straight to the rasterizer (graphics).
    Direct,
}

impl IsoTechnique {
    pub const ALL: [IsoTechnique; 2] = [IsoTechnique::Raymarch, IsoTechnique::Direct];

    pub fn name(self) -> &'static str {
        match self {
            IsoTechnique::Raymarch => "raymarch",
            IsoTechnique::Direct => "direct",
        }
    }

    /// The pipeline the technique runs on, as benchmarks report it.
    pub fn path(self) -> &'static str {
        match self {
            IsoTechnique::Raymarch => "compute",
            IsoTechnique::Direct => "mesh",
        }
    }

    pub fn parse(name: &str) -> Result<IsoTechnique> {
        Self::ALL
            .into_iter()
            .find(|t| t.name() == name)
            .ok_or_else(|| Error::Invalid(format!("unknown technique '{name}' (raymarch, direct)")))
    }
}

enum Inner {
    Raymarch(Box<Raymarch>),
    Direct(Box<Direct>),
}

pub struct IsoRenderer {
    inner: Inner,
}

/// One rendered image with its GPU time and, for rasterizing techniques, the triangle count.
pub struct IsoFrame {
    pub image: RgbaImage,
    pub gpu_ms: f64,
    pub triangles: Option<u32>,
}

impl IsoRenderer {
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        technique: IsoTechnique,
        scalar: ScalarType,
    ) -> Result<IsoRenderer> {
        let inner = match technique {
            IsoTechnique::Raymarch => {
                Inner::Raymarch(Box::new(Raymarch::new(gpu, compiler, scalar)?))
            }
            IsoTechnique::Direct => Inner::Direct(Box::new(Direct::new(gpu, compiler, scalar)?)),
        };
        Ok(IsoRenderer { inner })
    }

    pub fn prepare(&self, gpu: &Gpu, volume: &Volume) -> Result<PreparedVolume> {
        match &self.inner {
            Inner::Raymarch(r) => r.prepare(gpu, volume),
            Inner::Direct(d) => d.prepare(gpu, volume),
        }
    }

    pub fn render(
        &self,
        gpu: &Gpu,
        prepared: &PreparedVolume,
        iso: f32,
        camera: &OrbitCamera,
        size: (u32, u32),
        culling: bool,
    ) -> Result<IsoFrame> {
        match &self.inner {
            Inner::Raymarch(r) => {
                let target = PixelTarget::new(gpu, size.0, size.1)?;
                let result = r.render(gpu, prepared, &target, iso, camera);
                target.destroy(gpu);
                let (image, gpu_ms) = result?;
                Ok(IsoFrame {
                    image,
                    gpu_ms,
                    triangles: None,
                })
            }
            Inner::Direct(d) => {
                let target = RasterTarget::new(gpu, size.0, size.1)?;
                let state = if culling {
                    Some(CullState::new(gpu, prepared)?)
                } else {
                    None
                };
                let options = FrameOptions {
                    capture_capacity: 0,
                    culling: state.as_ref(),
                };
                let result = d.render(gpu, prepared, &target, iso, camera, &options);
                target.destroy(gpu);
                if let Some(state) = state {
                    state.destroy(gpu);
                }
                let frame = result?;
                Ok(IsoFrame {
                    image: frame.image,
                    gpu_ms: frame.gpu_ms,
                    triangles: Some(frame.stats.triangles),
                })
            }
        }
    }

    pub fn destroy(self, gpu: &Gpu) {
        match self.inner {
            Inner::Raymarch(r) => r.destroy(gpu),
            Inner::Direct(d) => d.destroy(gpu),
        }
    }
}
