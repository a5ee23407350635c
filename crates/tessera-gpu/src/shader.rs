//! GLSL → SPIR-V at run time through glslang, so `#define` variants and user functions need no
//! rebuild. Shared headers are registered by name and pulled in with `#include "name"`.
//! Compiled modules are cached in memory and on disk, keyed by everything that affects them.

use crate::error::{GpuError, Result};
use glslang::{
    include::{IncludeHandler, IncludeResult, IncludeType},
    Compiler, CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage,
    SpirvVersion, Target, VulkanVersion,
};
use std::collections::{BTreeMap, HashMap};
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// A shader's text and the path it is reported under (the file in the source tree for built-in
/// shaders, the user's file otherwise).
#[derive(Debug, Clone)]
pub struct Source {
    pub path: String,
    pub text: String,
}

impl Source {
    pub fn new(path: impl Into<String>, text: impl Into<String>) -> Source {
        Source {
            path: path.into(),
            text: text.into(),
        }
    }

    pub fn from_file(path: &Path) -> Result<Source> {
        let text = std::fs::read_to_string(path).map_err(|e| GpuError::ShaderCompile {
            path: path.display().to_string(),
            log: format!("cannot read: {e}"),
        })?;
        Ok(Source::new(path.display().to_string(), text))
    }

    /// The stage follows the `name.stage.glsl` convention.
    pub fn stage(&self) -> Result<Stage> {
        let stem = self.path.trim_end_matches(".glsl");
        let ext = stem.rsplit('.').next().unwrap_or("");
        Stage::from_extension(ext).ok_or_else(|| GpuError::ShaderCompile {
            path: self.path.clone(),
            log: format!("cannot tell the stage from '.{ext}': name shaders name.STAGE.glsl"),
        })
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stage {
    Vertex,
    TessControl,
    TessEval,
    Fragment,
    Compute,
    Task,
    Mesh,
    RayGen,
    ClosestHit,
    Miss,
    AnyHit,
    Intersection,
}

impl Stage {
    pub fn from_extension(ext: &str) -> Option<Stage> {
        Some(match ext {
            "vert" => Stage::Vertex,
            "tesc" => Stage::TessControl,
            "tese" => Stage::TessEval,
            "frag" => Stage::Fragment,
            "comp" => Stage::Compute,
            "task" => Stage::Task,
            "mesh" => Stage::Mesh,
            "rgen" => Stage::RayGen,
            "rchit" => Stage::ClosestHit,
            "rmiss" => Stage::Miss,
            "rahit" => Stage::AnyHit,
            "rint" => Stage::Intersection,
            _ => return None,
        })
    }

    fn glslang(self) -> ShaderStage {
        match self {
            Stage::Vertex => ShaderStage::Vertex,
            Stage::TessControl => ShaderStage::TesselationControl,
            Stage::TessEval => ShaderStage::TesselationEvaluation,
            Stage::Fragment => ShaderStage::Fragment,
            Stage::Compute => ShaderStage::Compute,
            Stage::Task => ShaderStage::Task,
            Stage::Mesh => ShaderStage::Mesh,
            Stage::RayGen => ShaderStage::RayGeneration,
            Stage::ClosestHit => ShaderStage::ClosestHit,
            Stage::Miss => ShaderStage::Miss,
            Stage::AnyHit => ShaderStage::AnyHit,
            Stage::Intersection => ShaderStage::Intersect,
        }
    }
}

/// A compiled module with the facts read back from its SPIR-V.
#[derive(Debug, Clone)]
pub struct Spirv {
    pub path: String,
    pub stage: Stage,
    pub words: Vec<u32>,
}

impl Spirv {
    /// The workgroup size declared by a compute, task or mesh shader.
    pub fn local_size(&self) -> Result<[u32; 3]> {
        crate::spirv::local_size(&self.words).ok_or_else(|| GpuError::ShaderReflect {
            path: self.path.clone(),
            message: "no LocalSize execution mode".into(),
        })
    }
}

/// Compiles shaders, resolving `#include` against registered headers and, for files on disk,
/// against the including file's folder.
pub struct ShaderCompiler {
    headers: BTreeMap<String, String>,
    memory_cache: Mutex<HashMap<u64, Vec<u32>>>,
    disk_cache: Option<PathBuf>,
}

struct Includer<'a> {
    headers: &'a BTreeMap<String, String>,
    root_dir: Option<PathBuf>,
}

impl IncludeHandler for Includer<'_> {
    fn include(
        &mut self,
        _ty: IncludeType,
        header_name: &str,
        _includer: &str,
        _depth: usize,
    ) -> Option<IncludeResult> {
        if let Some(text) = self.headers.get(header_name) {
            return Some(IncludeResult {
                name: header_name.to_string(),
                data: text.clone(),
            });
        }
        let path = self.root_dir.as_ref()?.join(header_name);
        let data = std::fs::read_to_string(&path).ok()?;
        Some(IncludeResult {
            name: path.display().to_string(),
            data,
        })
    }
}

fn default_cache_dir() -> Option<PathBuf> {
    if std::env::var_os("TESSERA_SHADER_CACHE").is_some_and(|v| v == "0") {
        return None;
    }
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("tessera").join("spirv"))
}

impl Default for ShaderCompiler {
    fn default() -> Self {
        Self::new()
    }
}

impl ShaderCompiler {
    pub fn new() -> ShaderCompiler {
        ShaderCompiler {
            headers: BTreeMap::new(),
            memory_cache: Mutex::new(HashMap::new()),
            disk_cache: default_cache_dir(),
        }
    }

    /// Makes `text` available to `#include "name"`.
    pub fn add_header(&mut self, name: &str, text: &str) {
        self.headers.insert(name.to_string(), text.to_string());
    }

    pub fn without_disk_cache(mut self) -> Self {
        self.disk_cache = None;
        self
    }

    fn cache_key(&self, source: &Source, stage: Stage, defines: &[(String, String)]) -> u64 {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        env!("CARGO_PKG_VERSION").hash(&mut h);
        source.path.hash(&mut h);
        source.text.hash(&mut h);
        stage.hash(&mut h);
        defines.hash(&mut h);
        self.headers.hash(&mut h);
        h.finish()
    }

    /// Compiles `source`; `defines` become `#define NAME VALUE` lines ahead of the text.
    /// Warnings count as errors so that shaders stay clean.
    pub fn compile(&self, source: &Source, defines: &[(String, String)]) -> Result<Spirv> {
        let stage = source.stage()?;
        let key = self.cache_key(source, stage, defines);
        let cached = self
            .memory_cache
            .lock()
            .ok()
            .and_then(|c| c.get(&key).cloned());
        let words = match cached.or_else(|| self.read_disk(key)) {
            Some(words) => words,
            None => {
                let words = self.compile_uncached(source, stage, defines)?;
                self.write_disk(key, &words);
                words
            }
        };
        if let Ok(mut c) = self.memory_cache.lock() {
            c.insert(key, words.clone());
        }
        Ok(Spirv {
            path: source.path.clone(),
            stage,
            words,
        })
    }

    fn read_disk(&self, key: u64) -> Option<Vec<u32>> {
        let bytes =
            std::fs::read(self.disk_cache.as_ref()?.join(format!("{key:016x}.spv"))).ok()?;
        if bytes.len() % 4 != 0 || bytes.len() < 20 {
            return None;
        }
        let words: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        (words[0] == 0x0723_0203).then_some(words)
    }

    fn write_disk(&self, key: u64, words: &[u32]) {
        // The cache only saves time; a read-only home must not stop rendering.
        if let Some(dir) = &self.disk_cache {
            if std::fs::create_dir_all(dir).is_ok() {
                let tmp = dir.join(format!("{key:016x}.{}.tmp", std::process::id()));
                let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
                if std::fs::write(&tmp, bytes).is_ok() {
                    let _ = std::fs::rename(&tmp, dir.join(format!("{key:016x}.spv")));
                }
            }
        }
    }

    fn compile_uncached(
        &self,
        source: &Source,
        stage: Stage,
        defines: &[(String, String)],
    ) -> Result<Vec<u32>> {
        let fail = |log: String| GpuError::ShaderCompile {
            path: source.path.clone(),
            log: attribute_log(&log, &source.path),
        };
        let compiler = Compiler::acquire().ok_or_else(|| fail("glslang failed to start".into()))?;
        // The include extension goes in first so that every shader may `#include`.
        let text = insert_after_version(
            &source.text,
            "#extension GL_GOOGLE_include_directive : require\n",
        );
        let glsl = ShaderSource::from(text);
        let options = CompilerOptions {
            source_language: SourceLanguage::GLSL,
            target: Target::Vulkan {
                version: VulkanVersion::Vulkan1_3,
                spirv_version: SpirvVersion::SPIRV1_6,
            },
            version_profile: None,
            messages: glslang::ShaderMessage::DEFAULT,
        };
        let define_pairs: Vec<(&str, Option<&str>)> = defines
            .iter()
            .map(|(k, v)| (k.as_str(), Some(v.as_str())))
            .collect();
        let mut includer = Includer {
            headers: &self.headers,
            root_dir: Path::new(&source.path).parent().map(Path::to_path_buf),
        };
        let input = ShaderInput::new(
            &glsl,
            stage.glslang(),
            &options,
            Some(&define_pairs[..]),
            Some(&mut includer),
        )
        .map_err(|e| fail(e.to_string()))?;
        let shader = compiler
            .create_shader(input)
            .map_err(|e| fail(e.to_string()))?;
        let log = shader.get_log();
        if log.contains("WARNING") {
            return Err(fail(log));
        }
        shader.compile().map_err(|e| fail(e.to_string()))
    }
}

fn insert_after_version(text: &str, line: &str) -> String {
    match text.find("#version") {
        Some(start) => {
            let end = text[start..]
                .find('\n')
                .map_or(text.len(), |i| start + i + 1);
            // A #line keeps reported line numbers equal to the file's own.
            let version_line = text[..start].matches('\n').count() + 1;
            format!(
                "{}{}{line}#line {}\n{}",
                &text[..start],
                &text[start..end],
                version_line + 1,
                &text[end..]
            )
        }
        None => format!("{line}{text}"),
    }
}

/// glslang names the main source "0"; replace that with the file path so that messages read
/// `path:line: error`.
fn attribute_log(log: &str, path: &str) -> String {
    log.replace("ERROR: 0:", &format!("ERROR: {path}:"))
        .replace("WARNING: 0:", &format!("WARNING: {path}:"))
}

#[cfg(test)]
mod tests {
    use super::*;

    const ADD: &str = "#version 460\nlayout(local_size_x = 64, local_size_y = 2) in;\nlayout(binding = 0) buffer B { uint v[]; };\nvoid main() { v[gl_GlobalInvocationID.x] += VALUE; }\n";

    #[test]
    fn compiles_with_defines_and_reports_local_size() {
        let c = ShaderCompiler::new().without_disk_cache();
        let spv = c
            .compile(
                &Source::new("add.comp.glsl", ADD),
                &[("VALUE".into(), "3u".into())],
            )
            .unwrap();
        assert_eq!(spv.words[0], 0x0723_0203);
        assert_eq!(spv.local_size().unwrap(), [64, 2, 1]);
    }

    #[test]
    fn error_names_file_and_line() {
        let c = ShaderCompiler::new().without_disk_cache();
        let text = "#version 460\nlayout(local_size_x = 1) in;\nvoid main() {\n  float x = undefined_thing;\n}\n";
        let err = c
            .compile(&Source::new("bad/user.comp.glsl", text), &[])
            .unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("bad/user.comp.glsl:4"), "{msg}");
        assert!(msg.contains("undefined_thing"), "{msg}");
    }

    #[test]
    fn includes_registered_headers() {
        let mut c = ShaderCompiler::new().without_disk_cache();
        c.add_header("common/value.glsl", "const uint VALUE_FROM_HEADER = 7u;\n");
        let text = "#version 460\n#include \"common/value.glsl\"\nlayout(local_size_x = 8) in;\nlayout(binding = 0) buffer B { uint v[]; };\nvoid main() { v[0] = VALUE_FROM_HEADER; }\n";
        c.compile(&Source::new("inc.comp.glsl", text), &[]).unwrap();
        let missing = text.replace("common/value.glsl", "common/missing.glsl");
        assert!(c
            .compile(&Source::new("inc.comp.glsl", missing), &[])
            .is_err());
    }

    #[test]
    fn stage_from_name() {
        assert_eq!(
            Source::new("a/b.mesh.glsl", "").stage().unwrap(),
            Stage::Mesh
        );
        assert!(Source::new("a/b.glsl", "").stage().is_err());
    }
}
