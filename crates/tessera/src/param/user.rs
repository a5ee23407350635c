//! User functions: a GLSL file defining `vec3 f(float u, float v)` compiled into every pass of
//! the parametric techniques at run time (paper E: "a parametric function is expressed directly
//! in source code").
//!
//! The file is registered with the shader compiler under its own path and included, with `f`
//! renamed by a macro, into the header the passes include (`param/user_function.glsl`), so
//! glslang's messages name the user's file and line. Parameter ranges come from the command line
//! or from comment lines in the file:
//!
//! ```glsl
//! // u: 0 2pi
//! // v: -1 1
//! vec3 f(float u, float v) { return vec3(cos(u), sin(u), v); }
//! ```
//!
//! Range ends are numbers, optionally times `pi` or `tau` (`pi`, `2pi`, `0.5*pi`, `tau`).

use super::{GpuParamScene, ParamPoints};
use crate::error::{Error, Result};
use glam::Vec3;
use tessera_gpu::{Gpu, ShaderCompiler};

pub use tessera_data::param::user::{parse_end, UserFunction};

/// Samples per parameter direction when measuring a user function's extent.
const BOUND_SAMPLES: u32 = 65;
/// Margin on the measured radius for what lies between the samples.
const BOUND_MARGIN: f32 = 1.1;

/// The header the passes include for the user's function.
pub const USER_HEADER: &str = "param/user_function.glsl";
/// Its content where no user function is registered.
pub const NO_USER_FUNCTION: &str =
    "vec3 param_user_function(float u, float v) { return vec3(0.0); }\n";

/// Most bytes of local variables `f` may keep per invocation. Every sample evaluates `f` in
/// its own invocation, and drivers reserve that scratch memory for all of them at once: a
/// function with a large local array exhausted memory and brought the driver down.
pub const MAX_LOCAL_BYTES: u64 = 16 * 1024;

/// Makes the passes `compiler` builds evaluate `function`, after checking that it compiles on
/// its own and keeps at most [`MAX_LOCAL_BYTES`] of local variables. Whether it ends cannot be
/// told before it runs: a GPU time limit (`tessera_gpu::GpuOptions::timeout`) catches that.
pub fn register_user_function(
    function: &UserFunction,
    compiler: &mut ShaderCompiler,
) -> Result<()> {
    compiler.add_header(&function.name, &function.text);
    let alone = tessera_gpu::Source::new(
        format!("{}.comp", function.name),
        format!(
            "#version 460\nlayout(local_size_x = 1) in;\n\
             layout(std430, binding = 0) writeonly buffer Out {{ vec3 result; }};\n\
             #include \"{}\"\nvoid main() {{ result = f(0.5, 0.5); }}\n",
            function.name
        ),
    );
    let spirv = compiler.compile(&alone, &[])?;
    let bytes = tessera_gpu::spirv::invocation_local_bytes(&spirv.words);
    if bytes > MAX_LOCAL_BYTES {
        return Err(Error::Invalid(format!(
            "{}: f keeps {bytes} bytes of local variables per evaluation, more than the \
             {MAX_LOCAL_BYTES} a GPU can give each of its many simultaneous evaluations; use \
             smaller arrays",
            function.name
        )));
    }
    compiler.add_header(
        USER_HEADER,
        &format!(
            "#define f param_user_function\n#include \"{}\"\n#undef f\n",
            function.name
        ),
    );
    Ok(())
}

/// Sets the bounding sphere of object `object` (`function`) in `scene` from the function
/// evaluated on the GPU on a grid over its domain, with a margin: the CPU cannot evaluate it,
/// and the view's depth range is fitted to the bounds. Non-finite positions are errors.
pub fn measure_bounds(
    function: &UserFunction,
    gpu: &Gpu,
    points: &ParamPoints,
    scene: &mut GpuParamScene,
    object: u32,
) -> Result<()> {
    let [u0, u1] = function.domain.u;
    let [v0, v1] = function.domain.v;
    let n = BOUND_SAMPLES;
    let at = |i: u32, lo: f32, hi: f32| lo + (hi - lo) * i as f32 / (n - 1) as f32;
    let samples: Vec<(u32, f32, f32)> = (0..n * n)
        .map(|k| (object, at(k % n, u0, u1), at(k / n, v0, v1)))
        .collect();
    let results = points.probe(gpu, scene, &samples)?;
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for (r, &(_, u, v)) in results.iter().zip(&samples) {
        let p = Vec3::from_slice(&r.position[..3]);
        if !p.is_finite() {
            return Err(Error::Invalid(format!(
                "{}: f({u}, {v}) is not finite ({p})",
                function.name
            )));
        }
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let centre = (lo + hi) * 0.5;
    let radius = results
        .iter()
        .map(|r| Vec3::from_slice(&r.position[..3]).distance(centre))
        .fold(0.0f32, f32::max);
    let slot = scene
        .bounds
        .get_mut(object as usize)
        .ok_or_else(|| Error::Invalid(format!("no object {object} in the scene")))?;
    *slot = (centre, (radius * BOUND_MARGIN).max(1e-6));
    Ok(())
}
