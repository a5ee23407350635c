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
use std::path::Path;
use tessera_data::param::ParamDomain;
use tessera_gpu::{Gpu, ShaderCompiler};

/// Samples per parameter direction when measuring a user function's extent.
const BOUND_SAMPLES: u32 = 65;
/// Margin on the measured radius for what lies between the samples.
const BOUND_MARGIN: f32 = 1.1;

/// The header the passes include for the user's function.
pub const USER_HEADER: &str = "param/user_function.glsl";
/// Its content where no user function is registered.
pub const NO_USER_FUNCTION: &str =
    "vec3 param_user_function(float u, float v) { return vec3(0.0); }\n";

/// A user's surface: where it came from, its text and its parameter domain.
#[derive(Debug, Clone)]
pub struct UserFunction {
    pub name: String,
    pub text: String,
    pub domain: ParamDomain,
}

impl UserFunction {
    /// Reads `path` and checks that it defines `vec3 f(float, float)`; `u`/`v` override the
    /// ranges the file gives, and one of the two must give each.
    pub fn load(path: &Path, u: Option<[f32; 2]>, v: Option<[f32; 2]>) -> Result<UserFunction> {
        let name = path.display().to_string();
        let text =
            std::fs::read_to_string(path).map_err(|e| Error::Invalid(format!("{name}: {e}")))?;
        UserFunction::from_text(&name, &text, u, v)
    }

    pub fn from_text(
        name: &str,
        text: &str,
        u: Option<[f32; 2]>,
        v: Option<[f32; 2]>,
    ) -> Result<UserFunction> {
        let fail = |message: String| Error::Invalid(format!("{name}: {message}"));
        check_signature(text).map_err(fail)?;
        let (file_u, file_v) = ranges(text).map_err(fail)?;
        let missing = |axis: &str| {
            fail(format!(
                "no range for {axis}: add a line '// {axis}: FROM TO' or give --{axis}-range"
            ))
        };
        let u = u.or(file_u).ok_or_else(|| missing("u"))?;
        let v = v.or(file_v).ok_or_else(|| missing("v"))?;
        let domain = ParamDomain::new(u, v).map_err(|e| fail(e.to_string()))?;
        Ok(UserFunction {
            name: name.to_string(),
            text: text.to_string(),
            domain,
        })
    }

    /// Makes the passes `compiler` builds evaluate this function.
    pub fn register(&self, compiler: &mut ShaderCompiler) {
        compiler.add_header(&self.name, &self.text);
        compiler.add_header(
            USER_HEADER,
            &format!(
                "#define f param_user_function\n#include \"{}\"\n#undef f\n",
                self.name
            ),
        );
    }
}

impl UserFunction {
    /// Sets the bounding sphere of object `object` (this function) in `scene` from the function
    /// evaluated on the GPU on a grid over its domain, with a margin: the CPU cannot evaluate
    /// it, and the view's depth range is fitted to the bounds. Non-finite positions are errors.
    pub fn measure_bounds(
        &self,
        gpu: &Gpu,
        points: &ParamPoints,
        scene: &mut GpuParamScene,
        object: u32,
    ) -> Result<()> {
        let [u0, u1] = self.domain.u;
        let [v0, v1] = self.domain.v;
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
                    self.name
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
}

/// The text without comments, lines kept (so positions still count lines).
fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, chars.peek()) {
            ('/', Some('/')) => {
                while chars.peek().is_some_and(|&c| c != '\n') {
                    chars.next();
                }
            }
            ('/', Some('*')) => {
                chars.next();
                let mut last = ' ';
                for c in chars.by_ref() {
                    if c == '\n' {
                        out.push('\n');
                    }
                    if last == '*' && c == '/' {
                        break;
                    }
                    last = c;
                }
            }
            _ => out.push(c),
        }
    }
    out
}

/// `vec3 f(float a, float b)` must be defined; a definition of `f` with other parameters or
/// return type is named with its line.
fn check_signature(text: &str) -> std::result::Result<(), String> {
    let code = strip_comments(text);
    let tokens = tokenize(&code);
    let wanted = "vec3 f(float u, float v)";
    for (i, (token, line)) in tokens.iter().enumerate() {
        if token != "f" || tokens.get(i + 1).map(|t| t.0.as_str()) != Some("(") {
            continue;
        }
        let Some(close) = tokens[i..].iter().position(|t| t.0 == ")") else {
            return Err(format!("line {line}: unfinished parameter list of f"));
        };
        let params: Vec<&str> = tokens[i + 2..i + close]
            .iter()
            .map(|t| t.0.as_str())
            .collect();
        let returns = i.checked_sub(1).map(|j| tokens[j].0.as_str());
        // A call of f (e.g. inside another function) has no type before it; skip those.
        if !matches!(
            returns,
            Some("vec3" | "float" | "vec2" | "vec4" | "void" | "int")
        ) {
            continue;
        }
        let floats = matches!(params[..], ["float", _, ",", "float", _]);
        if returns == Some("vec3") && floats {
            return Ok(());
        }
        return Err(format!(
            "line {line}: f must be `{wanted}`, found `{} f({})`",
            returns.unwrap_or(""),
            params.join(" ").replace(" ,", ",")
        ));
    }
    Err(format!("no function `{wanted}` (the surface to draw)"))
}

/// Identifiers, numbers and single punctuation characters, with their lines.
fn tokenize(code: &str) -> Vec<(String, usize)> {
    let mut tokens = Vec::new();
    for (number, line) in code.lines().enumerate() {
        let mut word = String::new();
        for c in line.chars() {
            if c.is_alphanumeric() || c == '_' || c == '.' {
                word.push(c);
                continue;
            }
            if !word.is_empty() {
                tokens.push((std::mem::take(&mut word), number + 1));
            }
            if !c.is_whitespace() {
                tokens.push((c.to_string(), number + 1));
            }
        }
        if !word.is_empty() {
            tokens.push((word, number + 1));
        }
    }
    tokens
}

type Range = Option<[f32; 2]>;

/// The `// u: A B` and `// v: A B` lines.
fn ranges(text: &str) -> std::result::Result<(Range, Range), String> {
    let mut found = (None, None);
    for (number, line) in text.lines().enumerate() {
        let Some(rest) = line.trim().strip_prefix("//") else {
            continue;
        };
        let rest = rest.trim();
        let (slot, values) = match rest.split_once(':') {
            Some(("u", values)) => (&mut found.0, values),
            Some(("v", values)) => (&mut found.1, values),
            _ => continue,
        };
        let ends: Vec<f32> = values
            .split_whitespace()
            .map(parse_end)
            .collect::<Option<_>>()
            .ok_or_else(|| {
                format!(
                    "line {}: expected two numbers, found '{values}'",
                    number + 1
                )
            })?;
        let [a, b] = ends[..] else {
            return Err(format!("line {}: expected two numbers", number + 1));
        };
        *slot = Some([a, b]);
    }
    Ok(found)
}

/// A number, optionally times pi or tau: `1.5`, `pi`, `2pi`, `0.5*pi`, `tau`, `-pi`.
pub fn parse_end(text: &str) -> Option<f32> {
    let t = text.trim().to_ascii_lowercase();
    for (name, value) in [("tau", std::f32::consts::TAU), ("pi", std::f32::consts::PI)] {
        if let Some(factor) = t.strip_suffix(name) {
            let factor = factor.trim_end_matches('*');
            let k = match factor {
                "" => 1.0,
                "-" => -1.0,
                f => f.parse::<f32>().ok()?,
            };
            return Some(k * value).filter(|v| v.is_finite());
        }
    }
    t.parse::<f32>().ok().filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TORUS: &str = "// u: 0 2pi\n// v: 0 tau\nvec3 f(float u, float v) {\n    return vec3((1.0 + 0.3 * cos(v)) * cos(u), (1.0 + 0.3 * cos(v)) * sin(u), 0.3 * sin(v));\n}\n";

    #[test]
    fn reads_ranges_and_signature() {
        let f = UserFunction::from_text("torus.glsl", TORUS, None, None).unwrap();
        assert_eq!(f.domain.u, [0.0, std::f32::consts::TAU]);
        let f = UserFunction::from_text("torus.glsl", TORUS, Some([0.0, 1.0]), None).unwrap();
        assert_eq!(f.domain.u, [0.0, 1.0]);
        assert_eq!(parse_end("0.5*pi"), Some(std::f32::consts::FRAC_PI_2));
        assert_eq!(parse_end("-pi"), Some(-std::f32::consts::PI));
        assert_eq!(parse_end("x"), None);
    }

    #[test]
    fn refuses_bad_files_by_name_and_line() {
        let cases = [
            (
                "vec3 g(float u, float v) { return vec3(u); }\n",
                "no function",
            ),
            (
                "// u: 0 1\n// v: 0 1\nvec3 f(float u) { return vec3(u); }\n",
                "line 3",
            ),
            (
                "// u: 0 1\n// v: 0 1\nfloat f(float u, float v) { return u; }\n",
                "found `float f",
            ),
            (
                "// u: 0 1\nvec3 f(float u, float v) { return vec3(u); }\n",
                "no range for v",
            ),
            (
                "// u: 0 one\n// v: 0 1\nvec3 f(float u, float v) { return vec3(u); }\n",
                "line 1",
            ),
            (
                "// u: 1 1\n// v: 0 1\nvec3 f(float u, float v) { return vec3(u); }\n",
                "surf.glsl",
            ),
        ];
        for (text, expected) in cases {
            let err = UserFunction::from_text("surf.glsl", text, None, None)
                .unwrap_err()
                .to_string();
            assert!(
                err.contains("surf.glsl") && err.contains(expected),
                "{text:?}: {err}"
            );
        }
        // A commented-out definition does not count.
        let err = UserFunction::from_text("s.glsl", "// vec3 f(float u, float v)\n", None, None)
            .unwrap_err()
            .to_string();
        assert!(err.contains("no function"), "{err}");
    }
}
