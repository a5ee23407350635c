//! The interactive viewer behind `tessera view`: a window that shows what the renderer front
//! door ([`tessera::renderer`]) draws, presented straight from the GPU target (no read back),
//! with egui controls to turn the object, edit the look and switch technique, an overlay of
//! GPU times and counts, and scripts that drive the same frame loop without a person.
//!
//! - [`session`]: the data, its look, the camera and the renderers; renders on change.
//! - [`app`]: the window, its event loop and the frame loop (script steps included).
//! - [`present`]: the swapchain and the egui renderer over the rendered image.
//! - [`controls`], [`tf_editor`], [`orbit`]: the panels and the mouse.
//! - [`script`]: the text format of scripted runs.
//! - [`offscreen`]: scripted runs without a window, for GPU machines with no display.

pub mod app;
pub mod controls;
pub mod error;
pub mod offscreen;
pub mod orbit;
pub mod present;
pub mod script;
pub mod session;
pub mod tf_editor;

pub use error::ViewError;
pub use script::{Script, Step};
pub use session::Scene;

use std::path::PathBuf;
use tessera_gpu::GpuOptions;

/// How the viewer runs.
#[derive(Debug, Clone)]
pub struct Settings {
    pub gpu: GpuOptions,
    /// Initial window size in pixels.
    pub size: (u32, u32),
    /// Where the screenshot key writes (a number is added when the file exists).
    pub screenshot: PathBuf,
    /// Steps to run instead of waiting for a person; the viewer exits after the last.
    pub script: Option<Script>,
    /// Render every frame, not only after a change.
    pub continuous: bool,
}

/// What a run did, for the terminal and for tests.
#[derive(Debug, Clone, Default)]
pub struct Summary {
    pub frames: u64,
    /// Live device allocations after each rendered frame (the `Gpu`'s allocator), so a test
    /// can see that the frame loop allocates nothing once warm.
    pub allocations: Vec<u64>,
    pub screenshots: Vec<PathBuf>,
    /// GPU milliseconds of each rendered frame (offscreen runs).
    pub frame_ms: Vec<f64>,
}

/// The frame after which allocations must stay constant.
pub const WARM_FRAME: usize = 5;

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "view: {} frames", self.frames)?;
        if let (Some(warm), Some(last)) = (
            self.allocations.get(WARM_FRAME - 1),
            self.allocations.last(),
        ) {
            write!(
                f,
                "; device allocations after frame {WARM_FRAME}: {warm}, after frame {}: {last}",
                self.allocations.len()
            )?;
        }
        if !self.frame_ms.is_empty() {
            let mut sorted = self.frame_ms.clone();
            sorted.sort_by(f64::total_cmp);
            write!(
                f,
                "\nGPU frame time over {} frames: median {:.3} ms, min {:.3}, max {:.3}",
                sorted.len(),
                sorted[sorted.len() / 2],
                sorted[0],
                sorted[sorted.len() - 1]
            )?;
        }
        for path in &self.screenshots {
            write!(f, "\nscreenshot {}", path.display())?;
        }
        Ok(())
    }
}

/// Fails with [`ViewError::NoDisplay`] where no window system is reachable (neither
/// `DISPLAY` nor `WAYLAND_DISPLAY` set), before anything is loaded.
pub fn check_display() -> Result<(), ViewError> {
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    if set("DISPLAY") || set("WAYLAND_DISPLAY") {
        Ok(())
    } else {
        Err(ViewError::NoDisplay)
    }
}

/// Opens the window on `scene` and runs until it is closed or the script ends.
pub fn run(scene: Scene, settings: Settings) -> Result<Summary, ViewError> {
    check_display()?;
    app::run(scene, settings)
}

/// Runs the script of `settings` on `scene` without a window ([`offscreen`]).
pub fn run_offscreen(scene: Scene, settings: Settings) -> Result<Summary, ViewError> {
    offscreen::run(scene, settings)
}
