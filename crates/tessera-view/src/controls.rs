//! The egui panels: the controls window (technique, path, isovalue, transfer function,
//! technique options, view), the frame overlay (GPU ms per stage, counts) and the mouse over
//! the image.

use crate::orbit;
use crate::session::Session;
use crate::tf_editor::{paint_histogram, TfEditor};
use egui::{PointerButton, Sense};
use tessera::path::PathChoice;
use tessera::renderer::{AmbientOcclusion, AmbiguityRule, Culling, Light, PmbBlockSize, Technique};
use tessera_data::scene::{Dataset, IntegrandChoice};
use tessera_data::tet::shell::{LayoutKind, DEFAULT_AO_RADIUS};
use tessera_data::IsoValue;

/// The integration choices the controls offer, by the name `--integrate` takes.
const INTEGRANDS: [&str; 5] = ["auto", "tet-absorption", "absorption", "emission", "mip"];

/// What the panels keep between frames and what they ask of the frame loop.
#[derive(Default)]
pub struct Panels {
    pub tf: TfEditor,
    /// The data's value histogram, computed once.
    pub histogram: Option<Vec<u64>>,
    /// Render every frame, not only after a change.
    pub continuous: bool,
    /// Set when the screenshot button or key was pressed; the frame loop takes it.
    pub screenshot: bool,
    /// The last screenshot written, or why it failed.
    pub status: Option<String>,
}

impl Panels {
    pub fn new(dataset: &Dataset, continuous: bool) -> Panels {
        Panels {
            histogram: crate::tf_editor::histogram_of(dataset),
            continuous,
            ..Panels::default()
        }
    }

    /// Lays out every panel for one frame, changing `session.state` as the user asks.
    pub fn show(&mut self, ctx: &egui::Context, session: &mut Session) {
        if ctx.input(|i| {
            i.key_pressed(egui::Key::F12) || i.key_pressed(egui::Key::P) && i.modifiers.ctrl
        }) {
            self.screenshot = true;
        }
        frame_overlay(ctx, session);
        egui::Window::new("Controls")
            .anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0])
            .default_width(300.0)
            .resizable(false)
            .show(ctx, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.controls(ui, session));
            });
        mouse(ctx, session);
    }

    fn controls(&mut self, ui: &mut egui::Ui, session: &mut Session) {
        technique_picker(ui, session);
        let technique = session.state.technique;
        let reads = |name: &str| technique.reads_options().contains(&name);
        if reads("path") {
            path_picker(ui, session);
        }
        if let Dataset::Volume(volume) = &session.dataset {
            let range = volume.value_range();
            ui.separator();
            let mut iso = session.state.look.iso.in_range(range);
            ui.horizontal(|ui| {
                let slider = egui::Slider::new(&mut iso, range.0..=range.1).text("isovalue");
                if ui.add(slider).changed() {
                    session.state.look.iso = IsoValue::Raw(iso);
                }
                ui.label(format!("{:.2} ms", session.times.total_ms()));
            });
            if let Some(counts) = &self.histogram {
                histogram_with_marker(
                    ui,
                    counts,
                    (iso - range.0) / (range.1 - range.0).max(f32::MIN_POSITIVE),
                );
            }
        }
        if matches!(technique, Technique::Interval | Technique::Shell) {
            ui.separator();
            ui.label("transfer function");
            self.tf.show(
                ui,
                &mut session.state.look.transfer,
                self.histogram.as_deref(),
            );
            ui.add(
                egui::Slider::new(&mut session.state.look.density, 0.1..=64.0)
                    .logarithmic(true)
                    .text("density"),
            );
        }
        if technique == Technique::Interval {
            integrand_picker(ui, session);
        }
        technique_options(ui, session);
        ui.separator();
        ui.horizontal(|ui| {
            if ui.button("reset view").clicked() {
                session.state.camera = session.home;
            }
            if ui.button("screenshot (F12)").clicked() {
                self.screenshot = true;
            }
            ui.checkbox(&mut self.continuous, "continuous");
        });
        stereo_control(ui, session);
        let c = &session.state.camera;
        ui.label(format!(
            "camera {:.1},{:.1},{:.2} (drag: orbit, right drag: pan, wheel: zoom, double click: reset)",
            c.azimuth_deg, c.elevation_deg, c.distance
        ));
        for line in self.status.iter().chain(session.problem.iter()) {
            ui.colored_label(egui::Color32::LIGHT_RED, line);
        }
    }
}

/// Eye separation of a new stereo pair (world units; the data's longest side is 1).
const DEFAULT_EYE_SEPARATION: f32 = 0.06;

/// A stereo pair side by side (each eye half the window), and its eye separation.
fn stereo_control(ui: &mut egui::Ui, session: &mut Session) {
    ui.horizontal(|ui| {
        let mut on = session.state.stereo.is_some();
        if ui.checkbox(&mut on, "stereo").changed() {
            session.state.stereo = on.then_some(DEFAULT_EYE_SEPARATION);
        }
        if let Some(separation) = &mut session.state.stereo {
            ui.add(egui::Slider::new(separation, 0.005..=0.3).text("eye separation"));
        }
    });
}

fn technique_picker(ui: &mut egui::Ui, session: &mut Session) {
    let current = session.state.technique;
    egui::ComboBox::from_label("technique")
        .selected_text(current.name())
        .show_ui(ui, |ui| {
            for t in session.techniques() {
                ui.selectable_value(&mut session.state.technique, t, t.name());
            }
        });
}

fn path_picker(ui: &mut egui::Ui, session: &mut Session) {
    let taken = session
        .renderer()
        .map(|r| format!(" (runs {})", r.path().name()))
        .unwrap_or_default();
    ui.horizontal(|ui| {
        ui.label("path");
        let choices = [
            (PathChoice::Auto, "auto"),
            (PathChoice::Graphics, "graphics"),
            (PathChoice::Compute, "compute"),
        ];
        for (choice, name) in choices {
            ui.radio_value(&mut session.state.options.path, choice, name);
        }
        ui.label(taken);
    });
}

fn integrand_picker(ui: &mut egui::Ui, session: &mut Session) {
    let look = &mut session.state.look;
    let name = INTEGRANDS
        .into_iter()
        .find(|n| IntegrandChoice::parse(n).ok() == Some(look.integrand))
        .unwrap_or("auto");
    egui::ComboBox::from_label("integrate")
        .selected_text(name)
        .show_ui(ui, |ui| {
            for n in INTEGRANDS {
                if let Ok(choice) = IntegrandChoice::parse(n) {
                    ui.selectable_value(&mut look.integrand, choice, n);
                }
            }
        });
}

/// The options of [`tessera::renderer::RendererOptions`] that the technique reads.
fn technique_options(ui: &mut egui::Ui, session: &mut Session) {
    let technique = session.state.technique;
    let reads = |name: &str| technique.reads_options().contains(&name);
    let up = session.state.camera.up;
    let options = &mut session.state.options;
    if reads("culling") {
        ui.horizontal(|ui| {
            ui.label("culling");
            for choice in [Culling::Auto, Culling::On, Culling::Off] {
                ui.radio_value(&mut options.culling, choice, choice.name());
            }
        });
    }
    if reads("supersample") {
        ui.add(egui::Slider::new(&mut options.supersample, 1..=4).text("supersample"));
    }
    if reads("msaa") {
        ui.horizontal(|ui| {
            ui.label("MSAA");
            for samples in [1, 2, 4, 8] {
                ui.radio_value(&mut options.msaa, samples, samples.to_string());
            }
        });
    }
    if reads("pre_split") {
        // 0 stands for the technique's own choice.
        let mut split = options.pre_split.unwrap_or(0);
        if ui
            .add(egui::Slider::new(&mut split, 0..=8).text("pre-split (0: auto)"))
            .changed()
        {
            options.pre_split = (split > 0).then_some(split);
        }
    }
    if reads("ambiguity") {
        ui.horizontal(|ui| {
            ui.label("ambiguous faces");
            ui.radio_value(
                &mut options.ambiguity,
                AmbiguityRule::AsymptoticDecider,
                "asymptotic decider",
            );
            ui.radio_value(&mut options.ambiguity, AmbiguityRule::Vtk, "VTK");
        });
    }
    if reads("pmb_block") {
        ui.horizontal(|ui| {
            ui.label("PMB block");
            for block in PmbBlockSize::ALL {
                ui.radio_value(&mut options.pmb_block, block, block.name());
            }
        });
    }
    if reads("layout") {
        ui.horizontal(|ui| {
            ui.label("layout");
            for kind in LayoutKind::ALL {
                ui.radio_value(&mut options.layout, kind, kind.name());
            }
        });
    }
    if reads("shadows") {
        let mut on = options.shadows.is_some();
        if ui.checkbox(&mut on, "shadows").changed() {
            options.shadows = on.then(|| Light::above(up.vector().as_dvec3()));
        }
    }
    if reads("ao") {
        let mut samples = options.ao.map_or(0, |ao| ao.samples);
        if ui
            .add(egui::Slider::new(&mut samples, 0..=64).text("AO rays (0: off)"))
            .changed()
        {
            let radius = options.ao.map_or(DEFAULT_AO_RADIUS, |ao| ao.radius);
            options.ao = (samples > 0)
                .then(|| AmbientOcclusion::new(samples, radius).ok())
                .flatten();
        }
    }
    if reads("gradient") {
        ui.checkbox(&mut options.gradient, "gradient shading");
    }
}

fn histogram_with_marker(ui: &mut egui::Ui, counts: &[u64], at: f32) {
    let (rect, _) = ui.allocate_exact_size(
        egui::vec2(ui.available_width().max(200.0), 40.0),
        Sense::hover(),
    );
    let painter = ui.painter();
    painter.rect_filled(rect, 2.0, egui::Color32::from_gray(30));
    paint_histogram(painter, rect, counts);
    let x = rect.left() + at.clamp(0.0, 1.0) * rect.width();
    painter.vline(
        x,
        rect.y_range(),
        egui::Stroke::new(1.5, egui::Color32::YELLOW),
    );
}

/// GPU milliseconds per stage and the frame's counts, over the image's top left.
fn frame_overlay(ctx: &egui::Context, session: &Session) {
    egui::Area::new(egui::Id::new("frame overlay"))
        .anchor(egui::Align2::LEFT_TOP, [8.0, 8.0])
        .interactable(false)
        .show(ctx, |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| {
                let path = session.renderer().map(|r| r.path().name()).unwrap_or("-");
                ui.strong(format!("{} ({path})", session.state.technique.name()));
                for (stage, ms) in &session.times.scopes {
                    ui.monospace(format!("{stage:<20} {ms:8.3} ms"));
                }
                ui.monospace(format!(
                    "{:<20} {:8.3} ms",
                    "GPU frame",
                    session.times.total_ms()
                ));
                let stats = &session.stats;
                let counts = [
                    ("triangles", stats.triangles),
                    ("patches", stats.patches),
                    ("tets clipped", stats.tets_clipped),
                ];
                for (name, value) in counts {
                    if let Some(v) = value {
                        ui.monospace(format!("{name:<20} {v:>11}"));
                    }
                }
                if let Some((kept, new)) = stats.blocks_drawn {
                    ui.monospace(format!("{:<20} {kept:>5} + {new}", "blocks drawn"));
                }
                for (name, v) in &stats.details {
                    ui.monospace(format!("{name:<20} {v:>11}"));
                }
            });
        });
}

/// Orbit, pan and zoom from the mouse over the image (anywhere the panels are not).
fn mouse(ctx: &egui::Context, session: &mut Session) {
    egui::CentralPanel::default()
        .frame(egui::Frame::NONE)
        .show(ctx, |ui| {
            let response = ui.interact(
                ui.max_rect(),
                egui::Id::new("image"),
                Sense::click_and_drag(),
            );
            let delta = response.drag_delta();
            let camera = &mut session.state.camera;
            let shift = ui.input(|i| i.modifiers.shift);
            if response.dragged_by(PointerButton::Primary) && !shift {
                orbit::orbit(camera, delta.x, delta.y);
            } else if response.dragged_by(PointerButton::Secondary)
                || response.dragged_by(PointerButton::Middle)
                || response.dragged_by(PointerButton::Primary)
            {
                orbit::pan(camera, delta.x, delta.y, ui.max_rect().height());
            }
            if response.hovered() {
                let scroll = ui.input(|i| i.smooth_scroll_delta.y);
                if scroll != 0.0 {
                    orbit::zoom(camera, scroll);
                }
            }
            if response.double_clicked() {
                *camera = session.home;
            }
        });
}
