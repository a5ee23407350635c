//! A tet mesh on the GPU, and the float target interval shading accumulates into.

use crate::error::Result;
use crate::path::Path;
use tessera_data::tet::asteroids::asteroid_spheres;
use tessera_data::tet::optical::MeshFrame;
use tessera_data::tet::scalar_integral::scalar_range;
use tessera_data::tet::TetMesh;
use tessera_gpu::{vk, Buffer, Gpu, Image, MemoryLocation};

/// A tet mesh on the GPU, placed in world space like the CPU reference places it.
pub struct GpuTetMesh {
    /// xyz world position, w the vertex's scalar as loaded (0 without scalars).
    pub vertices: Buffer,
    pub tets: Buffer,
    /// Per tet, a vec4: the absorption colour (rgb), or for the asteroid field the asteroid's
    /// centre and radius.
    pub absorption: Buffer,
    pub tet_count: u32,
    /// The scalar range the shaders map onto [0, 1] (push constants, so changing it uploads
    /// nothing): the mesh's own, until a caller sets another.
    pub scalar_range: (f32, f32),
}

impl GpuTetMesh {
    /// The mesh with its vertex scalars, if it has any, and its per-tet colours (white without).
    pub fn upload(gpu: &Gpu, mesh: &TetMesh) -> Result<GpuTetMesh> {
        let frame = MeshFrame::of(mesh);
        let vertices: Vec<[f32; 4]> = mesh
            .vertices
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                let s = mesh
                    .scalars
                    .as_ref()
                    .and_then(|n| n.get(i))
                    .copied()
                    .unwrap_or(0.0);
                frame.to_world(glam::Vec3::from(v)).extend(s).to_array()
            })
            .collect();
        GpuTetMesh::upload_parts(gpu, mesh, &vertices, &absorption_colours(mesh))
    }

    /// Gives every tet the absorption colour `colour` (an appearance: the geometry stays).
    pub fn write_absorption(&self, gpu: &Gpu, colour: [f32; 3]) -> Result<()> {
        let words = vec![[colour[0], colour[1], colour[2], 0.0f32]; self.tet_count as usize];
        Ok(gpu.write_buffer(&self.absorption, bytemuck::cast_slice(&words))?)
    }

    /// Gives the tets `mesh`'s own colours again (white where it has none).
    pub fn write_absorption_of(&self, gpu: &Gpu, mesh: &TetMesh) -> Result<()> {
        Ok(gpu.write_buffer(
            &self.absorption,
            bytemuck::cast_slice(&absorption_colours(mesh)),
        )?)
    }

    /// Bytes on the GPU.
    pub fn bytes(&self) -> u64 {
        self.vertices.size + self.tets.size + self.absorption.size
    }

    /// An asteroid field: each tet carries its asteroid's sphere ([`asteroid_spheres`]).
    pub fn upload_asteroids(gpu: &Gpu, mesh: &TetMesh) -> Result<GpuTetMesh> {
        let frame = MeshFrame::of(mesh);
        let vertices: Vec<[f32; 4]> = mesh
            .vertices
            .iter()
            .map(|&v| frame.to_world(glam::Vec3::from(v)).extend(0.0).to_array())
            .collect();
        GpuTetMesh::upload_parts(gpu, mesh, &vertices, &asteroid_spheres(mesh))
    }

    fn upload_parts(
        gpu: &Gpu,
        mesh: &TetMesh,
        vertices: &[[f32; 4]],
        absorption: &[[f32; 4]],
    ) -> Result<GpuTetMesh> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(GpuTetMesh {
            vertices: gpu.upload_buffer("tet vertices", bytemuck::cast_slice(vertices), usage)?,
            tets: gpu.upload_buffer("tets", bytemuck::cast_slice(&mesh.tets), usage)?,
            absorption: gpu.upload_buffer(
                "tet absorption",
                bytemuck::cast_slice(absorption),
                usage,
            )?,
            tet_count: mesh.tets.len() as u32,
            scalar_range: scalar_range(mesh).unwrap_or((0.0, 1.0)),
        })
    }
}

/// The mesh's per-tet colours as vec4s, white where it has none.
fn absorption_colours(mesh: &TetMesh) -> Vec<[f32; 4]> {
    match &mesh.absorption {
        Some(a) => a.iter().map(|c| [c[0], c[1], c[2], 0.0]).collect(),
        None => vec![[1.0, 1.0, 1.0, 0.0]; mesh.tets.len()],
    }
}

pub(super) const OPTICAL_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub(super) const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Where a frame accumulates: an RGBA32F attachment the graphics path blends into, or a buffer
/// of four floats per pixel the compute path adds to with atomics.
pub enum OpticalStore {
    /// With a depth attachment for the asteroid field, whose nearest hit wins.
    Image {
        image: Box<Image>,
        readback: Buffer,
        depth: Option<Box<Image>>,
    },
    Buffer(Buffer),
}

/// The per-pixel accumulation of one frame (optical depth, emission or maximum).
pub struct OpticalTarget {
    pub store: OpticalStore,
    pub width: u32,
    pub height: u32,
}

impl OpticalTarget {
    pub fn new(
        gpu: &Gpu,
        width: u32,
        height: u32,
        path: Path,
        with_depth: bool,
    ) -> Result<OpticalTarget> {
        crate::error::check_image_size(width, height)?;
        let bytes = width as u64 * height as u64 * 16;
        let store = match path {
            Path::Graphics => {
                let image = gpu.create_image(
                    "interval accumulation",
                    [width, height, 1],
                    OPTICAL_FORMAT,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::TRANSFER_SRC
                        | vk::ImageUsageFlags::STORAGE,
                    false,
                )?;
                let readback = gpu.create_buffer(
                    "interval accumulation readback",
                    bytes,
                    vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC,
                    MemoryLocation::GpuOnly,
                )?;
                let depth = if with_depth {
                    Some(Box::new(gpu.create_image(
                        "interval depth",
                        [width, height, 1],
                        DEPTH_FORMAT,
                        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                        false,
                    )?))
                } else {
                    None
                };
                OpticalStore::Image {
                    image: Box::new(image),
                    readback,
                    depth,
                }
            }
            Path::Compute => OpticalStore::Buffer(gpu.create_buffer(
                "interval accumulation",
                bytes,
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )?),
        };
        Ok(OpticalTarget {
            store,
            width,
            height,
        })
    }

    /// The accumulated values per pixel, rows top to bottom (rgb; the maximum mode keeps the
    /// largest scalar in r and coverage in g).
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<[f32; 3]>> {
        let bytes = match &self.store {
            OpticalStore::Image {
                image, readback, ..
            } => {
                gpu.submit("copy interval accumulation", |rec| {
                    rec.copy_image_to_buffer(image, readback)
                })?;
                gpu.read_buffer(readback)?
            }
            OpticalStore::Buffer(buffer) => {
                let words: Vec<f32> = gpu.read_buffer_as(buffer)?;
                let pixels = self.width as usize * self.height as usize;
                let at = |i, c| words[optical_index(i, c, pixels)];
                return Ok((0..pixels)
                    .map(|i| [at(i, 0), at(i, 1), at(i, 2)])
                    .collect());
            }
        };
        let texels: Vec<[f32; 4]> = bytemuck::allocation::pod_collect_to_vec(&bytes);
        Ok(texels.into_iter().map(|t| [t[0], t[1], t[2]]).collect())
    }
}

/// Where the compute path keeps channel `channel` of pixel `pixel` of `pixels`, as
/// `optical_layout.glsl` does: a plane per channel.
fn optical_index(pixel: usize, channel: usize, pixels: usize) -> usize {
    channel * pixels + pixel
}
