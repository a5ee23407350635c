//! Drivers inline every call, so each call site of a parametric function's evaluation becomes
//! one more copy of every built-in function and the user's `f` for the shader compiler to
//! optimise. Shading written with one call per finite-difference point once held ~66 copies and
//! took llvmpipe minutes per pipeline; these counts keep every pass small.

use crate::builtin_shader;
use crate::param::lod::lod_defines;
use crate::param::points::points_defines;
use tessera_gpu::spirv::inlined_copies;

/// Position, normal and base colour: one evaluation site each.
const MOST_COPIES: u64 = 3;

#[test]
fn every_parametric_pass_evaluates_the_functions_at_few_call_sites() {
    let compiler = crate::shaders::compiler();
    let (lod, points) = (lod_defines(), points_defines());
    let passes = [
        (builtin_shader!("lod_step.comp.glsl"), &lod),
        (builtin_shader!("points.comp.glsl"), &points),
        (builtin_shader!("resolve.comp.glsl"), &points),
        (builtin_shader!("probe.comp.glsl"), &points),
        (builtin_shader!("tess.tesc.glsl"), &points),
        (builtin_shader!("tess.tese.glsl"), &points),
        (builtin_shader!("tess.frag.glsl"), &points),
    ];
    for (source, defines) in passes {
        let spirv = compiler
            .compile(&source, defines)
            .unwrap_or_else(|e| panic!("{e}"));
        let copies = inlined_copies(&spirv.words, "param_position")
            .unwrap_or_else(|| panic!("{}: no param_position", source.path));
        assert!(
            (1..=MOST_COPIES).contains(&copies),
            "{}: param_position inlined {copies} times (at most {MOST_COPIES})",
            source.path
        );
    }
}

/// The ray tracer evaluates the SH series once while intersecting and once for the normal.
#[test]
fn the_ray_tracer_evaluates_the_sh_series_at_few_call_sites() {
    let compiler = crate::shaders::compiler();
    let defines = crate::param::raytrace::raytrace_defines(12);
    for source in [
        builtin_shader!("raytrace.comp.glsl"),
        builtin_shader!("raytrace_probe.comp.glsl"),
    ] {
        let spirv = compiler
            .compile(&source, &defines)
            .unwrap_or_else(|e| panic!("{e}"));
        let copies = inlined_copies(&spirv.words, "sh_evaluate")
            .unwrap_or_else(|| panic!("{}: no sh_evaluate", source.path));
        assert!(
            (1..=2).contains(&copies),
            "{}: sh_evaluate inlined {copies} times (at most 2)",
            source.path
        );
    }
}
