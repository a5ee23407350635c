//! One front door to the isosurface techniques, for tools that pick one by name.

use crate::error::{Error, Result};
use crate::iso::direct::compute::{ComputeTarget, DirectCompute, TriangleLists};
use crate::iso::direct::cull::CullState;
use crate::iso::direct::{Direct, FrameOptions, RasterTarget};
use crate::iso::raymarch::Raymarch;
use crate::iso::PreparedVolume;
use crate::path::{Path, PathChoice};
use crate::target::Target;
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
    DirectCompute(Box<DirectCompute>),
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
    /// `path` matters for techniques with a graphics and a compute path (direct).
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        technique: IsoTechnique,
        scalar: ScalarType,
        path: PathChoice,
    ) -> Result<IsoRenderer> {
        let technique = match technique {
            IsoTechnique::Direct => {
                let measured = crate::path::remembered(gpu.caps());
                match crate::path::choose(gpu.caps(), path, measured.as_ref())? {
                    Path::Graphics => IsoTechnique::Direct,
                    Path::Compute => {
                        let d = DirectCompute::new(gpu, compiler, scalar)?;
                        return Ok(IsoRenderer {
                            inner: Inner::DirectCompute(Box::new(d)),
                        });
                    }
                }
            }
            t => t,
        };
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
            Inner::DirectCompute(d) => d.prepare(gpu, volume),
        }
    }

    /// The pipeline the frames run on.
    pub fn path(&self) -> Path {
        match &self.inner {
            Inner::Direct(_) => Path::Graphics,
            Inner::Raymarch(_) | Inner::DirectCompute(_) => Path::Compute,
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
                let target = Target::new(gpu, size.0, size.1)?;
                let (image, gpu_ms) = r.render(gpu, prepared, &target, iso, camera)?;
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
                let frame = d.render(gpu, prepared, &target, iso, camera, &options)?;
                Ok(IsoFrame {
                    image: frame.image,
                    gpu_ms: frame.gpu_ms,
                    triangles: Some(frame.stats.triangles),
                })
            }
            Inner::DirectCompute(d) => {
                // Try a modest list first; an overflow reports the exact count, so at most one
                // retry with room for all of it.
                let mut capacity = TriangleLists::default_capacity(gpu).min(1 << 20);
                let (image, gpu_ms, stats) = loop {
                    let target = ComputeTarget::new(gpu, size.0, size.1, capacity)?;
                    match d.render(gpu, prepared, &target, iso, camera) {
                        Ok(frame) => break frame,
                        Err(_) if d.read_stats(gpu)?.triangles > capacity => {
                            let needed = d.read_stats(gpu)?.triangles;
                            if needed > TriangleLists::default_capacity(gpu) {
                                return Err(crate::Error::Invalid(format!(
                                    "the isosurface has {needed} triangles, more than fit in device memory"
                                )));
                            }
                            capacity = needed;
                        }
                        Err(e) => return Err(e),
                    }
                };
                Ok(IsoFrame {
                    image,
                    gpu_ms,
                    triangles: Some(stats.triangles),
                })
            }
        }
    }
}
