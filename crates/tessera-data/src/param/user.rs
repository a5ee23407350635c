//! User functions: a GLSL file defining `vec3 f(float u, float v)` that the parametric
//! techniques compile into every pass at run time (paper E: "a parametric function is expressed
//! directly in source code"). This is the part the CPU can do: reading the file, checking that
//! it defines `f`, and its parameter domain; compiling and measuring it is tessera's
//! (`tessera::param::user`).
//!
//! Parameter ranges come from the command line or from comment lines in the file:
//!
//! ```glsl
//! // u: 0 2pi
//! // v: -1 1
//! vec3 f(float u, float v) { return vec3(cos(u), sin(u), v); }
//! ```
//!
//! Range ends are numbers, optionally times `pi` or `tau` (`pi`, `2pi`, `0.5*pi`, `tau`).

use std::path::Path;

use super::ParamDomain;
use crate::error::{DataError, Result};

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
        let text = std::fs::read_to_string(path).map_err(|e| DataError::io(path, e))?;
        UserFunction::from_text(&name, &text, u, v)
    }

    pub fn from_text(
        name: &str,
        text: &str,
        u: Option<[f32; 2]>,
        v: Option<[f32; 2]>,
    ) -> Result<UserFunction> {
        let fail = |message: String| DataError::Invalid(format!("{name}: {message}"));
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
#[path = "user_tests.rs"]
mod tests;
