//! The isosurface techniques' host structs in the layout table: direct, ray marching and the
//! octree, meshlets and their draw, PMB and its draw.

use super::{compile, Table};
use crate::builtin_shader;
use crate::config::volume_defines;
use std::mem::offset_of;
use tessera_data::ScalarType;

pub(super) fn isosurface_structs(t: &mut Table) {
    use crate::iso::direct::block_list::BlockListHeader;
    use crate::iso::direct::compute::{CornerAttributes, ReprojectParams, TriangleAttributes};
    use crate::iso::direct::compute_cull::HzbTestParams;
    use crate::iso::direct::resolve::ResolveParams;
    use crate::iso::direct::stereo::StereoViews;
    use crate::iso::direct::DirectParams;
    use crate::iso::minmax::{block_defines, rows_defines, BlockParams, GroupParams, LevelsParams};
    use crate::iso::raymarch::RaymarchParams;
    let u8_defines = crate::config::marching_cubes_defines(ScalarType::U8, Default::default());
    let raymarch = compile(
        &builtin_shader!("../iso/raymarch/raymarch.comp.glsl"),
        &u8_defines,
    );
    #[rustfmt::skip]
    t.push_constants::<RaymarchParams>(&raymarch, "RaymarchParams", host!(RaymarchParams, eye,
        isovalue, forward, tan_half_fov_x, right, tan_half_fov_y, up, light, grid_to_world, dims,
        octree_levels, image));
    let extract_defines =
        crate::iso::direct::compute::extract_defines(ScalarType::U8, Default::default(), false);
    let extract = compile(
        &builtin_shader!("../iso/direct/extract.comp.glsl"),
        &extract_defines,
    );
    #[rustfmt::skip]
    t.push_constants::<DirectParams>(&extract, "DirectParams", host!(DirectParams, grid_to_clip,
        eye_world, isovalue, grid_to_world, light, dims, triangle_capacity));
    let cull_defines =
        crate::iso::direct::compute_cull::cull_defines(ScalarType::U8, Default::default(), false);
    let mut list_defines = cull_defines.clone();
    list_defines.push(("BLOCK_LIST".into(), "1".into()));
    let extract_list = compile(
        &builtin_shader!("../iso/direct/extract.comp.glsl"),
        &list_defines,
    );
    let cull_setup = compile(
        &builtin_shader!("../iso/direct/cull_setup.comp.glsl"),
        &u8_defines,
    );
    for spirv in [&extract_list, &cull_setup] {
        t.buffer(
            spirv,
            "BlockListHeader",
            host!(BlockListHeader, count, args),
        );
    }
    // Culling's second pass reads its raster pass's parameters from a buffer.
    let mut new_defines = list_defines.clone();
    new_defines.push(("HIDDEN_CELLS_LEFT_OUT".into(), "1".into()));
    let extract_new = compile(
        &builtin_shader!("../iso/direct/extract.comp.glsl"),
        &new_defines,
    );
    #[rustfmt::skip]
    t.buffer(&extract_new, "RasterPassParams", host!(crate::raster::RasterParams, size, capacity,
        index_base, frame_number, hidden_winding));
    let mut multiview_defines = u8_defines.clone();
    multiview_defines
        .extend([("MULTIVIEW", "1"), ("BLOCK_LIST", "0")].map(|(k, v)| (k.into(), v.into())));
    let multiview = compile(
        &builtin_shader!("../iso/direct/direct.mesh.glsl"),
        &multiview_defines,
    );
    t.buffer(
        &multiview,
        "Views",
        host!(StereoViews, grid_to_clip, eye_world),
    );
    let resolve = compile(
        &builtin_shader!("../iso/direct/resolve.comp.glsl"),
        &u8_defines,
    );
    t.push_constants::<ResolveParams>(
        &resolve,
        "ResolveParams",
        host!(
            ResolveParams,
            clip_to_world,
            eye_world,
            light,
            size,
            second_base,
            frame_number,
            empties,
            seen_number
        ),
    );
    t.buffer(
        &resolve,
        "TriangleAttributes",
        host!(TriangleAttributes, corners),
    );
    t.buffer(
        &resolve,
        "CornerAttributes",
        host!(CornerAttributes, normal_world, maker),
    );
    let reproject = compile(
        &builtin_shader!("../iso/direct/reproject.comp.glsl"),
        &u8_defines,
    );
    t.push_constants::<ReprojectParams>(
        &reproject,
        "ReprojectParams",
        host!(ReprojectParams, first_clip_to_second_clip, capacity),
    );
    let hzb_test = compile(
        &builtin_shader!("../iso/direct/hzb_test.comp.glsl"),
        &cull_defines,
    );
    t.push_constants::<HzbTestParams>(
        &hzb_test,
        "HzbTestParams",
        host!(
            HzbTestParams,
            grid_to_clip,
            dims,
            size,
            iso,
            first_pass_number
        ),
    );
    let blocks = compile(
        &builtin_shader!("../iso/minmax/minmax_blocks.comp.glsl"),
        &block_defines(ScalarType::U16, false),
    );
    t.push_constants::<BlockParams>(
        &blocks,
        "BlockParams",
        host!(BlockParams, volume_dims, block_dims),
    );
    let rows = compile(
        &builtin_shader!("../iso/minmax/minmax_rows.comp.glsl"),
        &rows_defines(ScalarType::U16),
    );
    t.push_constants::<BlockParams>(
        &rows,
        "BlockParams",
        host!(BlockParams, volume_dims, block_dims),
    );
    let groups = compile(
        &builtin_shader!("../iso/minmax/minmax_groups.comp.glsl"),
        &crate::config::volume_defines(ScalarType::U16),
    );
    t.push_constants::<GroupParams>(
        &groups,
        "GroupParams",
        host!(GroupParams, volume_dims, block_dims, parent_dims),
    );
    let levels = compile(
        &builtin_shader!("../iso/minmax/minmax_levels.comp.glsl"),
        &volume_defines(ScalarType::U16),
    );
    t.push_constants::<LevelsParams>(
        &levels,
        "LevelsParams",
        host!(LevelsParams, child_level, level_count),
    );
}

pub(super) fn meshlet_structs(t: &mut Table) {
    use crate::iso::direct::block_list::BlockListHeader;
    use crate::iso::meshlets::{MeshletCounters, MeshletParams};
    use tessera_data::meshlets::Meshlet;
    let defines = crate::config::meshlet_defines(
        ScalarType::U8,
        Default::default(),
        crate::iso::meshlets::ExtractionPath::Compute,
        true,
    );
    let extract = compile(
        &builtin_shader!("../iso/meshlets/extract.comp.glsl"),
        &defines,
    );
    let occupied = compile(
        &builtin_shader!("../iso/meshlets/occupied.comp.glsl"),
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

pub(super) fn meshlet_draw_structs(t: &mut Table) {
    use crate::iso::meshlet_draw::{DrawCounters, MeshletDrawParams};
    let defines = crate::config::meshlet_draw_defines();
    let triangles = compile(
        &builtin_shader!("../iso/meshlet_draw/triangles.comp.glsl"),
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

pub(super) fn pmb_structs(t: &mut Table) {
    use crate::iso::pmb::{PmbCounters, PmbParams};
    use tessera_data::pmb::{PmbBlock, PmbBlockSize};
    let defines = crate::config::pmb_defines(
        ScalarType::U8,
        Default::default(),
        PmbBlockSize::B884,
        128,
        true,
    );
    let extract = compile(&builtin_shader!("../iso/pmb/extract.comp.glsl"), &defines);
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

pub(super) fn pmb_draw_structs(t: &mut Table) {
    use crate::iso::meshlet_draw::MeshletDrawParams;
    use crate::iso::pmb_draw::{DrawIndexedIndirectCommand, PmbDrawCounters};
    use tessera_data::pmb::PmbBlockSize;
    let defines = crate::config::pmb_draw_defines(PmbBlockSize::B844);
    let triangles = compile(
        &builtin_shader!("../iso/pmb_draw/triangles.comp.glsl"),
        &defines,
    );
    let commands = compile(
        &builtin_shader!("../iso/pmb_draw/commands.comp.glsl"),
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
