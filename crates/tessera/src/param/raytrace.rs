//! `sh-raytrace`: SH glyphs ray traced per pixel after Peters et al. 2023 ("Ray Tracing
//! Spherical Harmonics Glyphs", VMV 2023), the method paper E compares its SH-glyph rendering
//! with. One compute pass: per pixel (times `k × k` with supersampling) a ray from the eye walks
//! a uniform grid of glyph cells, tests each glyph's bounding sphere and then finds the first
//! root of the glyph's implicit form written as a polynomial of degree `2k + 2` along the ray
//! (`raytrace_glyph.glsl`, the f32 port of `tessera_data::param::raytrace`, which documents the
//! method and what changes from the paper: the ray coordinate's scale, the normalisation's clamp,
//! per-glyph orders, first root only).
//!
//! Further changes from Peters et al.: glyphs are found through a uniform grid walked by a 3D
//! DDA in a compute shader (`raytrace_trace.glsl`), with an 8-entry mailbox per ray, where the
//! paper traces AABBs of its near-exact bounds with hardware ray tracing; the normal is the
//! central-difference gradient of `|p| - |r(p/|p|)|` in object space (steps of 1/1000 of the
//! radius) instead of the paper's analytic SH gradient; shading is param-points' (two-sided
//! Lambert + ambient, colour by direction, the constants of `tessera_data::param::reference`),
//! so the two techniques' images compare pixel for pixel.
//!
//! Buffers, bindings 0–2 those of every parametric pass (`param/scene.glsl`, from
//! [`GpuParamScene`]): 3 `RtGlyph` per object ([`GpuRtGlyph`]: world-to-object rows, world
//! bounding sphere, object-space bound `B`); 4 the grid (lowest corner, cell size, cells per
//! axis, then `cells + 1` list starts); 5 the glyph indices of every cell; 6 the inverse
//! Vandermonde matrices and monomial bounds of every even order
//! (`tessera_data::param::raytrace::vandermonde_table`); 7 the pixels (probe pass: the raster
//! positions to trace, 8 what they hit).

use super::scene::{scene_defines, sh_recurrence_table, GpuParamScene, ParamScene};
use crate::builtin_shader;
use crate::error::{Error, Result};
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use glam::{DMat3, DVec3, Mat4, Vec3};
use tessera_data::param::raytrace::{
    glyph_bound, vandermonde_stride, vandermonde_table, GlyphGrid, BOUND_DIVISOR,
    MAX_RAYTRACE_ORDER,
};
use tessera_data::param::reference::{AMBIENT, DIFFUSE};
use tessera_data::param::ParamFunction;
use tessera_data::View;
use tessera_data::{OrbitCamera, RgbaImage};
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot,
};

/// Settings of `sh-raytrace`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShRaytraceOptions {
    /// Highest SH order the shaders are built for (even, at most [`MAX_RAYTRACE_ORDER`]): it
    /// sizes their per-ray arrays, so a lower one runs faster; scenes above it are refused.
    pub max_order: u32,
    /// Rays per image pixel along each axis, averaged.
    pub supersample: u32,
    /// Grid cell edge as a multiple of the median glyph bounding diameter.
    pub cell_scale: f32,
}

impl Default for ShRaytraceOptions {
    fn default() -> Self {
        ShRaytraceOptions {
            max_order: 12,
            supersample: 1,
            cell_scale: 1.0,
        }
    }
}

/// Push constants of both passes (`RaytraceParams` in `raytrace_trace.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct RaytraceParams {
    pub eye: [f32; 4],
    pub ray_centre: [f32; 4],
    pub ray_x: [f32; 4],
    pub ray_y: [f32; 4],
    pub light: [f32; 4],
    pub background: [f32; 4],
    pub size: [u32; 2],
    pub supersample: u32,
    pub count: u32,
}

/// `RtGlyph` of `raytrace_trace.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuRtGlyph {
    pub to_object: [[f32; 4]; 3],
    pub sphere: [f32; 4],
    pub shape: [f32; 4],
}

/// What the probe pass's ray hit (`RayHit` of `raytrace_probe.comp.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct RayHit {
    /// World hit point; `w` = distance along the ray from the eye.
    pub position: [f32; 4],
    /// World unit normal, zero where degenerate.
    pub normal: [f32; 4],
    /// Base colour (by direction).
    pub colour: [f32; 4],
    /// The glyph hit, [`RayHit::NONE`] for a miss.
    pub glyph: u32,
    pub pad: [u32; 3],
}

impl RayHit {
    pub const NONE: u32 = u32::MAX;
}

/// Defines of both passes for shaders built for SH orders up to `max_order`.
pub fn raytrace_defines(max_order: u32) -> Vec<(String, String)> {
    let mut d = scene_defines();
    let square = (max_order + 1) * (max_order + 1);
    d.extend([
        ("SHADE_AMBIENT".into(), format!("{AMBIENT:?}")),
        ("SHADE_DIFFUSE".into(), format!("{DIFFUSE:?}")),
        ("RT_MAX_ORDER".into(), max_order.to_string()),
        (
            "RT_TABLE_STRIDE".into(),
            format!("{}u", vandermonde_stride(max_order)),
        ),
        ("RT_TABLE_SQUARE".into(), format!("{square}u")),
        ("RT_BOUND_DIVISOR".into(), format!("{BOUND_DIVISOR:?}")),
    ]);
    d
}

/// A scene of SH glyphs on the GPU with its ray-tracing structures.
pub struct RaytraceScene {
    pub scene: GpuParamScene,
    glyphs: Buffer,
    grid: Buffer,
    items: Buffer,
    pub grid_dims: [u32; 3],
    /// Highest SH order among the glyphs.
    pub max_order: u32,
}

impl RaytraceScene {
    /// Bytes on the GPU.
    pub fn bytes(&self) -> u64 {
        self.scene.bytes() + self.glyphs.size + self.grid.size + self.items.size
    }
}

/// A bound on how far `m`'s linear part stretches any vector: the square root of a Gershgorin
/// bound on the largest eigenvalue of `mᵀm` (exact for rotations of axis scalings).
fn stretch(m: Mat4) -> f32 {
    let a = m.as_dmat4();
    let cols = [
        a.x_axis.truncate(),
        a.y_axis.truncate(),
        a.z_axis.truncate(),
    ];
    let row_sum = |i: usize| cols.iter().map(|c| cols[i].dot(*c).abs()).sum::<f64>();
    ((0..3).map(row_sum).fold(0.0, f64::max).sqrt() * (1.0 + 1e-6)) as f32
}

/// The record of `object` and its world bounding sphere.
fn glyph_record(object: &super::ParamObject, bound: f64) -> (GpuRtGlyph, (Vec3, f32)) {
    let inverse = object.object_to_world.as_dmat4().inverse();
    let row = |i: usize| inverse.row(i).as_vec4().to_array();
    let centre = object.object_to_world.w_axis.truncate();
    let radius = (bound as f32) * stretch(object.object_to_world);
    let record = GpuRtGlyph {
        to_object: [row(0), row(1), row(2)],
        sphere: centre.extend(radius).to_array(),
        shape: [bound as f32, 0.0, 0.0, 0.0],
    };
    (record, (centre, radius))
}

/// The rays of `view`'s own matrix, in f64: its centre of projection and the matrix taking
/// `(ndc.x, ndc.y, 1)` to the (unnormalised) direction through that NDC point. Only the rows of
/// clip x, y and w matter for rays; unprojecting through the depth row instead moves the rays
/// by ~1e-4 rad, the f32 rounding of that row amplified.
pub fn camera_rays(view: &View) -> (DVec3, DMat3) {
    let m = view.world_to_clip.as_dmat4();
    let rows = [m.row(0), m.row(1), m.row(3)];
    let a =
        DMat3::from_cols(rows[0].truncate(), rows[1].truncate(), rows[2].truncate()).transpose();
    let inverse = a.inverse();
    let centre = -(inverse * DVec3::new(rows[0].w, rows[1].w, rows[2].w));
    (centre, inverse)
}

/// Storage buffers holding `data`, all or none.
fn upload_all<const N: usize>(gpu: &Gpu, data: [(&str, &[u8]); N]) -> Result<[Buffer; N]> {
    let mut buffers = Vec::with_capacity(N);
    for (name, bytes) in data {
        buffers.push(gpu.upload_buffer(name, bytes, vk::BufferUsageFlags::STORAGE_BUFFER)?);
    }
    match buffers.try_into() {
        Ok(all) => Ok(all),
        Err(_) => unreachable!("one buffer was pushed per entry"),
    }
}

pub struct ShRaytrace {
    render: Pipeline,
    probe: Pipeline,
    sh_table: Buffer,
    vandermonde: Buffer,
    options: ShRaytraceOptions,
}

impl ShRaytrace {
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        options: ShRaytraceOptions,
    ) -> Result<ShRaytrace> {
        let usable = options.max_order.is_multiple_of(2)
            && options.max_order <= MAX_RAYTRACE_ORDER
            && (1..=8).contains(&options.supersample)
            && options.cell_scale > 0.0
            && options.cell_scale.is_finite();
        if !usable {
            return Err(Error::Invalid(format!(
                "sh-raytrace needs an even max_order up to {MAX_RAYTRACE_ORDER}, supersampling in \
                 1..=8 and a positive cell scale, got {options:?}"
            )));
        }
        let defines = raytrace_defines(options.max_order);
        let render = compiler.compile(&builtin_shader!("raytrace.comp.glsl"), &defines)?;
        let probe = compiler.compile(&builtin_shader!("raytrace_probe.comp.glsl"), &defines)?;
        let render = gpu.compute_pipeline("sh-raytrace", &render, &[Slot::StorageBuffer; 8])?;
        let probe = gpu.compute_pipeline("sh-raytrace probe", &probe, &[Slot::StorageBuffer; 9])?;
        let recurrence = sh_recurrence_table();
        let vandermonde = vandermonde_table(options.max_order);
        let tables = upload_all(
            gpu,
            [
                (
                    "sh-raytrace sh recurrence",
                    bytemuck::cast_slice(&recurrence),
                ),
                (
                    "sh-raytrace vandermonde",
                    bytemuck::cast_slice(&vandermonde),
                ),
            ],
        );
        match tables {
            Ok([sh_table, vandermonde]) => Ok(ShRaytrace {
                render,
                probe,
                sh_table,
                vandermonde,
                options,
            }),
            Err(e) => Err(e),
        }
    }

    pub fn options(&self) -> &ShRaytraceOptions {
        &self.options
    }

    /// Uploads `scene`, which must hold SH glyphs of orders up to the options' `max_order`
    /// only, with the glyph records and the grid.
    pub fn prepare(&self, gpu: &Gpu, scene: &ParamScene) -> Result<RaytraceScene> {
        let mut records = Vec::with_capacity(scene.objects.len());
        let mut spheres = Vec::with_capacity(scene.objects.len());
        let mut max_order = 0;
        for (i, o) in scene.objects.iter().enumerate() {
            let g = match &o.function {
                ParamFunction::ShGlyph(g) => g,
                other => {
                    let kind = match other {
                        ParamFunction::Sphere => "a sphere",
                        ParamFunction::Heart => "a heart",
                        ParamFunction::Seashell(_) => "a seashell",
                        _ => "a yarn tube",
                    };
                    return Err(Error::Invalid(format!(
                        "sh-raytrace draws SH glyphs only, but object {i} is {kind}"
                    )));
                }
            };
            if g.order() > self.options.max_order {
                return Err(Error::Invalid(format!(
                    "object {i}: SH order {} exceeds sh-raytrace's max_order {} (raise it, up to \
                     {MAX_RAYTRACE_ORDER})",
                    g.order(),
                    self.options.max_order
                )));
            }
            max_order = max_order.max(g.order());
            let (record, sphere) = glyph_record(o, glyph_bound(g));
            records.push(record);
            spheres.push(sphere);
        }
        // The upload validates the transforms (finite, affine, invertible) before they are used.
        let uploaded = GpuParamScene::upload(gpu, scene)?;
        let grid = GlyphGrid::build(&spheres, self.options.cell_scale)?;
        let mut header: Vec<u32> = [grid.lo, grid.cell]
            .iter()
            .flat_map(|v| v.extend(0.0).to_array().map(f32::to_bits))
            .collect();
        header.extend(grid.dims);
        header.push(0);
        header.extend(&grid.cell_start);
        let [glyphs, grid_buffer, items] = upload_all(
            gpu,
            [
                ("sh-raytrace glyphs", bytemuck::cast_slice(&records)),
                ("sh-raytrace grid", bytemuck::cast_slice(&header)),
                ("sh-raytrace grid items", bytemuck::cast_slice(&grid.items)),
            ],
        )?;
        Ok(RaytraceScene {
            scene: uploaded,
            glyphs,
            grid: grid_buffer,
            items,
            grid_dims: grid.dims,
            max_order,
        })
    }

    /// The view of `camera` onto `scene` at `size` with this technique's supersampling.
    pub fn view(
        &self,
        scene: &RaytraceScene,
        camera: &OrbitCamera,
        size: (u32, u32),
    ) -> Result<View> {
        scene.scene.view(camera, size, self.options.supersample)
    }

    fn params(view: &View, background: [f32; 3], count: u32) -> RaytraceParams {
        let (eye, rays) = camera_rays(view);
        let v = |d: DVec3| d.as_vec3().extend(0.0).to_array();
        RaytraceParams {
            eye: eye.as_vec3().extend(1.0).to_array(),
            ray_centre: v(rays.z_axis),
            ray_x: v(rays.x_axis),
            ray_y: v(rays.y_axis),
            light: view.light.extend(0.0).to_array(),
            background: [background[0], background[1], background[2], 1.0],
            size: [view.size.0, view.size.1],
            supersample: view.supersample,
            count,
        }
    }

    fn bindings<'a>(&'a self, scene: &'a RaytraceScene) -> [Binding<'a>; 7] {
        [
            Binding::Buffer(&scene.scene.objects),
            Binding::Buffer(&scene.scene.values),
            Binding::Buffer(&self.sh_table),
            Binding::Buffer(&scene.glyphs),
            Binding::Buffer(&scene.grid),
            Binding::Buffer(&scene.items),
            Binding::Buffer(&self.vandermonde),
        ]
    }

    /// A scene prepared by an instance built for higher orders would be cut to this one's.
    pub fn check_scene(&self, scene: &RaytraceScene) -> Result<()> {
        if scene.max_order > self.options.max_order {
            return Err(Error::Invalid(format!(
                "sh-raytrace built for SH order {} cannot draw a scene of order {}",
                self.options.max_order, scene.max_order
            )));
        }
        Ok(())
    }

    /// Records the image pass: `scene` from `view` into `target` (of the view's image size).
    /// `scene` must not exceed the options' `max_order` ([`Self::render_into`] checks).
    pub fn record(
        &self,
        rec: &Recorder,
        scene: &RaytraceScene,
        view: &View,
        target: &Target,
        background: [f32; 3],
    ) {
        let params = Self::params(view, background, 0);
        let [a, b, c, d, e, f, g] = self.bindings(scene);
        let bindings = [a, b, c, d, e, f, g, Binding::Buffer(&target.pixels)];
        rec.dispatch(
            &self.render,
            &bindings,
            bytemuck::bytes_of(&params),
            [view.size.0, view.size.1, 1],
        );
        rec.barrier();
    }

    /// Renders into `target` and returns the GPU milliseconds of the pass.
    pub fn render_into(
        &self,
        gpu: &Gpu,
        scene: &RaytraceScene,
        view: &View,
        target: &Target,
        background: [f32; 3],
    ) -> Result<f64> {
        self.check_scene(scene)?;
        if (target.width, target.height) != view.size {
            return Err(Error::Invalid(format!(
                "sh-raytrace: a {}x{} target for a {:?} view",
                target.width, target.height, view.size
            )));
        }
        tessera_gpu::timing::time_once(gpu, "sh-raytrace", |rec| {
            self.record(rec, scene, view, target, background);
            Ok(())
        })
    }

    /// Renders `scene` from `camera` at `size` in front of `background`: the image and the GPU
    /// milliseconds of the frame.
    pub fn render_image(
        &self,
        gpu: &Gpu,
        scene: &RaytraceScene,
        camera: &OrbitCamera,
        size: (u32, u32),
        background: [f32; 3],
    ) -> Result<(RgbaImage, f64)> {
        let view = self.view(scene, camera, size)?;
        let target = Target::new(gpu, size.0, size.1)?;
        let ms = self.render_into(gpu, scene, &view, &target, background)?;
        Ok((target.read(gpu)?, ms))
    }

    /// Traces the camera rays through raster positions `raster` (pixel `(i, j)`'s centre is
    /// `(i + 0.5, j + 0.5)`, times the supersampling) as the image pass does.
    pub fn probe(
        &self,
        gpu: &Gpu,
        scene: &RaytraceScene,
        view: &View,
        raster: &[[f32; 2]],
    ) -> Result<Vec<RayHit>> {
        self.check_scene(scene)?;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
        let padded = if raster.is_empty() {
            &[[0.0; 2]][..]
        } else {
            raster
        };
        let input = gpu.upload_buffer("sh-raytrace probes", bytemuck::cast_slice(padded), usage)?;
        let bytes = (padded.len() * std::mem::size_of::<RayHit>()) as u64;
        let usage = usage | vk::BufferUsageFlags::TRANSFER_DST;
        let output =
            gpu.create_buffer("sh-raytrace hits", bytes, usage, MemoryLocation::GpuOnly)?;
        let params = Self::params(view, [0.0; 3], raster.len() as u32);
        let [a, b, c, d, e, f, g] = self.bindings(scene);
        let bindings = [
            a,
            b,
            c,
            d,
            e,
            f,
            g,
            Binding::Buffer(&input),
            Binding::Buffer(&output),
        ];
        let result = gpu
            .submit("sh-raytrace probe", |rec| {
                // Poisoned, so that a probe the shader never answers cannot pass for a miss.
                rec.fill_buffer(&output, 0x7fc0_dead);
                rec.barrier();
                let threads = [raster.len() as u32, 1, 1];
                rec.dispatch(&self.probe, &bindings, bytemuck::bytes_of(&params), threads);
            })
            .map_err(Error::from)
            .and_then(|_| Ok(gpu.read_elements::<RayHit>(&output, raster.len())?));
        result
    }
}
