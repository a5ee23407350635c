//! Host structs against the shaders' SPIR-V layouts: every member's offset, by name, for the
//! push constants and buffer records not checked beside their technique's tests (raymarch,
//! param, throughput and culling structs are checked there). Compiles GLSL only; needs no
//! device.

use crate::builtin_shader;
use crate::config::volume_defines;
use crate::path::Path;
use crate::tet::interval::{Interval, IntervalOptions, TileCapacity};
use std::mem::offset_of;
use tessera_data::ScalarType;
use tessera_gpu::{Spirv, PUSH_CONSTANT_BYTES};

/// Member names and offsets of `block` in `spirv`, padding left out.
fn members(spirv: &Spirv, block: &str) -> Vec<(String, usize)> {
    tessera_gpu::spirv::struct_offsets(&spirv.words, block)
        .unwrap_or_else(|| panic!("no struct {block} in the SPIR-V"))
        .into_iter()
        .filter(|(name, _)| !name.starts_with("pad"))
        .map(|(name, offset)| (name, offset as usize))
        .collect()
}

macro_rules! host {
    ($t:ty, $($f:ident),*) => {
        vec![$((stringify!($f).to_string(), offset_of!($t, $f))),*]
    };
}

fn compile(source: &tessera_gpu::Source, defines: &[(String, String)]) -> Spirv {
    crate::shaders::compiler()
        .compile(source, defines)
        .unwrap_or_else(|e| panic!("{e}"))
}

fn fits_push_constants<T>(name: &str) {
    let bytes = std::mem::size_of::<T>();
    assert!(
        bytes <= PUSH_CONSTANT_BYTES as usize,
        "{name}: {bytes} bytes of push constants"
    );
}

#[test]
fn direct_structs_match_their_shaders() {
    use crate::iso::direct::compute::{ReprojectParams, ResolveParams};
    use crate::iso::direct::DirectParams;
    let defines = volume_defines(ScalarType::U8);
    let extract = compile(&builtin_shader!("iso/direct/extract.comp.glsl"), &defines);
    assert_eq!(
        members(&extract, "DirectParams"),
        host!(
            DirectParams,
            grid_to_clip,
            eye_world,
            isovalue,
            grid_to_world,
            light,
            dims,
            triangle_capacity
        )
    );
    fits_push_constants::<DirectParams>("DirectParams");
    let resolve = compile(&builtin_shader!("iso/direct/resolve.comp.glsl"), &defines);
    assert_eq!(
        members(&resolve, "ResolveParams"),
        host!(ResolveParams, eye_world, light, size)
    );
    let reproject = compile(&builtin_shader!("iso/direct/reproject.comp.glsl"), &defines);
    assert_eq!(
        members(&reproject, "ReprojectParams"),
        host!(ReprojectParams, world_to_clip, capacity)
    );
}

#[test]
fn minmax_structs_match_their_shaders() {
    use crate::iso::minmax::{block_defines, BlockParams, ReduceParams};
    let blocks = compile(
        &builtin_shader!("iso/minmax/minmax_blocks.comp.glsl"),
        &block_defines(ScalarType::U16, false),
    );
    assert_eq!(
        members(&blocks, "BlockParams"),
        host!(BlockParams, volume_dims, block_dims)
    );
    let reduce = compile(
        &builtin_shader!("iso/minmax/minmax_reduce.comp.glsl"),
        &volume_defines(ScalarType::U16),
    );
    assert_eq!(
        members(&reduce, "ReduceParams"),
        host!(ReduceParams, child, parent)
    );
}

#[test]
fn raster_structs_match_their_shaders() {
    use crate::raster::indirect::PrepareParams;
    use crate::raster::{raster_defines, RasterParams, RasterTriangle};
    let raster = compile(
        &builtin_shader!("raster/raster.comp.glsl"),
        &raster_defines(),
    );
    assert_eq!(
        members(&raster, "RasterParams"),
        host!(RasterParams, size, capacity, index_base)
    );
    assert_eq!(
        members(&raster, "RasterTriangle"),
        host!(RasterTriangle, clip)
    );
    let prepare = compile(&builtin_shader!("raster/raster_prepare.comp.glsl"), &[]);
    assert_eq!(
        members(&prepare, "PrepareParams"),
        host!(PrepareParams, max_groups, group_size)
    );
}

#[test]
fn interval_structs_match_their_shaders() {
    use crate::tet::interval::composite::{composite_defines, CompositeParams};
    use crate::tet::interval::compute::compute_defines;
    use crate::tet::interval::IntervalParams;
    let defines = Interval::defines(&IntervalOptions::new(Path::Compute));
    let raster = compile(
        &builtin_shader!("tet/interval/interval_raster.comp.glsl"),
        &compute_defines(&defines, TileCapacity::default()),
    );
    assert_eq!(
        members(&raster, "IntervalParams"),
        host!(
            IntervalParams,
            world_to_clip,
            tan_half_fov,
            near_depth,
            counts,
            eye,
            scalar_range
        )
    );
    fits_push_constants::<IntervalParams>("IntervalParams");
    let composite = compile(
        &builtin_shader!("tet/interval/composite.comp.glsl"),
        &composite_defines(&defines, Path::Compute),
    );
    assert_eq!(
        members(&composite, "CompositeParams"),
        host!(CompositeParams, background, size)
    );
}

#[test]
fn probe_records_match_their_shader() {
    use crate::param::points::points_defines;
    use crate::param::ProbeResult;
    let probe = compile(&builtin_shader!("param/probe.comp.glsl"), &points_defines());
    assert_eq!(
        members(&probe, "ProbeResult"),
        host!(ProbeResult, position, normal, colour)
    );
}
