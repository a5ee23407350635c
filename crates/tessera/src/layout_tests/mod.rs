//! Every host struct the shaders read or write, held to the shader's SPIR-V layout: each
//! member's offset by name, and the push-constant size. One table for the whole crate, and a
//! check that every `#[repr(C)]` struct in the sources is in it, so a new struct cannot go
//! unchecked. Compiles GLSL only; needs no device.

use crate::builtin_shader;
use crate::path::Path;
use crate::tet::interval::{Interval, IntervalOptions, SubgroupDraw, TileCapacity};
use std::collections::BTreeSet;
use std::mem::{offset_of, size_of};
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

mod iso;

fn raster_structs(t: &mut Table) {
    use crate::raster::hzb::HzbBuildParams;
    use crate::raster::indirect::PrepareParams;
    use crate::raster::{raster_defines, RasterCounts, RasterParams, RasterTriangle};
    let raster = compile(
        &builtin_shader!("../raster/raster.comp.glsl"),
        &raster_defines(),
    );
    t.push_constants::<RasterParams>(
        &raster,
        "RasterParams",
        host!(
            RasterParams,
            size,
            capacity,
            index_base,
            frame_number,
            hidden_winding
        ),
    );
    t.buffer(&raster, "RasterTriangle", host!(RasterTriangle, clip));
    let prepare = compile(&builtin_shader!("../raster/raster_prepare.comp.glsl"), &[]);
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
        &builtin_shader!("../raster/hzb_build.comp.glsl"),
        &crate::raster::hzb::build_defines(),
    );
    t.push_constants::<HzbBuildParams>(
        &hzb,
        "HzbBuildParams",
        host!(HzbBuildParams, size, first_level, level_count, frame_number),
    );
}

fn interval_structs(t: &mut Table) {
    use crate::tet::interval::composite::{composite_defines, CompositeParams};
    use crate::tet::interval::compute::compute_defines;
    use crate::tet::interval::IntervalParams;
    let defines = Interval::defines(&IntervalOptions::new(Path::Compute));
    let raster = compile(
        &builtin_shader!("../tet/interval/interval_raster.comp.glsl"),
        &compute_defines(&defines, TileCapacity::default(), SubgroupDraw::Off),
    );
    #[rustfmt::skip]
    t.push_constants::<IntervalParams>(&raster, "IntervalParams", host!(IntervalParams,
        world_to_clip, tan_half_fov, near_depth, counts, eye, scalar_range));
    let composite = compile(
        &builtin_shader!("../tet/interval/composite.comp.glsl"),
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
    let rays = compile(
        &builtin_shader!("../tet/shell/shell_rays.comp.glsl"),
        &defines,
    );
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
        &builtin_shader!("../tet/shell/lighting.comp.glsl"),
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
    let step = compile(&builtin_shader!("../param/lod_step.comp.glsl"), &lod);
    #[rustfmt::skip]
    t.push_constants::<LodParams>(&step, "LodParams", host!(LodParams, world_to_clip, viewport,
        thresholds, step, last, eval_capacity, render_capacity, culling, capture_capacity,
        object_count, pre_split));
    t.buffer(&step, "LodSample", host!(LodSample, object, u, v, x, y));
    let prepare = compile(&builtin_shader!("../param/lod_prepare.comp.glsl"), &lod);
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
    let init = compile(&builtin_shader!("../param/lod_init.comp.glsl"), &lod);
    #[rustfmt::skip]
    t.buffer(&init, "ParamObject", host!(GpuObject, model, colour, domain, radius_map, kind,
        params, order, flags));
    t.buffer(&init, "Patch", host!(GpuPatch, u, v, extent, object, info));
    let draw = compile(&builtin_shader!("../param/points.comp.glsl"), &points);
    #[rustfmt::skip]
    t.push_constants::<PointsParams>(&draw, "PointsParams", host!(PointsParams, world_to_clip,
        viewport, density, max_side, raster, uv_bits, render_capacity, footprint, eye));
    let resolve = compile(&builtin_shader!("../param/resolve.comp.glsl"), &points);
    #[rustfmt::skip]
    t.push_constants::<ResolveParams>(&resolve, "ResolveParams", host!(ResolveParams, eye, light,
        background, size, supersample, uv_bits));
    let probe = compile(&builtin_shader!("../param/probe.comp.glsl"), &points);
    t.buffer(
        &probe,
        "ProbeResult",
        host!(ProbeResult, position, normal, colour),
    );
    let control = compile(&builtin_shader!("../param/tess.tesc.glsl"), &points);
    #[rustfmt::skip]
    t.push_constants::<TessParams>(&control, "TessParams", host!(TessParams, world_to_clip, eye,
        light, viewport, pixels_per_segment, fixed_level, min_level, max_level, render_capacity,
        patches_per_instance));
    let downsample = compile(
        &builtin_shader!("../param/tess_downsample.comp.glsl"),
        &points,
    );
    t.push_constants::<DownsampleParams>(
        &downsample,
        "DownsampleParams",
        host!(DownsampleParams, size, supersample),
    );
    let args = compile(&builtin_shader!("../param/tess_args.comp.glsl"), &points);
    t.push_constants::<ArgsParams>(
        &args,
        "TessArgsParams",
        host!(ArgsParams, render_capacity, patches_per_instance),
    );
    let rt = raytrace_defines(12);
    let render = compile(&builtin_shader!("../param/raytrace.comp.glsl"), &rt);
    let rt_probe = compile(&builtin_shader!("../param/raytrace_probe.comp.glsl"), &rt);
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
        compile(&builtin_shader!("../throughput/busy.frag.glsl"), &defines),
        compile(&builtin_shader!("../throughput/busy.comp.glsl"), &defines),
    ] {
        t.push_constants::<ArithmeticParams>(
            &spirv,
            "ArithmeticParams",
            host!(ArithmeticParams, size, iterations),
        );
    }
    for spirv in [
        compile(&builtin_shader!("../throughput/grid.mesh.glsl"), &defines),
        compile(&builtin_shader!("../throughput/splat.comp.glsl"), &defines),
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
    iso::isosurface_structs(&mut t);
    iso::meshlet_structs(&mut t);
    iso::meshlet_draw_structs(&mut t);
    iso::pmb_structs(&mut t);
    iso::pmb_draw_structs(&mut t);
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
