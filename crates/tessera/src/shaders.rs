//! The shader compiler set up with Tessera's shared GLSL headers.

use tessera_gpu::{ShaderCompiler, Source};

/// Shared headers, included as `#include "common/NAME.glsl"`.
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
        "common/throughput.glsl",
        include_str!("shaders/common/throughput.glsl"),
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
    c
}
