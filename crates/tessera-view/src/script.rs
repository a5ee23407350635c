//! Scripted runs: a text file of steps, one a line, that the viewer carries out between
//! frames as if someone used the controls, then exits. `#` starts a comment.
//!
//! ```text
//! size 128x96                # resize the window (and so the image) to W x H pixels
//! camera 30,20,1.8           # azimuth, elevation (degrees), distance
//! pan 0.1,0                  # shift the view right and up (world units)
//! iso 0.42                   # isovalue in the data's units
//! iso-fraction 0.3           # isovalue as a fraction of the value range
//! tf hot                     # transfer function: preset or 'at r g b a' file (as --tf)
//! tf-save out/tf.txt         # write the current transfer function
//! density 6                  # absorption / emission density of tet integration
//! technique direct           # switch technique (keeps the data of earlier ones)
//! path compute               # graphics, compute or auto
//! culling off                # on, off or auto
//! supersample 2              # samples per pixel along each axis (parametric objects)
//! stereo 0.06                # a stereo pair with this eye separation, side by side; or off
//! frames 10                  # render this many frames before the next step
//! screenshot out/a.png       # write the rendered image (without the controls) as PNG
//! ```

use crate::error::ViewError;
use std::path::{Path, PathBuf};
use tessera::path::PathChoice;
use tessera::renderer::{Culling, Technique};
use tessera_data::scene::parse::parse_size;
use tessera_data::transfer::TransferFunction;
use tessera_data::{IsoValue, OrbitCamera};

/// One step of a script.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    Resize(u32, u32),
    Camera {
        azimuth: f32,
        elevation: f32,
        distance: f32,
    },
    Pan(f32, f32),
    Iso(IsoValue),
    Transfer(TransferFunction),
    SaveTransfer(PathBuf),
    Density(f32),
    Technique(Technique),
    Path(PathChoice),
    Culling(Culling),
    Supersample(u32),
    Stereo(Option<f32>),
    Frames(u32),
    Screenshot(PathBuf),
}

/// The steps of a script file, in order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Script {
    pub steps: Vec<Step>,
}

impl Script {
    pub fn load(path: &Path) -> Result<Script, ViewError> {
        let text = std::fs::read_to_string(path).map_err(|e| ViewError::File {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        Script::parse(&text).map_err(|(line, message)| ViewError::Script {
            path: path.display().to_string(),
            line,
            message,
        })
    }

    /// Parses script text; the error gives the line number (from 1) and what is wrong.
    pub fn parse(text: &str) -> Result<Script, (usize, String)> {
        let mut steps = Vec::new();
        for (index, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let (word, rest) = line.split_once(char::is_whitespace).unwrap_or((line, ""));
            steps.push(parse_step(word, rest.trim()).map_err(|e| (index + 1, e))?);
        }
        Ok(Script { steps })
    }
}

fn number<T: std::str::FromStr>(text: &str, what: &str) -> Result<T, String> {
    text.trim()
        .parse()
        .map_err(|_| format!("{what}: '{text}' is not a number"))
}

fn finite(text: &str, what: &str) -> Result<f32, String> {
    let v: f32 = number(text, what)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{what}: '{text}' is not a finite number"))
    }
}

fn pair(text: &str, what: &str) -> Result<(f32, f32), String> {
    match text.split(',').collect::<Vec<_>>()[..] {
        [a, b] => Ok((finite(a, what)?, finite(b, what)?)),
        _ => Err(format!("{what}: expected X,Y, found '{text}'")),
    }
}

fn parse_step(word: &str, rest: &str) -> Result<Step, String> {
    let needs_path = |step: fn(PathBuf) -> Step| {
        if rest.is_empty() {
            Err(format!("{word}: give a file path"))
        } else {
            Ok(step(PathBuf::from(rest)))
        }
    };
    match word {
        "size" => parse_size(rest).map(|(w, h)| Step::Resize(w, h)),
        "camera" => OrbitCamera::parse(rest).map(|c| Step::Camera {
            azimuth: c.azimuth_deg,
            elevation: c.elevation_deg,
            distance: c.distance,
        }),
        "pan" => pair(rest, "pan").map(|(x, y)| Step::Pan(x, y)),
        "iso" => finite(rest, "iso").map(|v| Step::Iso(IsoValue::Raw(v))),
        "iso-fraction" => finite(rest, "iso-fraction").map(|v| Step::Iso(IsoValue::Normalized(v))),
        "tf" => TransferFunction::load(rest)
            .map(Step::Transfer)
            .map_err(|e| e.to_string()),
        "tf-save" => needs_path(Step::SaveTransfer),
        "density" => match finite(rest, "density")? {
            d if d > 0.0 => Ok(Step::Density(d)),
            d => Err(format!("density {d} must be positive")),
        },
        "technique" => Technique::parse(rest)
            .map(Step::Technique)
            .map_err(|e| e.to_string()),
        "path" => PathChoice::parse(rest)
            .map(Step::Path)
            .map_err(|e| e.to_string()),
        "culling" => Culling::parse(rest)
            .map(Step::Culling)
            .map_err(|e| e.to_string()),
        "stereo" if rest == "off" => Ok(Step::Stereo(None)),
        "stereo" => match finite(rest, "stereo")? {
            separation if separation > 0.0 => Ok(Step::Stereo(Some(separation))),
            _ => Err(format!(
                "stereo: give a positive eye separation or off, not '{rest}'"
            )),
        },
        "supersample" => match number::<u32>(rest, "supersample")? {
            k @ 1..=4 => Ok(Step::Supersample(k)),
            k => Err(format!("supersample {k}: choose 1 to 4")),
        },
        "frames" => match number::<u32>(rest, "frames")? {
            n @ 1..=100_000 => Ok(Step::Frames(n)),
            n => Err(format!("frames {n}: choose 1 to 100000")),
        },
        "screenshot" => needs_path(Step::Screenshot),
        _ => Err(format!(
            "unknown step '{word}' (size, camera, pan, iso, iso-fraction, tf, tf-save, density, \
             technique, path, culling, supersample, frames, screenshot)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_parse_and_errors_name_the_line() {
        let script = Script::parse(
            "# a comment\nsize 64x48\ncamera 10,-20,2\niso-fraction 0.3 # trailing\n\
             tf hot\nframes 3\nscreenshot out/a b.png\n",
        )
        .unwrap();
        assert_eq!(script.steps.len(), 6);
        assert_eq!(script.steps[0], Step::Resize(64, 48));
        assert_eq!(
            script.steps[1],
            Step::Camera {
                azimuth: 10.0,
                elevation: -20.0,
                distance: 2.0
            }
        );
        assert_eq!(script.steps[5], Step::Screenshot("out/a b.png".into()));
        let (line, message) = Script::parse("frames 2\nspin 3\n").unwrap_err();
        assert_eq!(line, 2);
        assert!(message.contains("unknown step 'spin'"), "{message}");
        assert_eq!(Script::parse("iso nan").unwrap_err().0, 1);
        assert!(Script::parse("camera 1,2").is_err());
        assert!(Script::parse("screenshot").is_err());
        assert!(Script::parse("frames 0").is_err());
        let culling = Script::parse("culling auto\nculling off\n").unwrap();
        assert_eq!(
            culling.steps,
            [Step::Culling(Culling::Auto), Step::Culling(Culling::Off)]
        );
        let (line, message) = Script::parse("frames 1\nculling sometimes\n").unwrap_err();
        assert_eq!(line, 2);
        assert!(message.contains("culling 'sometimes'"), "{message}");
    }
}

/// How long a resize step waits for the window system to give the size asked for.
const RESIZE_WAIT: std::time::Duration = std::time::Duration::from_secs(10);

/// What the frame loop does after the steps due before a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Before {
    Render,
    /// Skip this frame (a resize is under way).
    Wait,
    /// The script is over: exit.
    Done,
}

/// Carries out a script's steps between frames.
pub struct Runner {
    steps: std::collections::VecDeque<Step>,
    /// Frames rendered of the current `frames` step.
    frames_done: u32,
    resize_started: Option<std::time::Instant>,
}

impl Runner {
    pub fn new(script: Script) -> Runner {
        Runner {
            steps: script.steps.into(),
            frames_done: 0,
            resize_started: None,
        }
    }

    /// Applies the steps due before the next frame; `size` is the image's now, and
    /// `request_size` asks the window (or the offscreen frame) for another.
    pub fn before_frame(
        &mut self,
        session: &mut crate::session::Session,
        request_size: &mut dyn FnMut(u32, u32),
        size: (u32, u32),
    ) -> Result<Before, ViewError> {
        let state = &mut session.state;
        loop {
            let Some(step) = self.steps.front() else {
                return Ok(Before::Done);
            };
            match step {
                Step::Screenshot(_) | Step::Frames(_) => return Ok(Before::Render),
                &Step::Resize(w, h) => {
                    if size == (w, h) {
                        self.resize_started = None;
                    } else {
                        let started = *self.resize_started.get_or_insert_with(|| {
                            request_size(w, h);
                            std::time::Instant::now()
                        });
                        if started.elapsed() > RESIZE_WAIT {
                            return Err(ViewError::Window(format!(
                                "the window system kept the window at {}x{} when {w}x{h} was asked for",
                                size.0, size.1
                            )));
                        }
                        return Ok(Before::Wait);
                    }
                }
                &Step::Camera {
                    azimuth,
                    elevation,
                    distance,
                } => {
                    state.camera.azimuth_deg = azimuth;
                    state.camera.elevation_deg = elevation;
                    state.camera.distance = distance;
                }
                &Step::Pan(x, y) => {
                    state.camera.eye_shift = x;
                    state.camera.eye_rise = y;
                }
                &Step::Iso(iso) => state.look.iso = iso,
                Step::Transfer(tf) => state.look.transfer = tf.clone(),
                Step::SaveTransfer(path) => std::fs::write(path, state.look.transfer.to_text())
                    .map_err(|e| ViewError::File {
                        path: path.clone(),
                        message: e.to_string(),
                    })?,
                &Step::Density(d) => state.look.density = d,
                &Step::Technique(t) => {
                    if t.draws() != session.dataset.kind() {
                        return Err(ViewError::Render(tessera::Error::Invalid(format!(
                            "script: technique '{}' draws {}, not {}",
                            t.name(),
                            t.draws().describe(),
                            session.dataset.kind().describe()
                        ))));
                    }
                    state.technique = t;
                }
                &Step::Path(p) => state.options.path = p,
                &Step::Culling(choice) => state.options.culling = choice,
                &Step::Supersample(k) => state.options.supersample = k,
                &Step::Stereo(separation) => state.stereo = separation,
            }
            self.steps.pop_front();
        }
    }

    /// After a frame was rendered and shown: the screenshot to take now, if one is due.
    pub fn after_frame(&mut self) -> Result<Option<PathBuf>, ViewError> {
        match self.steps.front() {
            Some(Step::Screenshot(path)) => {
                let path = path.clone();
                self.steps.pop_front();
                Ok(Some(path))
            }
            Some(&Step::Frames(n)) => {
                self.frames_done += 1;
                if self.frames_done >= n {
                    self.frames_done = 0;
                    self.steps.pop_front();
                }
                Ok(None)
            }
            _ => Ok(None),
        }
    }
}
