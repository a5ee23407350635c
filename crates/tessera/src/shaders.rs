//! The shader compiler set up with Tessera's shared GLSL headers.

use tessera_data::mc_tables;
use tessera_gpu::{ShaderCompiler, Source};

/// Shared headers, included by name: `common/…` for all techniques, `<technique>/…` for the
/// pieces one technique's stages share.
const COMMON: &[(&str, &str)] = &[
    (
        "common/volume.glsl",
        include_str!("shaders/common/volume.glsl"),
    ),
    (
        "common/shading.glsl",
        include_str!("shaders/common/shading.glsl"),
    ),
    (
        "common/exact.glsl",
        include_str!("shaders/common/exact.glsl"),
    ),
    (
        "common/ablation.glsl",
        include_str!("shaders/common/ablation.glsl"),
    ),
    (
        "common/workgroup_scan.glsl",
        include_str!("shaders/common/workgroup_scan.glsl"),
    ),
    (
        "common/subgroup_turns.glsl",
        include_str!("shaders/common/subgroup_turns.glsl"),
    ),
    (
        "common/mc_cell.glsl",
        include_str!("shaders/common/mc_cell.glsl"),
    ),
    (
        "common/held_samples.glsl",
        include_str!("shaders/common/held_samples.glsl"),
    ),
    (
        "common/mc_vertex.glsl",
        include_str!("shaders/common/mc_vertex.glsl"),
    ),
    (
        "common/mc_edges.glsl",
        include_str!("shaders/common/mc_edges.glsl"),
    ),
    (
        "iso/meshlets/params.glsl",
        include_str!("iso/meshlets/params.glsl"),
    ),
    (
        "common/grid_world.glsl",
        include_str!("shaders/common/grid_world.glsl"),
    ),
    (
        "common/frustum.glsl",
        include_str!("shaders/common/frustum.glsl"),
    ),
    (
        "iso/meshlets/format.glsl",
        include_str!("iso/meshlets/format.glsl"),
    ),
    (
        "iso/meshlet_draw/params.glsl",
        include_str!("iso/meshlet_draw/params.glsl"),
    ),
    (
        "iso/meshlet_draw/buffers.glsl",
        include_str!("iso/meshlet_draw/buffers.glsl"),
    ),
    (
        "iso/meshlet_draw/payload.glsl",
        include_str!("iso/meshlet_draw/payload.glsl"),
    ),
    (
        "iso/meshlet_draw/corner.glsl",
        include_str!("iso/meshlet_draw/corner.glsl"),
    ),
    (
        "iso/meshlet_draw/list.glsl",
        include_str!("iso/meshlet_draw/list.glsl"),
    ),
    (
        "iso/meshlets/buffers.glsl",
        include_str!("iso/meshlets/buffers.glsl"),
    ),
    (
        "iso/meshlets/payload.glsl",
        include_str!("iso/meshlets/payload.glsl"),
    ),
    (
        "iso/meshlets/samples.glsl",
        include_str!("iso/meshlets/samples.glsl"),
    ),
    (
        "iso/meshlets/subblock.glsl",
        include_str!("iso/meshlets/subblock.glsl"),
    ),
    (
        "iso/meshlets/scan.glsl",
        include_str!("iso/meshlets/scan.glsl"),
    ),
    (
        "iso/meshlets/analysis.glsl",
        include_str!("iso/meshlets/analysis.glsl"),
    ),
    (
        "iso/meshlets/extraction.glsl",
        include_str!("iso/meshlets/extraction.glsl"),
    ),
    ("iso/pmb/params.glsl", include_str!("iso/pmb/params.glsl")),
    ("iso/pmb/format.glsl", include_str!("iso/pmb/format.glsl")),
    (
        "iso/pmb_draw/blocks.glsl",
        include_str!("iso/pmb_draw/blocks.glsl"),
    ),
    (
        "iso/direct/payload.glsl",
        include_str!("iso/direct/payload.glsl"),
    ),
    (
        "iso/direct/params.glsl",
        include_str!("iso/direct/params.glsl"),
    ),
    ("iso/direct/cull.glsl", include_str!("iso/direct/cull.glsl")),
    (
        "tet/interval/params.glsl",
        include_str!("tet/interval/params.glsl"),
    ),
    (
        "tet/interval/proxy.glsl",
        include_str!("tet/interval/proxy.glsl"),
    ),
    (
        "tet/interval/length.glsl",
        include_str!("tet/interval/length.glsl"),
    ),
    (
        "tet/interval/buffers.glsl",
        include_str!("tet/interval/buffers.glsl"),
    ),
    (
        "tet/interval/compute_buffers.glsl",
        include_str!("tet/interval/compute_buffers.glsl"),
    ),
    (
        "tet/interval/optical_layout.glsl",
        include_str!("tet/interval/optical_layout.glsl"),
    ),
    (
        "tet/interval/subgroup_draw.glsl",
        include_str!("tet/interval/subgroup_draw.glsl"),
    ),
    ("tet/table.glsl", include_str!("tet/table.glsl")),
    (
        "tet/interval/table.glsl",
        include_str!("tet/interval/table.glsl"),
    ),
    (
        "tet/interval/integrand.glsl",
        include_str!("tet/interval/integrand.glsl"),
    ),
    (
        "tet/interval/splat.glsl",
        include_str!("tet/interval/splat.glsl"),
    ),
    (
        "tet/interval/sdf.glsl",
        include_str!("tet/interval/sdf.glsl"),
    ),
    (
        "tet/interval/pixel_value.glsl",
        include_str!("tet/interval/pixel_value.glsl"),
    ),
    (
        "tet/interval/tet_draw.glsl",
        include_str!("tet/interval/tet_draw.glsl"),
    ),
    (
        "tet/interval/bin_buffers.glsl",
        include_str!("tet/interval/bin_buffers.glsl"),
    ),
    (
        "tet/interval/pixel_passes.glsl",
        include_str!("tet/interval/pixel_passes.glsl"),
    ),
    ("raster/hzb.glsl", include_str!("raster/hzb.glsl")),
    ("raster/hzb_test.glsl", include_str!("raster/hzb_test.glsl")),
    (
        "iso/direct/block_list.glsl",
        include_str!("iso/direct/block_list.glsl"),
    ),
    (
        "iso/direct/cell_box.glsl",
        include_str!("iso/direct/cell_box.glsl"),
    ),
    (
        "iso/direct/cell_box_record.glsl",
        include_str!("iso/direct/cell_box_record.glsl"),
    ),
    (
        "iso/direct/views.glsl",
        include_str!("iso/direct/views.glsl"),
    ),
    ("raster/raster.glsl", include_str!("raster/raster.glsl")),
    (
        "raster/raster_draw.glsl",
        include_str!("raster/raster_draw.glsl"),
    ),
    (
        "iso/direct/attributes.glsl",
        include_str!("iso/direct/attributes.glsl"),
    ),
    (
        "common/indirect_args.glsl",
        include_str!("shaders/common/indirect_args.glsl"),
    ),
    (
        "common/throughput.glsl",
        include_str!("shaders/common/throughput.glsl"),
    ),
    (
        "tet/shell/buffers.glsl",
        include_str!("tet/shell/buffers.glsl"),
    ),
    (
        "tet/shell/params.glsl",
        include_str!("tet/shell/params.glsl"),
    ),
    (
        "tet/shell/ray_space.glsl",
        include_str!("tet/shell/ray_space.glsl"),
    ),
    ("tet/shell/bvh.glsl", include_str!("tet/shell/bvh.glsl")),
    ("tet/shell/hit.glsl", include_str!("tet/shell/hit.glsl")),
    ("tet/shell/stage.glsl", include_str!("tet/shell/stage.glsl")),
    ("tet/shell/trace.glsl", include_str!("tet/shell/trace.glsl")),
    (
        "tet/shell/rt_trace.glsl",
        include_str!("tet/shell/rt_trace.glsl"),
    ),
    (
        "tet/shell/layout.glsl",
        include_str!("tet/shell/layout.glsl"),
    ),
    (
        "tet/shell/integrate.glsl",
        include_str!("tet/shell/integrate.glsl"),
    ),
    (
        "tet/shell/traverse.glsl",
        include_str!("tet/shell/traverse.glsl"),
    ),
    ("tet/shell/stats.glsl", include_str!("tet/shell/stats.glsl")),
    (
        "tet/shell/pixel_ray.glsl",
        include_str!("tet/shell/pixel_ray.glsl"),
    ),
    (
        "tet/shell/effects.glsl",
        include_str!("tet/shell/effects.glsl"),
    ),
    ("param/scene.glsl", include_str!("param/scene.glsl")),
    ("param/sh.glsl", include_str!("param/sh.glsl")),
    ("param/functions.glsl", include_str!("param/functions.glsl")),
    ("param/normal.glsl", include_str!("param/normal.glsl")),
    ("param/view.glsl", include_str!("param/view.glsl")),
    ("param/patch.glsl", include_str!("param/patch.glsl")),
    (
        "param/lod_params.glsl",
        include_str!("param/lod_params.glsl"),
    ),
    ("param/payload.glsl", include_str!("param/payload.glsl")),
    (
        "param/min_extent.glsl",
        include_str!("param/min_extent.glsl"),
    ),
    (
        crate::param::user::USER_HEADER,
        crate::param::user::NO_USER_FUNCTION,
    ),
    (
        "param/raytrace_glyph.glsl",
        include_str!("param/raytrace_glyph.glsl"),
    ),
    (
        "param/raytrace_trace.glsl",
        include_str!("param/raytrace_trace.glsl"),
    ),
    ("param/shade.glsl", include_str!("param/shade.glsl")),
    (
        "param/tess_params.glsl",
        include_str!("param/tess_params.glsl"),
    ),
];

/// A built-in shader beside the Rust file that drives it: reported under its source-tree path,
/// with its text compiled into the binary so the tool runs from anywhere.
#[macro_export]
macro_rules! builtin_shader {
    ($file:literal) => {
        $crate::shaders::builtin(file!(), $file, include_str!($file))
    };
}

pub fn builtin(rust_file: &str, name: &str, text: &str) -> Source {
    let dir = std::path::Path::new(rust_file)
        .parent()
        .map(|d| d.join(name))
        .unwrap_or_else(|| name.into());
    Source::new(dir.display().to_string(), text)
}

pub fn compiler() -> ShaderCompiler {
    let mut c = ShaderCompiler::new();
    for (name, text) in COMMON {
        c.add_header(name, text);
    }
    c.add_header("common/mc_tables.glsl", &mc_tables_glsl());
    c
}

/// The marching-cubes tables as GLSL constants, generated from `tessera_data::mc_tables` so
/// the CPU reference and the shaders share one definition (conventions documented there).
///
/// `MC_CASES[case]` holds the case's first row (bits 0–15) and its ambiguous faces (bits
/// 16–21). `MC_ROWS[row]` packs the row's edge ids as nibbles, entries 0–7 in `.x`, 8–15 in
/// `.y` and so on, and the triangle count in the last nibble of `.w`. `MC_EDGE_MASK[case]`
/// has bit `e` set for each crossing edge; `MC_EDGE_CORNERS` packs each edge's start and end
/// corner, `MC_FACE_CORNERS` each face's four corners (a nibble each, in the face's order).
pub fn mc_tables_glsl() -> String {
    use std::fmt::Write;
    const ROW_NIBBLES: usize = 32;
    const _: () = assert!(
        3 * mc_tables::MAX_TRIANGLES < ROW_NIBBLES,
        "a row's edge ids and its count fit a uvec4"
    );
    let t = mc_tables::mc_tables();
    let mut out = String::from("// Generated from tessera_data::mc_tables at run time.\n");
    let _ = writeln!(
        out,
        "// Most triangles any row holds.\nconst uint MC_MAX_TRIANGLES = {}u;",
        mc_tables::MAX_TRIANGLES
    );
    let list = |items: Vec<String>| items.join(",");
    let masks = t.edge_mask.iter().map(|m| format!("{m}u")).collect();
    let _ = writeln!(
        out,
        "const uint MC_EDGE_MASK[256] = uint[]({});",
        list(masks)
    );
    let cases = (0..256)
        .map(|c| {
            format!(
                "{}u",
                u32::from(t.first_row[c]) | u32::from(t.ambiguous_faces[c]) << 16
            )
        })
        .collect();
    let _ = writeln!(out, "const uint MC_CASES[256] = uint[]({});", list(cases));
    let rows = (0..t.row_count())
        .map(|row| {
            let mut words = [0u32; 4];
            for (i, &e) in t.tris[row].iter().enumerate() {
                let nibble = if e < 0 { 0xF } else { e as u32 };
                words[i / 8] |= nibble << ((i % 8) * 4);
            }
            words[3] |= u32::from(t.tri_count[row]) << 28;
            format!(
                "uvec4({}u,{}u,{}u,{}u)",
                words[0], words[1], words[2], words[3]
            )
        })
        .collect();
    let _ = writeln!(
        out,
        "const uvec4 MC_ROWS[{}] = uvec4[]({});",
        t.row_count(),
        list(rows)
    );
    let corners = mc_tables::EDGE_CORNERS
        .iter()
        .map(|[a, b]| format!("{}u", u32::from(*a) | (u32::from(*b) << 4)))
        .collect();
    let _ = writeln!(
        out,
        "const uint MC_EDGE_CORNERS[12] = uint[]({});",
        list(corners)
    );
    let faces = mc_tables::FACE_CORNERS
        .iter()
        .map(|c| {
            format!(
                "{}u",
                (0..4).fold(0u32, |w, j| w | u32::from(c[j]) << (4 * j))
            )
        })
        .collect();
    let _ = writeln!(
        out,
        "const uint MC_FACE_CORNERS[6] = uint[]({});",
        list(faces)
    );
    out.push_str(
        "uint mc_tri_count(uint row) { return MC_ROWS[row].w >> 28; }\n\
         uint mc_tri_edge(uint row, uint i) { return (MC_ROWS[row][i >> 3] >> ((i & 7u) * 4u)) & 15u; }\n\
         uint mc_first_row(uint case_index) { return MC_CASES[case_index] & 0xffffu; }\n\
         uint mc_ambiguous_faces(uint case_index) { return MC_CASES[case_index] >> 16; }\n\
         uvec3 mc_corner_offset(uint corner) { return uvec3(corner & 1u, (corner >> 1) & 1u, corner >> 2); }\n",
    );
    out
}
