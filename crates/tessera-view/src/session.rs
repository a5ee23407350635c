//! What is viewed and how: the data set, its look, the camera, the technique and its
//! options, and the renderers made for them. A frame is rendered only when one of these
//! changed (or when asked to render continuously).

use crate::error::ViewError;
use tessera::renderer::{
    self, Frame, FrameStats, FrameTimes, Renderer, RendererOptions, Technique,
};
use tessera::target::Target;
use tessera_data::scene::{Appearance, Dataset};
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

/// Renderers kept for switching back without uploading the data again.
const KEPT_RENDERERS: usize = 3;

/// The data and the first state of the view.
pub struct Scene {
    /// What the title bar shows (the DATA argument).
    pub name: String,
    pub dataset: Dataset,
    pub technique: Technique,
    pub options: RendererOptions,
    pub look: Appearance,
    pub camera: OrbitCamera,
}

/// What a person (or a script) changes between frames.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewState {
    pub technique: Technique,
    pub options: RendererOptions,
    pub look: Appearance,
    pub camera: OrbitCamera,
    /// A stereo pair with this eye separation (world units), the eyes side by side, each half
    /// the image's width (as `tessera render --stereo` at half the width).
    pub stereo: Option<f32>,
}

/// A renderer with the state it was made for and the look it last had.
struct Kept {
    technique: Technique,
    options: RendererOptions,
    look: Appearance,
    renderer: Box<dyn Renderer>,
}

/// The view's state, its renderers and the last frame.
pub struct Session {
    pub name: String,
    pub dataset: Dataset,
    pub state: ViewState,
    /// The view the user returns to with "reset view".
    pub home: OrbitCamera,
    /// Most recently used first.
    kept: Vec<Kept>,
    /// The image shown: the frame, or the stereo pair side by side.
    frame: Option<Frame>,
    /// The eyes' frames of a stereo pair.
    eyes: Option<(Frame, Frame)>,
    /// What the last frame was rendered with; `None` before the first.
    rendered: Option<ViewState>,
    pub times: FrameTimes,
    pub stats: FrameStats,
    /// The last failure to make or run a renderer, shown in the controls.
    pub problem: Option<String>,
}

impl Session {
    /// The session of `scene` with its first renderer made (data uploaded).
    pub fn new(gpu: &Gpu, scene: Scene) -> Result<Session, ViewError> {
        let state = ViewState {
            technique: scene.technique,
            options: scene.options,
            look: scene.look,
            camera: scene.camera,
            stereo: None,
        };
        let renderer = renderer::create_for(
            gpu,
            state.technique,
            &state.options,
            &state.look,
            &scene.dataset,
        )?;
        Ok(Session {
            name: scene.name,
            kept: vec![Kept {
                technique: state.technique,
                options: state.options,
                look: state.look.clone(),
                renderer,
            }],
            dataset: scene.dataset,
            home: state.camera,
            state,
            frame: None,
            eyes: None,
            rendered: None,
            times: FrameTimes::default(),
            stats: FrameStats::default(),
            problem: None,
        })
    }

    /// The techniques that draw this data set.
    pub fn techniques(&self) -> Vec<Technique> {
        let kind = self.dataset.kind();
        Technique::ALL
            .into_iter()
            .filter(|t| t.draws() == kind)
            .collect()
    }

    /// The current renderer, when one exists for the current technique and options.
    pub fn renderer(&self) -> Option<&dyn Renderer> {
        self.kept
            .first()
            .filter(|k| k.technique == self.state.technique && k.options == self.state.options)
            .map(|k| k.renderer.as_ref())
    }

    /// Whether the image no longer shows the state (or a size of `size`).
    pub fn stale(&self, size: (u32, u32)) -> bool {
        let shown = self.image_size(size);
        self.rendered.as_ref() != Some(&self.state)
            || self
                .frame
                .as_ref()
                .is_none_or(|f| (f.target.width, f.target.height) != shown)
    }

    /// Each eye's size in a window of `size`.
    fn eye_size(size: (u32, u32)) -> (u32, u32) {
        ((size.0 / 2).max(1), size.1)
    }

    /// The size of the image shown in a window of `size`: a stereo pair is two whole eyes.
    fn image_size(&self, size: (u32, u32)) -> (u32, u32) {
        match self.state.stereo {
            Some(_) => {
                let eye = Self::eye_size(size);
                (2 * eye.0, eye.1)
            }
            None => size,
        }
    }

    /// The last rendered image, if any.
    pub fn target(&self) -> Option<&Target> {
        self.frame.as_ref().map(|f| &f.target)
    }

    /// Renders the current state at `size` pixels. A technique or option that cannot be
    /// made falls back to the last state that rendered, with the reason kept in `problem`.
    pub fn render(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<(), ViewError> {
        if let Err(e) = self.select(gpu) {
            self.problem = Some(format!("{}: {e}", self.state.technique.name()));
            match &self.rendered {
                Some(last) => {
                    let look = self.state.look.clone();
                    let camera = self.state.camera;
                    self.state = ViewState {
                        look,
                        camera,
                        ..last.clone()
                    };
                    self.select(gpu)?;
                }
                None => return Err(e),
            }
        }
        let shown = self.image_size(size);
        if self
            .frame
            .as_ref()
            .is_none_or(|f| (f.target.width, f.target.height) != shown)
        {
            // The old target goes first, so the new one can take its memory.
            self.frame = None;
            self.frame = Some(Frame::new(gpu, shown)?);
        }
        let eye = Self::eye_size(size);
        match self.state.stereo {
            Some(_) if !matches!(&self.eyes, Some((l, _)) if (l.target.width, l.target.height) == eye) =>
            {
                self.eyes = None;
                self.eyes = Some((Frame::new(gpu, eye)?, Frame::new(gpu, eye)?));
            }
            None => self.eyes = None,
            Some(_) => {}
        }
        let (Some(kept), Some(frame)) = (self.kept.first_mut(), self.frame.as_mut()) else {
            return Ok(());
        };
        if kept.look != self.state.look {
            kept.renderer.set_appearance(gpu, &self.state.look)?;
            kept.look = self.state.look.clone();
        }
        self.times = match (self.state.stereo, self.eyes.as_mut()) {
            (Some(separation), Some((left, right))) => {
                let view = kept.renderer.view(&self.state.camera, eye)?;
                let eyes = view.stereo_pair(separation);
                let times =
                    renderer::render_stereo(gpu, kept.renderer.as_mut(), &eyes, left, right)?;
                let mut joined = Ok(());
                gpu.submit("stereo pair side by side", |rec| {
                    joined = frame
                        .target
                        .record_side_by_side(rec, &left.target, &right.target);
                })?;
                joined?;
                times
            }
            _ => {
                let view = kept.renderer.view(&self.state.camera, size)?;
                frame.render(gpu, kept.renderer.as_mut(), &view)?
            }
        };
        self.stats = kept.renderer.stats();
        self.rendered = Some(self.state.clone());
        Ok(())
    }

    /// Puts the renderer for the current technique and options first, making it (and
    /// uploading the data to it) when none was kept.
    fn select(&mut self, gpu: &Gpu) -> Result<(), ViewError> {
        let (technique, options) = (self.state.technique, self.state.options);
        if let Some(i) = self
            .kept
            .iter()
            .position(|k| k.technique == technique && k.options == options)
        {
            let kept = self.kept.remove(i);
            self.kept.insert(0, kept);
            return Ok(());
        }
        // Make room first: the GPU memory of the renderer dropped can serve the new one.
        self.kept.truncate(KEPT_RENDERERS - 1);
        let renderer =
            renderer::create_for(gpu, technique, &options, &self.state.look, &self.dataset)?;
        self.kept.insert(
            0,
            Kept {
                technique,
                options,
                look: self.state.look.clone(),
                renderer,
            },
        );
        self.problem = None;
        Ok(())
    }

    /// The last image read back, for screenshots.
    pub fn read_image(&self, gpu: &Gpu) -> Result<Option<tessera_data::RgbaImage>, ViewError> {
        Ok(match &self.frame {
            Some(frame) => Some(frame.target.read(gpu)?),
            None => None,
        })
    }

    /// Writes the last image as a PNG at `path` (its folder made); `false` before the first
    /// frame, when there is nothing to write.
    pub fn write_png(&self, gpu: &Gpu, path: &std::path::Path) -> Result<bool, ViewError> {
        let Some(image) = self.read_image(gpu)? else {
            return Ok(false);
        };
        let file_error = |e: &dyn std::fmt::Display| ViewError::File {
            path: path.to_owned(),
            message: e.to_string(),
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| file_error(&e))?;
        }
        let file = std::fs::File::create(path).map_err(|e| file_error(&e))?;
        let mut out = std::io::BufWriter::new(file);
        image.write_png(&mut out).map_err(|e| file_error(&e))?;
        std::io::Write::flush(&mut out).map_err(|e| file_error(&e))?;
        Ok(true)
    }
}
