//! What can go wrong in the viewer, worded for the person at the terminal.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    #[error(
        "no display: neither DISPLAY nor WAYLAND_DISPLAY is set. The viewer needs a window \
         system; without one, run it under a virtual X server (`xvfb-run -a tessera view …`) \
         or use `tessera render`"
    )]
    NoDisplay,
    #[error("cannot open a window: {0} (without a display, run under `xvfb-run -a`)")]
    Window(String),
    #[error(transparent)]
    Gpu(#[from] tessera_gpu::GpuError),
    #[error(transparent)]
    Render(#[from] tessera::Error),
    #[error(transparent)]
    Data(#[from] tessera_data::DataError),
    #[error("drawing the controls: {0}")]
    Overlay(String),
    #[error("script {path}, line {line}: {message}")]
    Script {
        path: String,
        line: usize,
        message: String,
    },
    #[error("{path}: {message}")]
    File { path: PathBuf, message: String },
    #[error("an offscreen run has no one at the controls: give it --script")]
    OffscreenWithoutScript,
    #[error("the validation layer reported {0} error(s)")]
    Validation(usize),
}
