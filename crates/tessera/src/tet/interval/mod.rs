//! Interval shading of tetrahedral meshes — paper A (Sinclair et al.): a mesh shader turns each
//! tetrahedron into screen-space proxy triangles (3 when its projection is a triangle, 4 when it
//! is a quad) whose vertices carry the inverse view depths of the front and back faces; every
//! fragment then knows the interval its pixel's ray spends in the tet. Here the fragments add
//! length × per-tet absorption into a float target (optical depth, additive blending), and the
//! Beer–Lambert law turns that into transmittance afterwards.
//!
//! Tets crossing the near plane are clipped into 1 or 3 tets, so the camera may be inside the
//! mesh. Not yet: the per-vertex scalar integration, the SDF scene and the compute path.

pub mod compute;

use crate::builtin_shader;
use crate::error::{Error, Result};
use crate::target::PixelTarget;
use bytemuck::{Pod, Zeroable};
use tessera_data::tet::TetMesh;
use tessera_data::{GridFrame, OrbitCamera, Projection, RgbaImage};
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, Image, MemoryLocation, Pipeline, Recorder, RenderTargets,
    ShaderCompiler, Slot, Timer,
};

const OPTICAL_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
/// Tets per mesh workgroup (`interval.mesh.glsl`'s GROUP): 16 leave room for 3 proxies each.
const TETS_PER_WORKGROUP: u32 = 16;

/// Push constants (`tet/interval/params.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct IntervalParams {
    pub world_to_clip: [[f32; 4]; 4],
    pub view: [f32; 4],
    pub counts: [u32; 4],
}

/// A tet mesh on the GPU, placed in world space like the CPU reference places it.
pub struct GpuTetMesh {
    pub vertices: Buffer,
    pub tets: Buffer,
    pub absorption: Buffer,
    pub tet_count: u32,
}

impl GpuTetMesh {
    pub fn upload(gpu: &Gpu, mesh: &TetMesh) -> Result<GpuTetMesh> {
        let frame = tessera_data::tet::optical::MeshFrame::of(mesh);
        let vertices: Vec<[f32; 4]> = mesh
            .vertices
            .iter()
            .map(|&v| frame.to_world(glam::Vec3::from(v)).extend(1.0).to_array())
            .collect();
        let absorption: Vec<[f32; 4]> = match &mesh.absorption {
            Some(a) => a.iter().map(|c| [c[0], c[1], c[2], 0.0]).collect(),
            None => vec![[1.0, 1.0, 1.0, 0.0]; mesh.tets.len()],
        };
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(GpuTetMesh {
            vertices: gpu.upload_buffer("tet vertices", bytemuck::cast_slice(&vertices), usage)?,
            tets: gpu.upload_buffer("tets", bytemuck::cast_slice(&mesh.tets), usage)?,
            absorption: gpu.upload_buffer(
                "tet absorption",
                bytemuck::cast_slice(&absorption),
                usage,
            )?,
            tet_count: mesh.tets.len() as u32,
        })
    }

    pub fn destroy(self, gpu: &Gpu) {
        for b in [self.vertices, self.tets, self.absorption] {
            gpu.destroy_buffer(b);
        }
    }
}

/// The float target optical depth accumulates in, with its readback buffer.
pub struct OpticalTarget {
    pub image: Image,
    readback: Buffer,
    pub width: u32,
    pub height: u32,
}

impl OpticalTarget {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<OpticalTarget> {
        crate::error::check_image_size(width, height)?;
        let image = gpu.create_image(
            "optical depth",
            [width, height, 1],
            OPTICAL_FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::STORAGE,
            false,
        )?;
        let readback = gpu.create_buffer(
            "optical depth readback",
            width as u64 * height as u64 * 16,
            vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        Ok(OpticalTarget {
            image,
            readback,
            width,
            height,
        })
    }

    /// Optical depth per pixel, rows top to bottom.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<[f32; 3]>> {
        gpu.submit("copy optical depth", |rec| {
            rec.copy_image_to_buffer(&self.image, &self.readback)
        })?;
        let texels: Vec<[f32; 4]> =
            bytemuck::allocation::pod_collect_to_vec(&gpu.read_buffer(&self.readback)?);
        Ok(texels.into_iter().map(|t| [t[0], t[1], t[2]]).collect())
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.destroy_image(self.image);
        gpu.destroy_buffer(self.readback);
    }
}

pub struct Interval {
    pipeline: Pipeline,
    composite: Pipeline,
    stats: Buffer,
}

/// Push constants of `beer_lambert.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CompositeParams {
    pub background: [f32; 4],
    pub size: [u32; 4],
}

/// One frame's optical depth, its GPU time and the tets clipped at the near plane.
pub struct IntervalFrame {
    pub optical_depth: Vec<[f32; 3]>,
    pub gpu_ms: f64,
    pub clipped_near: u32,
}

impl Interval {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<Interval> {
        if !gpu.caps().mesh_shader {
            return Err(Error::Invalid(format!(
                "interval shading needs mesh shaders, which {} lacks",
                gpu.caps().device_name
            )));
        }
        let defines = crate::config::common_defines();
        let mesh = compiler.compile(&builtin_shader!("interval.mesh.glsl"), &defines)?;
        let frag = compiler.compile(&builtin_shader!("interval.frag.glsl"), &defines)?;
        let targets = RenderTargets {
            blend_additive: true,
            ..RenderTargets::color(OPTICAL_FORMAT)
        };
        let pipeline = gpu.graphics_pipeline_for(
            "interval shading",
            &[&mesh, &frag],
            &[Slot::StorageBuffer; 4],
            &targets,
        )?;
        let stats = gpu.create_buffer(
            "interval stats",
            16,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let composite = compiler.compile(&builtin_shader!("beer_lambert.comp.glsl"), &defines)?;
        let composite = gpu.compute_pipeline(
            "beer-lambert composite",
            &composite,
            &[Slot::StorageImage, Slot::StorageBuffer],
        )?;
        Ok(Interval {
            pipeline,
            composite,
            stats,
        })
    }

    pub fn params(
        mesh: &GpuTetMesh,
        camera: &OrbitCamera,
        width: u32,
        height: u32,
    ) -> IntervalParams {
        // The volume frame is irrelevant to the world-to-clip transform; any will do.
        let projection =
            Projection::new(camera, &GridFrame::new([2, 2, 2], [1.0; 3]), width, height);
        let (near, _) = Projection::near_far(camera);
        let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
        let tan_x = tan_y * width as f32 / height as f32;
        IntervalParams {
            world_to_clip: projection.world_to_clip.to_cols_array_2d(),
            view: [tan_x, tan_y, 0.0, near],
            counts: [mesh.tet_count, width, height, 0],
        }
    }

    /// Records one frame of optical depth into `target` (cleared first).
    pub fn record(
        &self,
        rec: &Recorder,
        mesh: &GpuTetMesh,
        target: &OpticalTarget,
        params: &IntervalParams,
    ) -> Result<()> {
        rec.fill_buffer(&self.stats, 0);
        rec.barrier();
        rec.discard_to_general(&target.image);
        rec.begin_rendering(&target.image, [0.0; 4]);
        let drawn = rec.draw_mesh_tasks(
            &self.pipeline,
            &[
                Binding::Buffer(&mesh.vertices),
                Binding::Buffer(&mesh.tets),
                Binding::Buffer(&mesh.absorption),
                Binding::Buffer(&self.stats),
            ],
            bytemuck::bytes_of(params),
            // Mesh dispatch limits are not in the capabilities; stay within the guaranteed minimum.
            tessera_gpu::spread_groups(
                mesh.tet_count.div_ceil(TETS_PER_WORKGROUP),
                tessera_gpu::pipeline::MIN_GROUPS_PER_AXIS,
            ),
        );
        rec.end_rendering();
        rec.barrier();
        Ok(drawn?)
    }

    pub fn render(
        &self,
        gpu: &Gpu,
        mesh: &GpuTetMesh,
        target: &OpticalTarget,
        camera: &OrbitCamera,
    ) -> Result<IntervalFrame> {
        let params = Self::params(mesh, camera, target.width, target.height);
        let gpu_ms = crate::bench::time_once(gpu, "interval shading", |rec| {
            self.record(rec, mesh, target, &params)
        })?;
        Ok(IntervalFrame {
            optical_depth: target.read(gpu)?,
            gpu_ms,
            clipped_near: crate::bench::read_words(gpu, &self.stats)?[0],
        })
    }

    /// Records the Beer–Lambert post pass: `background` light through the optical depth in
    /// `target`, packed into `pixels`.
    pub fn record_composite(
        &self,
        rec: &Recorder,
        target: &OpticalTarget,
        pixels: &PixelTarget,
        background: [f32; 3],
    ) {
        let params = CompositeParams {
            background: [background[0], background[1], background[2], 1.0],
            size: [target.width, target.height, 0, 0],
        };
        rec.dispatch(
            &self.composite,
            &[
                Binding::StorageImage(&target.image),
                Binding::Buffer(&pixels.pixels),
            ],
            bytemuck::bytes_of(&params),
            [target.width, target.height, 1],
        );
    }

    /// Renders the mesh as light absorbed on its way from a `background` of that colour.
    pub fn render_image(
        &self,
        gpu: &Gpu,
        mesh: &GpuTetMesh,
        camera: &OrbitCamera,
        (width, height): (u32, u32),
        background: [f32; 3],
    ) -> Result<(RgbaImage, f64)> {
        let target = OpticalTarget::new(gpu, width, height)?;
        let pixels = match PixelTarget::new(gpu, width, height) {
            Ok(p) => p,
            Err(e) => {
                target.destroy(gpu);
                return Err(e);
            }
        };
        let params = Self::params(mesh, camera, width, height);
        let mut timer = Timer::new(gpu, 1)?;
        timer.reset(gpu);
        let mut drawn = Ok(());
        let submitted = gpu.submit("interval shading image", |rec| {
            drawn = timer.scope(rec, "interval", |rec| {
                let r = self.record(rec, mesh, &target, &params);
                self.record_composite(rec, &target, &pixels, background);
                r
            });
        });
        let result = submitted.map_err(Error::from).and(drawn).and_then(|_| {
            Ok((
                pixels.read(gpu)?,
                timer.read_ms(gpu)?.first().map(|s| s.1).unwrap_or(0.0),
            ))
        });
        timer.destroy(gpu);
        target.destroy(gpu);
        pixels.destroy(gpu);
        result
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.destroy_pipeline(self.pipeline);
        gpu.destroy_pipeline(self.composite);
        gpu.destroy_buffer(self.stats);
    }
}
