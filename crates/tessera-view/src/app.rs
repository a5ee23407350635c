//! The window and its event loop. Each redraw runs the script's steps due before the frame,
//! lays out the panels, renders the data when the view changed (every frame when
//! continuous or scripted), shows the image with the panels over it, and then takes the
//! screenshot or the script step that waits for the frame.

use crate::controls::Panels;
use crate::error::ViewError;
use crate::present::Presenter;
use crate::script::Runner;
use crate::session::{Scene, Session};
use crate::{Settings, Summary};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use std::path::{Path, PathBuf};
use tessera_gpu::Gpu;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

/// The window with what draws into it; fields drop in order, the surface before the window.
struct Windowed {
    presenter: Presenter,
    input: egui_winit::State,
    /// The window's size from its last resize event: asking the window system instead fails
    /// once the window is gone (destroyed from outside), and a failed swapchain then ends the
    /// run with an error.
    size: PhysicalSize<u32>,
    window: Window,
}

struct App {
    // Dropped first: the presenter's objects must go before the device.
    windowed: Option<Windowed>,
    session: Session,
    panels: Panels,
    egui: egui::Context,
    script: Option<Runner>,
    size: (u32, u32),
    screenshot: PathBuf,
    summary: Summary,
    outcome: Result<(), ViewError>,
    gpu: Gpu,
}

/// Opens the window on `scene` and runs the event loop until the window closes or the
/// script ends.
pub fn run(scene: Scene, settings: Settings) -> Result<Summary, ViewError> {
    let window_error = |e: &dyn std::fmt::Display| ViewError::Window(e.to_string());
    let event_loop = EventLoop::new().map_err(|e| window_error(&e))?;
    let display = event_loop
        .display_handle()
        .map_err(|e| window_error(&e))?
        .as_raw();
    let gpu = Gpu::for_display(&settings.gpu, display)?;
    let validation = gpu.validation_log();
    let validating = gpu.validation_enabled();
    let panels = Panels::new(&scene.dataset, settings.continuous);
    let session = Session::new(&gpu, scene)?;
    let mut app = App {
        windowed: None,
        session,
        panels,
        egui: egui::Context::default(),
        script: settings.script.map(Runner::new),
        size: settings.size,
        screenshot: settings.screenshot,
        summary: Summary::default(),
        outcome: Ok(()),
        gpu,
    };
    let ran = event_loop.run_app(&mut app);
    let App {
        windowed,
        session,
        outcome,
        summary,
        gpu,
        ..
    } = app;
    // The window's objects, then the renderers, then the device: validation sees them all go.
    drop(windowed);
    drop(session);
    drop(gpu);
    ran.map_err(|e| window_error(&e))?;
    outcome?;
    let errors = validation.errors().len();
    if validating && errors > 0 {
        return Err(ViewError::Validation(errors));
    }
    Ok(summary)
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: ViewError) {
        if self.outcome.is_ok() {
            self.outcome = Err(error);
        }
        event_loop.exit();
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<(), ViewError> {
        let attributes = Window::default_attributes()
            .with_title(format!("tessera view: {}", self.session.name))
            .with_inner_size(PhysicalSize::new(self.size.0, self.size.1));
        let window = event_loop
            .create_window(attributes)
            .map_err(|e| ViewError::Window(e.to_string()))?;
        let handle = |e: raw_window_handle::HandleError| ViewError::Window(e.to_string());
        let display = window.display_handle().map_err(handle)?.as_raw();
        let raw = window.window_handle().map_err(handle)?.as_raw();
        let size = window.inner_size();
        let presenter = Presenter::new(&self.gpu, display, raw, (size.width, size.height))?;
        let input = egui_winit::State::new(
            self.egui.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            None,
        );
        window.request_redraw();
        self.windowed = Some(Windowed {
            presenter,
            input,
            size,
            window,
        });
        Ok(())
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<(), ViewError> {
        let Some(w) = self.windowed.as_mut().filter(|_| !event_loop.exiting()) else {
            return Ok(());
        };
        let size = w.size;
        if size.width == 0 || size.height == 0 {
            return Ok(()); // minimised: nothing to show
        }
        let size = (size.width, size.height);
        if let Some(runner) = &mut self.script {
            let window = &w.window;
            let mut request_size = |width, height| {
                let _ = window.request_inner_size(winit::dpi::PhysicalSize::new(width, height));
            };
            match runner.before_frame(&mut self.session, &mut request_size, size)? {
                crate::script::Before::Render => {}
                crate::script::Before::Wait => return Ok(()),
                crate::script::Before::Done => {
                    event_loop.exit();
                    return Ok(());
                }
            }
        }
        w.presenter.fit(&self.gpu, size)?;
        let extent = w.presenter.size();
        let raw_input = w.input.take_egui_input(&w.window);
        let (panels, session) = (&mut self.panels, &mut self.session);
        let output = self.egui.run(raw_input, |ctx| panels.show(ctx, session));
        w.input
            .handle_platform_output(&w.window, output.platform_output);
        let scripted = self.script.is_some();
        if scripted || self.panels.continuous || self.session.stale(extent) {
            self.session.render(&self.gpu, extent)?;
            self.summary.frames += 1;
            self.summary
                .allocations
                .push(self.gpu.memory_report().allocations);
        }
        let Some(target) = self.session.target() else {
            return Ok(());
        };
        let primitives = self.egui.tessellate(output.shapes, output.pixels_per_point);
        w.presenter.show(
            &self.gpu,
            target,
            &output.textures_delta,
            output.pixels_per_point,
            &primitives,
        )?;
        if std::mem::take(&mut self.panels.screenshot) {
            let path = free_name(&self.screenshot);
            self.panels.status = Some(match self.write_screenshot(&path) {
                Ok(()) => format!("wrote {}", path.display()),
                Err(e) => e.to_string(),
            });
        }
        if let Some(runner) = &mut self.script {
            if let Some(path) = runner.after_frame()? {
                self.write_screenshot(&path)?;
            }
        }
        let repaint_now = output
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .is_some_and(|v| v.repaint_delay.is_zero());
        if let (true, Some(w)) = (repaint_now, &self.windowed) {
            w.window.request_redraw();
        }
        Ok(())
    }

    /// Writes the rendered image (without the panels) as a PNG.
    fn write_screenshot(&mut self, path: &Path) -> Result<(), ViewError> {
        if self.session.write_png(&self.gpu, path)? {
            self.summary.screenshots.push(path.to_owned());
        }
        Ok(())
    }
}

/// `path`, or the first of `stem-1.ext`, `stem-2.ext`, … that does not exist yet, so
/// screenshots taken one after another do not overwrite each other.
fn free_name(path: &Path) -> PathBuf {
    if !path.exists() {
        return path.to_owned();
    }
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    let ext = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    (1..)
        .map(|n| path.with_file_name(format!("{stem}-{n}{ext}")))
        .find(|p| !p.exists())
        .unwrap_or_else(|| path.to_owned())
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.windowed.is_none() {
            if let Err(e) = self.open(event_loop) {
                self.fail(event_loop, e);
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(w) = self.windowed.as_mut() else {
            return;
        };
        let response = w.input.on_window_event(&w.window, &event);
        if response.repaint {
            w.window.request_redraw();
        }
        match event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => event_loop.exit(),
            WindowEvent::Resized(size) => {
                w.size = size;
                w.presenter.invalidate();
                w.window.request_redraw();
            }
            WindowEvent::ScaleFactorChanged { .. } => {
                w.presenter.invalidate();
                w.window.request_redraw();
            }
            WindowEvent::RedrawRequested => match self.redraw(event_loop) {
                // The window went away before its close reached us: the person closed it.
                Err(ViewError::Gpu(tessera_gpu::GpuError::SurfaceLost { .. })) => event_loop.exit(),
                Err(e) => self.fail(event_loop, e),
                Ok(()) => {}
            },
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if self.script.is_some() || self.panels.continuous {
            if let Some(w) = &self.windowed {
                w.window.request_redraw();
            }
        }
    }
}
