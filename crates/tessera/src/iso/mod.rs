//! Isosurface techniques over regular volumes (papers C and D and their references).

pub mod ablation;
pub mod attempts;
pub mod direct;
pub mod meshlet_draw;
pub mod meshlets;
pub mod minmax;
pub mod pmb;
pub mod pmb_draw;
pub mod raymarch;
pub mod surface;

use crate::error::{Error, Result};
use crate::gpu_volume::GpuVolume;
use minmax::{MinMaxBuilder, MinMaxOctreeGpu};
use std::sync::atomic::{AtomicU64, Ordering};
use tessera_data::{ScalarType, Volume};
use tessera_gpu::Gpu;

/// A volume uploaded with its min-max octree, ready to render at any isovalue by any
/// isosurface technique.
pub struct PreparedVolume {
    pub volume: GpuVolume,
    pub octree: MinMaxOctreeGpu,
    pub spacing: [f32; 3],
    /// The lowest and highest sample on the grid's six faces
    /// ([`tessera_data::facing::boundary_range`]): whether a surface is closed. Whoever copies
    /// other samples into `volume` sets it for them (the range of all of them).
    pub boundary_range: (f32, f32),
    /// Whether draws of this volume's closed surfaces leave out the side no pixel shows.
    pub hidden_side: HiddenSide,
    id: u64,
}

/// What the isosurface draws do with the side of a closed surface that no pixel shows
/// ([`tessera_data::facing`]). The image is the same either way; drawing it measures what
/// leaving it out saves.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum HiddenSide {
    /// Left out of the raster passes, where the surface is closed and the grid lies wholly
    /// before the near plane.
    #[default]
    Skip,
    /// Drawn, as every triangle of an open surface is.
    Draw,
}

impl HiddenSide {
    /// The name the options give it: `skip` or `draw`.
    pub fn name(self) -> &'static str {
        match self {
            HiddenSide::Skip => "skip",
            HiddenSide::Draw => "draw",
        }
    }

    /// The choice named `skip` or `draw`.
    pub fn parse(text: &str) -> Result<HiddenSide> {
        match text {
            "skip" => Ok(HiddenSide::Skip),
            "draw" => Ok(HiddenSide::Draw),
            other => Err(Error::Invalid(format!(
                "hidden side '{other}': choose skip or draw"
            ))),
        }
    }
}

/// The id the next prepared volume gets.
static NEXT_VOLUME_ID: AtomicU64 = AtomicU64::new(1);

impl PreparedVolume {
    /// A number no other volume prepared by this process has: what state kept from frame to
    /// frame is checked against (e.g. culling's per-block boxes, valid for one volume only).
    /// Samples copied into `volume` in place (playback into one upload) keep the id: reset the
    /// culling states that drew the old samples.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// The side of `iso` (texel units) every boundary sample lies on, when the surface there
    /// is closed and [`Self::hidden_side`] lets draws leave its hidden side out; else `None`.
    pub fn closed_side(&self, iso: f32) -> Option<tessera_data::facing::BoundarySide> {
        match self.hidden_side {
            HiddenSide::Skip => tessera_data::facing::boundary_side(self.boundary_range, iso),
            HiddenSide::Draw => None,
        }
    }

    /// Refuses a volume of another sample type than `pipelines` (named in the message) were
    /// built for.
    pub fn require_scalar(&self, scalar: ScalarType, pipelines: &str) -> Result<()> {
        if self.volume.scalar != scalar {
            return Err(Error::Invalid(format!(
                "the {pipelines} pipelines were built for {} samples, the volume has {}",
                scalar.name(),
                self.volume.scalar.name()
            )));
        }
        Ok(())
    }

    /// Uploads `volume` and builds its octree on the GPU.
    pub fn new(gpu: &Gpu, builder: &MinMaxBuilder, volume: &Volume) -> Result<PreparedVolume> {
        if volume.scalar_type() != builder.scalar() {
            return Err(Error::Invalid(format!(
                "the pipelines were built for {} samples, the volume has {}",
                builder.scalar().name(),
                volume.scalar_type().name()
            )));
        }
        let gpu_volume = GpuVolume::upload(gpu, volume)?;
        let octree = MinMaxOctreeGpu::allocate(gpu, volume.dims())?;
        let prepared = PreparedVolume {
            volume: gpu_volume,
            octree,
            spacing: volume.spacing(),
            boundary_range: tessera_data::facing::boundary_range(volume),
            hidden_side: HiddenSide::default(),
            id: NEXT_VOLUME_ID.fetch_add(1, Ordering::Relaxed),
        };
        gpu.submit("build min-max octree", |rec| {
            builder.record(rec, &prepared.volume, &prepared.octree)
        })?;
        Ok(prepared)
    }
}
