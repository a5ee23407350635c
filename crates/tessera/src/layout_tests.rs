//! Every host struct the shaders read or write, held to the shader's SPIR-V layout: each
//! member's offset by name, and the push-constant size. One table for the whole crate, and a
//! check that every `#[repr(C)]` struct in the sources is in it, so a new struct cannot go
//! unchecked. Compiles GLSL only; needs no device.

use crate::builtin_shader;
use crate::config::volume_defines;
use crate::path::Path;
use crate::tet::interval::{Interval, IntervalOptions, TileCapacity};
use std::collections::BTreeSet;
use std::mem::{offset_of, size_of};
use tessera_data::ScalarType;
use tessera_gpu::{Source, Spirv, PUSH_CONSTANT_BYTES};

/// One struct against one shader.
struct Check {
    /// The host type's full path (`std::any::type_name`).
    host_type: &'static str,
    spirv: Spirv,
    /// The block or struct name in the shader.
    block: &'static str,
    host: Vec<(String, usize)>,
    /// Bytes the host struct takes, checked against the push-constant limit when it is
    /// passed as push constants.
    push_constant_bytes: Option<usize>,
}

macro_rules! host {
    ($t:ty, $($f:ident),*) => {
        (
            std::any::type_name::<$t>(),
            vec![$((stringify!($f).to_string(), offset_of!($t, $f))),*],
        )
    };
}

fn compile(source: &Source, defines: &[(String, String)]) -> Spirv {
    crate::shaders::compiler()
        .compile(source, defines)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Member names and offsets of `block` in `spirv`, padding left out. A struct also copied
/// into locals has a second, undecorated SPIR-V type of the same name; the first is the one
/// the buffer or push-constant block uses.
fn members(spirv: &Spirv, block: &str) -> Option<Vec<(String, usize)>> {
    let found = tessera_gpu::spirv::struct_offsets(&spirv.words, block)?;
    Some(
        found
            .into_iter()
            .filter(|(name, _)| !name.starts_with("pad"))
            .map(|(name, offset)| (name, offset as usize))
            .collect(),
    )
}

struct Table(Vec<Check>);

impl Table {
    fn push_constants<T>(&mut self, spirv: &Spirv, block: &'static str, host: HostLayout) {
        self.add(spirv, block, host, Some(size_of::<T>()));
    }

    fn buffer(&mut self, spirv: &Spirv, block: &'static str, host: HostLayout) {
        self.add(spirv, block, host, None);
    }

    fn add(
        &mut self,
        spirv: &Spirv,
        block: &'static str,
        (host_type, host): HostLayout,
        push_constant_bytes: Option<usize>,
    ) {
        self.0.push(Check {
            host_type,
            spirv: spirv.clone(),
            block,
            host: host.into_iter().filter(|(n, _)| n != "pad").collect(),
            push_constant_bytes,
        });
    }
}

type HostLayout = (&'static str, Vec<(String, usize)>);

fn isosurface_structs(t: &mut Table) {
    use crate::iso::direct::block_list::BlockListHeader;
    use crate::iso::direct::compute::{ReprojectParams, ResolveParams};
    use crate::iso::direct::compute_cull::HzbTestParams;
    use crate::iso::direct::stereo::StereoViews;
    use crate::iso::direct::DirectParams;
    use crate::iso::minmax::{block_defines, rows_defines, BlockParams, GroupParams, LevelsParams};
    use crate::iso::raymarch::RaymarchParams;
    let u8_defines = crate::config::marching_cubes_defines(ScalarType::U8, Default::default());
    let raymarch = compile(
        &builtin_shader!("iso/raymarch/raymarch.comp.glsl"),
        &u8_defines,
    );
    #[rustfmt::skip]
    t.push_constants::<RaymarchParams>(&raymarch, "RaymarchParams", host!(RaymarchParams, eye,
        isovalue, forward, tan_half_fov_x, right, tan_half_fov_y, up, light, grid_to_world, dims,
        octree_levels, image));
    let extract_defines =
        crate::iso::direct::compute::extract_defines(ScalarType::U8, Default::default());
    let extract = compile(
        &builtin_shader!("iso/direct/extract.comp.glsl"),
        &extract_defines,
    );
    #[rustfmt::skip]
    t.push_constants::<DirectParams>(&extract, "DirectParams", host!(DirectParams, grid_to_clip,
        eye_world, isovalue, grid_to_world, light, dims, triangle_capacity));
    let mut list_defines = extract_defines.clone();
    list_defines.push(("BLOCK_LIST".into(), "1".into()));
    let extract_list = compile(
        &builtin_shader!("iso/direct/extract.comp.glsl"),
        &list_defines,
    );
    let cull_setup = compile(
        &builtin_shader!("iso/direct/cull_setup.comp.glsl"),
        &u8_defines,
    );
    for spirv in [&extract_list, &cull_setup] {
        t.buffer(
            spirv,
            "BlockListHeader",
            host!(BlockListHeader, count, args),
        );
    }
    let mut multiview_defines = u8_defines.clone();
    multiview_defines
        .extend([("MULTIVIEW", "1"), ("BLOCK_LIST", "0")].map(|(k, v)| (k.into(), v.into())));
    let multiview = compile(
        &builtin_shader!("iso/direct/direct.mesh.glsl"),
        &multiview_defines,
    );
    t.buffer(
        &multiview,
        "Views",
        host!(StereoViews, grid_to_clip, eye_world),
    );
    let resolve = compile(
        &builtin_shader!("iso/direct/resolve.comp.glsl"),
        &u8_defines,
    );
    t.push_constants::<ResolveParams>(
        &resolve,
        "ResolveParams",
        host!(ResolveParams, eye_world, light, size),
    );
    let reproject = compile(
        &builtin_shader!("iso/direct/reproject.comp.glsl"),
        &u8_defines,
    );
    t.push_constants::<ReprojectParams>(
        &reproject,
        "ReprojectParams",
        host!(ReprojectParams, world_to_clip, capacity),
    );
    let hzb_test = compile(
        &builtin_shader!("iso/direct/hzb_test.comp.glsl"),
        &u8_defines,
    );
    t.push_constants::<HzbTestParams>(
        &hzb_test,
        "HzbTestParams",
        host!(HzbTestParams, grid_to_clip, dims, size, iso),
    );
    let blocks = compile(
        &builtin_shader!("iso/minmax/minmax_blocks.comp.glsl"),
        &block_defines(ScalarType::U16, false),
    );
    t.push_constants::<BlockParams>(
        &blocks,
        "BlockParams",
        host!(BlockParams, volume_dims, block_dims),
    );
    let rows = compile(
        &builtin_shader!("iso/minmax/minmax_rows.comp.glsl"),
        &rows_defines(ScalarType::U16),
    );
    t.push_constants::<BlockParams>(
        &rows,
        "BlockParams",
        host!(BlockParams, volume_dims, block_dims),
    );
    let groups = compile(
        &builtin_shader!("iso/minmax/minmax_groups.comp.glsl"),
        &crate::config::volume_defines(ScalarType::U16),
    );
    t.push_constants::<GroupParams>(
        &groups,
        "GroupParams",
        host!(GroupParams, volume_dims, block_dims, parent_dims),
    );
    let levels = compile(
        &builtin_shader!("iso/minmax/minmax_levels.comp.glsl"),
        &volume_defines(ScalarType::U16),
    );
    t.push_constants::<LevelsParams>(
        &levels,
        "LevelsParams",
        host!(LevelsParams, child_level, level_count),
    );
}

fn meshlet_structs(t: &mut Table) {
    use crate::iso::direct::block_list::BlockListHeader;
    use crate::iso::meshlets::{MeshletCounters, MeshletParams};
    use tessera_data::meshlets::Meshlet;
    let defines = crate::config::meshlet_defines(
        ScalarType::U8,
        Default::default(),
        crate::iso::meshlets::ExtractionPath::Compute,
        true,
    );
    let extract = compile(&builtin_shader!("iso/meshlets/extract.comp.glsl"), &defines);
    let occupied = compile(
        &builtin_shader!("iso/meshlets/occupied.comp.glsl"),
        &defines,
    );
    for spirv in [&extract, &occupied] {
        #[rustfmt::skip]
        t.push_constants::<MeshletParams>(spirv, "MeshletParams", host!(MeshletParams,
            volume_dims, isovalue, block_dims, meshlet_capacity, vertex_capacity,
            triangle_capacity));
        t.buffer(
            spirv,
            "BlockListHeader",
            host!(BlockListHeader, count, args),
        );
    }
    #[rustfmt::skip]
    t.buffer(&extract, "Meshlet", host!(Meshlet, vertex_offset, triangle_offset, counts,
        aabb_min, aabb_max, subblock));
    t.buffer(
        &extract,
        "MeshletCounters",
        host!(MeshletCounters, meshlets, vertices, triangles, overflow),
    );
}

fn meshlet_draw_structs(t: &mut Table) {
    use crate::iso::meshlet_draw::{DrawCounters, MeshletDrawParams};
    let defines = crate::config::meshlet_draw_defines();
    let triangles = compile(
        &builtin_shader!("iso/meshlet_draw/triangles.comp.glsl"),
        &defines,
    );
    #[rustfmt::skip]
    t.push_constants::<MeshletDrawParams>(&triangles, "MeshletDrawParams", host!(
        MeshletDrawParams, grid_to_clip, eye_world, bounds, grid_to_world, frame_width, light,
        frame_height, dims, triangle_capacity));
    t.buffer(
        &triangles,
        "DrawCounters",
        host!(DrawCounters, meshlets_drawn, triangles_drawn),
    );
}

fn pmb_structs(t: &mut Table) {
    use crate::iso::pmb::{PmbCounters, PmbParams};
    use tessera_data::pmb::{PmbBlock, PmbBlockSize};
    let defines = crate::config::pmb_defines(
        ScalarType::U8,
        Default::default(),
        PmbBlockSize::B884,
        128,
        true,
    );
    let extract = compile(&builtin_shader!("iso/pmb/extract.comp.glsl"), &defines);
    #[rustfmt::skip]
    t.push_constants::<PmbParams>(&extract, "PmbParams", host!(PmbParams, volume_dims,
        isovalue, block_dims, vertex_capacity, node_dims, triangle_capacity));
    t.buffer(
        &extract,
        "PmbCounters",
        host!(PmbCounters, blocks, vertices, triangles, overflow),
    );
    #[rustfmt::skip]
    t.buffer(&extract, "PmbBlock", host!(PmbBlock, block, first_vertex, vertex_count,
        first_index, triangle_count));
}

fn pmb_draw_structs(t: &mut Table) {
    use crate::iso::meshlet_draw::MeshletDrawParams;
    use crate::iso::pmb_draw::{DrawIndexedIndirectCommand, PmbDrawCounters};
    use tessera_data::pmb::PmbBlockSize;
    let defines = crate::config::pmb_draw_defines(PmbBlockSize::B844);
    let triangles = compile(
        &builtin_shader!("iso/pmb_draw/triangles.comp.glsl"),
        &defines,
    );
    let commands = compile(
        &builtin_shader!("iso/pmb_draw/commands.comp.glsl"),
        &defines,
    );
    for spirv in [&triangles, &commands] {
        #[rustfmt::skip]
        t.push_constants::<MeshletDrawParams>(spirv, "MeshletDrawParams", host!(
            MeshletDrawParams, grid_to_clip, eye_world, bounds, grid_to_world, frame_width,
            light, frame_height, dims, triangle_capacity));
        t.buffer(
            spirv,
            "PmbDrawCounters",
            host!(PmbDrawCounters, blocks_drawn, triangles_drawn),
        );
    }
    #[rustfmt::skip]
    t.buffer(&commands, "DrawIndexedIndirectCommand", host!(DrawIndexedIndirectCommand,
        index_count, instance_count, first_index, vertex_offset, first_instance));
}

fn raster_structs(t: &mut Table) {
    use crate::raster::hzb::HzbBuildParams;
    use crate::raster::indirect::PrepareParams;
    use crate::raster::{raster_defines, RasterCounts, RasterParams, RasterTriangle};
    let raster = compile(
        &builtin_shader!("raster/raster.comp.glsl"),
        &raster_defines(),
    );
    t.push_constants::<RasterParams>(
        &raster,
        "RasterParams",
        host!(RasterParams, size, capacity, index_base),
    );
    t.buffer(&raster, "RasterTriangle", host!(RasterTriangle, clip));
    let prepare = compile(&builtin_shader!("raster/raster_prepare.comp.glsl"), &[]);
    t.buffer(
        &prepare,
        "Counts",
        host!(RasterCounts, triangle_count, dispatch),
    );
    t.push_constants::<PrepareParams>(
        &prepare,
        "PrepareParams",
        host!(PrepareParams, max_groups, group_size),
    );
    let hzb = compile(
        &builtin_shader!("raster/hzb_build.comp.glsl"),
        &crate::raster::hzb::build_defines(),
    );
    t.push_constants::<HzbBuildParams>(
        &hzb,
        "HzbBuildParams",
        host!(HzbBuildParams, size, first_level, level_count),
    );
}

fn interval_structs(t: &mut Table) {
    use crate::tet::interval::composite::{composite_defines, CompositeParams};
    use crate::tet::interval::compute::compute_defines;
    use crate::tet::interval::IntervalParams;
    let defines = Interval::defines(&IntervalOptions::new(Path::Compute));
    let raster = compile(
        &builtin_shader!("tet/interval/interval_raster.comp.glsl"),
        &compute_defines(&defines, TileCapacity::default()),
    );
    #[rustfmt::skip]
    t.push_constants::<IntervalParams>(&raster, "IntervalParams", host!(IntervalParams,
        world_to_clip, tan_half_fov, near_depth, counts, eye, scalar_range));
    let composite = compile(
        &builtin_shader!("tet/interval/composite.comp.glsl"),
        &composite_defines(&defines, Path::Compute),
    );
    t.push_constants::<CompositeParams>(
        &composite,
        "CompositeParams",
        host!(CompositeParams, background, size),
    );
}

fn shell_structs(t: &mut Table) {
    use crate::tet::shell::{
        defines, GpuRay, RayResult, ShellOptions, ShellParams, VisitedTet, RECORDED_STEPS,
    };
    use tessera_data::tet::shell::{BvhNode, LayoutKind};
    let options = ShellOptions::new(LayoutKind::Tet20);
    let mut defines = defines(&options, 256);
    defines.push(("RECORDED_STEPS".into(), RECORDED_STEPS.to_string()));
    let rays = compile(&builtin_shader!("tet/shell/shell_rays.comp.glsl"), &defines);
    #[rustfmt::skip]
    t.push_constants::<ShellParams>(&rays, "ShellParams", host!(ShellParams,
        eye, near_depth, forward, tan_half_fov_x, right, tan_half_fov_y, up, max_steps,
        background, tet_count, scalar_range, size, vertex_count));
    t.buffer(&rays, "BvhNode", host!(BvhNode, lo, first, hi, count));
    t.buffer(&rays, "ShellRay", host!(GpuRay, origin, t_min, dir, t_max));
    #[rustfmt::skip]
    t.buffer(&rays, "RayResult", host!(RayResult, colour, steps, transmittance, segments));
    t.buffer(&rays, "VisitedTet", host!(VisitedTet, tet, segment));
    use crate::tet::shell::effects::{effect_defines, pass_defines, EffectParams, LightingPass};
    let effects = tessera_data::tet::shell::ShellEffects {
        gradient: true,
        ..Default::default()
    };
    let mut lighting_defines = crate::tet::shell::defines(&options, 256);
    lighting_defines.extend(effect_defines(&effects));
    lighting_defines.extend(pass_defines(&effects, LightingPass::Gradients));
    let lighting = compile(
        &builtin_shader!("tet/shell/lighting.comp.glsl"),
        &lighting_defines,
    );
    // The host's trailing padding has no shader member.
    #[rustfmt::skip]
    t.buffer(&lighting, "EffectParams", host!(EffectParams, light, ground, ao_radius,
        max_absorption));
}

fn parametric_structs(t: &mut Table) {
    use crate::param::lod::{lod_defines, GpuPatch, LodParams, LodSample, PrepareParams};
    use crate::param::points::{points_defines, PointsParams, ResolveParams};
    use crate::param::raytrace::{raytrace_defines, GpuRtGlyph, RayHit, RaytraceParams};
    use crate::param::scene::GpuObject;
    use crate::param::tess::{ArgsParams, DownsampleParams, TessParams};
    use crate::param::ProbeResult;
    let (lod, points) = (lod_defines(), points_defines());
    let step = compile(&builtin_shader!("param/lod_step.comp.glsl"), &lod);
    #[rustfmt::skip]
    t.push_constants::<LodParams>(&step, "LodParams", host!(LodParams, world_to_clip, viewport,
        thresholds, step, last, eval_capacity, render_capacity, culling, capture_capacity,
        object_count, pre_split));
    t.buffer(&step, "LodSample", host!(LodSample, object, u, v, x, y));
    let prepare = compile(&builtin_shader!("param/lod_prepare.comp.glsl"), &lod);
    t.push_constants::<PrepareParams>(
        &prepare,
        "PrepareParams",
        host!(
            PrepareParams,
            max_groups,
            entry,
            capacity,
            per_group,
            spread_target
        ),
    );
    // `init` only indexes its buffers, so the first type of each name is the buffer's.
    let init = compile(&builtin_shader!("param/lod_init.comp.glsl"), &lod);
    #[rustfmt::skip]
    t.buffer(&init, "ParamObject", host!(GpuObject, model, colour, domain, radius_map, kind,
        params, order, flags));
    t.buffer(&init, "Patch", host!(GpuPatch, u, v, extent, object, info));
    let draw = compile(&builtin_shader!("param/points.comp.glsl"), &points);
    #[rustfmt::skip]
    t.push_constants::<PointsParams>(&draw, "PointsParams", host!(PointsParams, world_to_clip,
        viewport, density, max_side, raster, uv_bits, render_capacity, footprint));
    let resolve = compile(&builtin_shader!("param/resolve.comp.glsl"), &points);
    #[rustfmt::skip]
    t.push_constants::<ResolveParams>(&resolve, "ResolveParams", host!(ResolveParams, eye, light,
        background, size, supersample, uv_bits));
    let probe = compile(&builtin_shader!("param/probe.comp.glsl"), &points);
    t.buffer(
        &probe,
        "ProbeResult",
        host!(ProbeResult, position, normal, colour),
    );
    let control = compile(&builtin_shader!("param/tess.tesc.glsl"), &points);
    #[rustfmt::skip]
    t.push_constants::<TessParams>(&control, "TessParams", host!(TessParams, world_to_clip, eye,
        light, viewport, pixels_per_segment, fixed_level, min_level, max_level, render_capacity,
        patches_per_instance));
    let downsample = compile(&builtin_shader!("param/tess_downsample.comp.glsl"), &points);
    t.push_constants::<DownsampleParams>(
        &downsample,
        "DownsampleParams",
        host!(DownsampleParams, size, supersample),
    );
    let args = compile(&builtin_shader!("param/tess_args.comp.glsl"), &points);
    t.push_constants::<ArgsParams>(
        &args,
        "TessArgsParams",
        host!(ArgsParams, render_capacity, patches_per_instance),
    );
    let rt = raytrace_defines(12);
    let render = compile(&builtin_shader!("param/raytrace.comp.glsl"), &rt);
    let rt_probe = compile(&builtin_shader!("param/raytrace_probe.comp.glsl"), &rt);
    for spirv in [&render, &rt_probe] {
        #[rustfmt::skip]
        t.push_constants::<RaytraceParams>(spirv, "RaytraceParams", host!(RaytraceParams, eye,
            ray_centre, ray_x, ray_y, light, background, size, supersample, count));
    }
    t.buffer(
        &render,
        "RtGlyph",
        host!(GpuRtGlyph, to_object, sphere, shape),
    );
    t.buffer(
        &rt_probe,
        "RayHit",
        host!(RayHit, position, normal, colour, glyph),
    );
}

fn throughput_structs(t: &mut Table) {
    use crate::throughput::arithmetic::ArithmeticParams;
    use crate::throughput::shader_defines;
    use crate::throughput::triangles::TriangleParams;
    let defines = shader_defines();
    for spirv in [
        compile(&builtin_shader!("throughput/busy.frag.glsl"), &defines),
        compile(&builtin_shader!("throughput/busy.comp.glsl"), &defines),
    ] {
        t.push_constants::<ArithmeticParams>(
            &spirv,
            "ArithmeticParams",
            host!(ArithmeticParams, size, iterations),
        );
    }
    for spirv in [
        compile(&builtin_shader!("throughput/grid.mesh.glsl"), &defines),
        compile(&builtin_shader!("throughput/splat.comp.glsl"), &defines),
    ] {
        t.push_constants::<TriangleParams>(
            &spirv,
            "TriangleParams",
            host!(TriangleParams, size, triangles),
        );
    }
}

fn table() -> Table {
    let mut t = Table(Vec::new());
    isosurface_structs(&mut t);
    meshlet_structs(&mut t);
    meshlet_draw_structs(&mut t);
    pmb_structs(&mut t);
    pmb_draw_structs(&mut t);
    raster_structs(&mut t);
    interval_structs(&mut t);
    shell_structs(&mut t);
    parametric_structs(&mut t);
    throughput_structs(&mut t);
    t
}

/// The `#[repr(C)]` structs of this crate's sources, as `tessera::module::Name` paths.
fn repr_c_structs() -> BTreeSet<String> {
    fn walk(dir: &std::path::Path, module: &str, found: &mut BTreeSet<String>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for path in entries {
            let stem = path.file_stem().unwrap().to_string_lossy().to_string();
            if path.is_dir() {
                walk(&path, &format!("{module}::{stem}"), found);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") || stem.ends_with("tests") {
                continue;
            }
            let here = match stem.as_str() {
                "mod" | "lib" => module.to_string(),
                _ => format!("{module}::{stem}"),
            };
            let text = std::fs::read_to_string(&path).unwrap();
            let mut lines = text.lines();
            while let Some(line) = lines.next() {
                if line.trim() != "#[repr(C)]" {
                    continue;
                }
                let declared = lines.by_ref().find(|l| !l.trim().starts_with("#["));
                if let Some(name) = declared
                    .and_then(|l| l.split("struct ").nth(1))
                    .and_then(|rest| rest.split([' ', '{', '<', '(']).next())
                {
                    found.insert(format!("{here}::{name}"));
                }
            }
        }
    }
    let mut found = BTreeSet::new();
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    walk(&src, "tessera", &mut found);
    found
}

#[test]
fn every_host_struct_matches_its_shader() {
    let table = table();
    let mut wrong = Vec::new();
    for check in &table.0 {
        match members(&check.spirv, check.block) {
            None => wrong.push(format!(
                "{}: no struct {} in the SPIR-V",
                check.host_type, check.block
            )),
            Some(found) if found != check.host => wrong.push(format!(
                "{} vs the shader's {}:\n  host   {:?}\n  shader {:?}",
                check.host_type, check.block, check.host, found
            )),
            Some(_) => {}
        }
        if let Some(bytes) = check.push_constant_bytes {
            if bytes > PUSH_CONSTANT_BYTES as usize {
                wrong.push(format!(
                    "{}: {bytes} bytes of push constants",
                    check.host_type
                ));
            }
        }
    }
    let checked: BTreeSet<String> = table.0.iter().map(|c| c.host_type.to_string()).collect();
    for unchecked in repr_c_structs().difference(&checked) {
        wrong.push(format!(
            "{unchecked}: #[repr(C)] but not in the layout table"
        ));
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
