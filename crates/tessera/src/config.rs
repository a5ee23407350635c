//! Constants shared by Rust and GLSL. Each is defined once on the Rust side (next to the CPU
//! code that needs it) and handed to every shader as a `#define`, so no value is copied by hand
//! between the two languages.

use crate::iso::direct;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::minmax::BLOCK_CELLS;
use tessera_data::raycast::{REFINEMENTS, STEP};
use tessera_data::shading;
use tessera_data::ScalarType;

pub(crate) fn float(v: f32) -> String {
    format!("{v:?}")
}

pub(crate) fn vec3(v: [f32; 3]) -> String {
    format!("vec3({}, {}, {})", float(v[0]), float(v[1]), float(v[2]))
}

fn vec4(v: [f32; 4]) -> String {
    format!(
        "vec4({}, {}, {}, {})",
        float(v[0]),
        float(v[1]),
        float(v[2]),
        float(v[3])
    )
}

/// Defines every shader receives.
pub fn common_defines() -> Vec<(String, String)> {
    vec![
        ("BLOCK_X".into(), format!("{}u", BLOCK_CELLS[0])),
        (
            "RESOLVE_PIXELS".into(),
            format!("{}u", crate::raster::RESOLVE_PIXELS),
        ),
        (
            "RASTER_TILE".into(),
            format!("{}u", crate::raster::RASTER_TILE),
        ),
        ("BLOCK_Y".into(), format!("{}u", BLOCK_CELLS[1])),
        ("BLOCK_Z".into(), format!("{}u", BLOCK_CELLS[2])),
        ("STEP".into(), float(STEP)),
        ("REFINEMENTS".into(), REFINEMENTS.to_string()),
        ("GOOCH_COOL".into(), vec3(shading::GOOCH_COOL)),
        ("GOOCH_WARM".into(), vec3(shading::GOOCH_WARM)),
        (
            "SPECULAR_STRENGTH".into(),
            float(shading::SPECULAR_STRENGTH),
        ),
        (
            "SPECULAR_EXPONENT".into(),
            float(shading::SPECULAR_EXPONENT),
        ),
        ("BACKGROUND".into(), vec4(shading::BACKGROUND)),
        (
            "DIRECT_MAX_CELLS".into(),
            format!("{}u", direct::MAX_CELLS_PER_LIST),
        ),
        (
            "DIRECT_MAX_VERTICES".into(),
            format!("{}u", direct::MAX_VERTICES_PER_LIST),
        ),
        (
            "DIRECT_MAX_TRIANGLES".into(),
            format!("{}u", direct::MAX_TRIANGLES_PER_LIST),
        ),
    ]
}

/// Defines for shaders that read a volume of `scalar` samples.
pub fn volume_defines(scalar: ScalarType) -> Vec<(String, String)> {
    let sampler = match scalar {
        ScalarType::U8 | ScalarType::U16 => "usampler3D",
        ScalarType::F32 => "sampler3D",
    };
    let mut d = common_defines();
    d.push(("VOLUME_SAMPLER".into(), sampler.into()));
    d
}

/// Defines for shaders that run marching cubes (`common/mc_cell.glsl`) on a volume of
/// `scalar` samples, cutting ambiguous faces by `rule`.
///
/// The rule is a define rather than a push constant: it is fixed for a pipeline's lifetime
/// (a renderer is built for one rule), the VTK rule then compiles to no saddle arithmetic
/// at all, and the direct path's push-constant block already fills the 128 bytes Vulkan
/// guarantees.
pub fn marching_cubes_defines(scalar: ScalarType, rule: AmbiguityRule) -> Vec<(String, String)> {
    let mut d = volume_defines(scalar);
    let decider = rule == AmbiguityRule::AsymptoticDecider;
    d.push((
        "MC_ASYMPTOTIC_DECIDER".into(),
        u32::from(decider).to_string(),
    ));
    d
}

/// Defines for the meshlet extraction (`iso/meshlets`): marching cubes' (see
/// [`marching_cubes_defines`]) plus the meshlet limits, the cells of a block's eighth (a
/// 2×2×2 subblock, the smallest of the partition) and the workgroup size of `path`.
pub fn meshlet_defines(
    scalar: ScalarType,
    rule: AmbiguityRule,
    path: crate::iso::meshlets::ExtractionPath,
    subgroup_arithmetic: bool,
) -> Vec<(String, String)> {
    use tessera_data::meshlets::{
        subblock::SUBBLOCK_CELL_COUNTS, MAX_OCCUPIED_CELLS, MAX_TRIANGLES, MAX_VERTICES,
    };
    let mut d = marching_cubes_defines(scalar, rule);
    let smallest_subblock = SUBBLOCK_CELL_COUNTS[SUBBLOCK_CELL_COUNTS.len() - 1];
    for (name, value) in [
        ("MESHLET_MAX_VERTICES", MAX_VERTICES),
        ("MESHLET_MAX_TRIANGLES", MAX_TRIANGLES),
        ("MESHLET_MAX_OCCUPIED_CELLS", MAX_OCCUPIED_CELLS),
        ("MESHLET_EIGHTH_CELLS", smallest_subblock),
        ("MESHLET_WORKGROUP", path.workgroup_size()),
    ] {
        d.push((name.into(), format!("{value}u")));
    }
    // A preprocessor condition: a plain 0 or 1.
    d.push((
        "MESHLET_SUBGROUP_SCAN".into(),
        u32::from(path.subgroup_scan(subgroup_arithmetic)).to_string(),
    ));
    d
}

/// Defines for the meshlet draw (`iso/meshlet_draw`): the meshlet limits, the task
/// workgroup's size and the codes of the culling boxes, and the raster pass's (its compute
/// path writes that pass's dispatch arguments).
pub fn meshlet_draw_defines() -> Vec<(String, String)> {
    use crate::iso::meshlet_draw::{MeshletBounds, TASK_SIZE};
    use tessera_data::meshlets::{MAX_TRIANGLES, MAX_VERTICES};
    let mut d = [common_defines(), crate::raster::raster_defines()].concat();
    for (name, value) in [
        ("MESHLET_MAX_VERTICES", MAX_VERTICES),
        ("MESHLET_MAX_TRIANGLES", MAX_TRIANGLES),
        ("MESHLET_DRAW_TASK_SIZE", TASK_SIZE),
        ("MESHLET_BOUNDS_EXPLICIT", MeshletBounds::Explicit.code()),
        ("MESHLET_BOUNDS_IMPLICIT", MeshletBounds::Implicit.code()),
        ("MESHLET_BOUNDS_NONE", MeshletBounds::None.code()),
    ] {
        d.push((name.into(), format!("{value}u")));
    }
    d
}

/// Defines for the PMB extraction (`iso/pmb`): marching cubes' (see
/// [`marching_cubes_defines`]) plus the block size the pipelines are built for and the
/// extraction's workgroup size.
pub fn pmb_defines(
    scalar: ScalarType,
    rule: AmbiguityRule,
    block_size: crate::iso::pmb::PmbBlockSize,
    workgroup: u32,
    subgroup_arithmetic: bool,
) -> Vec<(String, String)> {
    let mut d = marching_cubes_defines(scalar, rule);
    let [x, y, z] = block_size.cells();
    for (name, value) in [
        ("PMB_BLOCK_X", x),
        ("PMB_BLOCK_Y", y),
        ("PMB_BLOCK_Z", z),
        ("PMB_WORKGROUP", workgroup),
    ] {
        d.push((name.into(), format!("{value}u")));
    }
    // A preprocessor condition: a plain 0 or 1.
    d.push((
        "PMB_SUBGROUP_SCAN".into(),
        u32::from(subgroup_arithmetic).to_string(),
    ));
    d
}

/// Defines for the PMB draw (`iso/pmb_draw`): the meshlet draw's (whose push constants,
/// culling codes and fragment shader it shares), the block size its boxes have and the
/// command pass's workgroup size.
pub fn pmb_draw_defines(block_size: crate::iso::pmb::PmbBlockSize) -> Vec<(String, String)> {
    let mut d = meshlet_draw_defines();
    let [x, y, z] = block_size.cells();
    for (name, value) in [
        ("PMB_BLOCK_X", x),
        ("PMB_BLOCK_Y", y),
        ("PMB_BLOCK_Z", z),
        ("PMB_DRAW_GROUP", crate::iso::pmb_draw::COMMAND_GROUP),
    ] {
        d.push((name.into(), format!("{value}u")));
    }
    d
}

/// The asteroid field's constants (`tet/interval/sdf.glsl`), from its CPU reference.
pub fn asteroid_defines() -> Vec<(String, String)> {
    use tessera_data::tet::asteroids as a;
    let v3 = |v: [f64; 3]| vec3(v.map(|c| c as f32));
    vec![
        ("SDF_AMPLITUDE".into(), float(a::AMPLITUDE as f32)),
        ("SDF_FREQUENCY".into(), float(a::FREQUENCY as f32)),
        ("SDF_OCTAVES".into(), a::OCTAVES.to_string()),
        ("SDF_STEPS".into(), a::STEPS.to_string()),
        ("SDF_STEP_SCALE".into(), float(a::STEP_SCALE as f32)),
        ("SDF_EPSILON".into(), float(a::EPSILON as f32)),
        ("SDF_LIGHT".into(), v3(a::LIGHT)),
        ("SDF_AMBIENT".into(), float(a::AMBIENT as f32)),
        ("SDF_DARK_ROCK".into(), v3(a::DARK_ROCK)),
        ("SDF_LIGHT_ROCK".into(), v3(a::LIGHT_ROCK)),
    ]
}
