//! Scripted runs without a window, for machines with a GPU and no display: the same session
//! and script steps as the windowed frame loop, each frame rendered into the session's target
//! and its GPU time kept, but nothing presented (no swapchain, no controls).

use crate::error::ViewError;
use crate::script::{Before, Runner};
use crate::session::{Scene, Session};
use crate::{Settings, Summary};
use tessera_gpu::Gpu;

/// Runs `settings.script` (required) on `scene` offscreen at `settings.size` (until a `size`
/// step changes it).
pub fn run(scene: Scene, settings: Settings) -> Result<Summary, ViewError> {
    let script = settings.script.ok_or(ViewError::OffscreenWithoutScript)?;
    let gpu = Gpu::new(&settings.gpu)?;
    let validation = gpu.validation_log();
    let validating = gpu.validation_enabled();
    let mut session = Session::new(&gpu, scene)?;
    let mut runner = Runner::new(script);
    let mut summary = Summary::default();
    let mut size = settings.size;
    loop {
        let mut asked = None;
        let before = runner.before_frame(&mut session, &mut |w, h| asked = Some((w, h)), size)?;
        if let Some(new_size) = asked {
            size = new_size; // no window system to wait for
        }
        match before {
            Before::Done => break,
            Before::Wait => continue,
            Before::Render => {}
        }
        session.render(&gpu, size)?;
        summary.frames += 1;
        summary.allocations.push(gpu.memory_report().allocations);
        summary.frame_ms.push(session.times.total_ms());
        if let Some(path) = runner.after_frame()? {
            if session.write_png(&gpu, &path)? {
                summary.screenshots.push(path);
            }
        }
    }
    // The renderers, then the device: validation sees them go.
    drop(session);
    drop(gpu);
    let errors = validation.errors().len();
    if validating && errors > 0 {
        return Err(ViewError::Validation(errors));
    }
    Ok(summary)
}
