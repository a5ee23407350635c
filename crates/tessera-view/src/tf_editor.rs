//! The transfer-function editor: colour and opacity control points over the data's value
//! histogram, presets, and loading and saving in the `--tf` file format.
//!
//! Drag a point to move it (along the value axis between its neighbours, and in opacity),
//! click empty space to add one, right-click a point to remove it; the selected point's
//! colour is edited below the plot.

use egui::{Color32, Pos2, Rect, Sense, Stroke, Vec2};
use tessera_data::scene::Dataset;
use tessera_data::transfer::{Knot, TransferFunction, PRESETS};

/// Histogram bins shown behind the editor.
const BINS: usize = 128;
/// Pixels within which a click picks a control point.
const PICK_RADIUS: f32 = 8.0;

/// Counts of the data's values in [`BINS`] bins over their range (a volume's samples, a tet
/// mesh's vertex scalars); `None` for data without scalars.
pub fn histogram_of(dataset: &Dataset) -> Option<Vec<u64>> {
    match dataset {
        Dataset::Volume(volume) => Some(tessera_data::histogram::histogram(volume, BINS)),
        Dataset::Tets(tets) => {
            let values = tets.mesh.scalars.as_ref()?;
            let (lo, hi) = values
                .iter()
                .filter(|v| v.is_finite())
                .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
            let mut counts = vec![0u64; BINS];
            let width = hi - lo;
            for &v in values.iter().filter(|v| v.is_finite()) {
                let bin = if width > 0.0 {
                    (((v - lo) / width) * BINS as f32) as usize
                } else {
                    0
                };
                counts[bin.min(BINS - 1)] += 1;
            }
            Some(counts)
        }
        Dataset::Param(_) => None,
    }
}

/// Draws `counts` as grey bars (log scale, so sparse values stay visible) filling `rect`.
pub fn paint_histogram(painter: &egui::Painter, rect: Rect, counts: &[u64]) {
    let top = counts.iter().copied().max().unwrap_or(0);
    if top == 0 {
        return;
    }
    let scale = 1.0 / ((top as f32).ln_1p());
    let width = rect.width() / counts.len() as f32;
    for (i, &c) in counts.iter().enumerate() {
        let h = (c as f32).ln_1p() * scale * rect.height();
        let x = rect.left() + i as f32 * width;
        let bar = Rect::from_min_max(
            Pos2::new(x, rect.bottom() - h),
            Pos2::new(x + width, rect.bottom()),
        );
        painter.rect_filled(bar, 0.0, Color32::from_gray(70));
    }
}

/// The editor's own state between frames.
#[derive(Default)]
pub struct TfEditor {
    selected: Option<usize>,
    dragging: Option<usize>,
    /// The file name typed for loading and saving.
    pub file: String,
    /// The outcome of the last load or save.
    pub message: Option<String>,
}

fn colour_of(rgba: [f32; 4]) -> Color32 {
    let [r, g, b, _] = rgba.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
    Color32::from_rgb(r, g, b)
}

impl TfEditor {
    /// Shows the editor for `tf` over `histogram`; returns whether `tf` changed.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        tf: &mut TransferFunction,
        histogram: Option<&[u64]>,
    ) -> bool {
        let mut changed = self.presets(ui, tf);
        let size = Vec2::new(ui.available_width().max(200.0), 110.0);
        let (response, painter) = ui.allocate_painter(size, Sense::click_and_drag());
        let rect = response.rect.shrink(4.0);
        painter.rect_filled(response.rect, 2.0, Color32::from_gray(30));
        if let Some(counts) = histogram {
            paint_histogram(&painter, rect, counts);
        }
        let to_screen = |k: &Knot| {
            Pos2::new(
                rect.left() + k.at * rect.width(),
                rect.bottom() - k.rgba[3] * rect.height(),
            )
        };
        let from_screen = |p: Pos2| {
            (
                ((p.x - rect.left()) / rect.width()).clamp(0.0, 1.0),
                ((rect.bottom() - p.y) / rect.height()).clamp(0.0, 1.0),
            )
        };
        let points: Vec<Pos2> = tf.knots.iter().map(to_screen).collect();
        painter.line(points.clone(), Stroke::new(1.5, Color32::WHITE));
        for (i, (p, k)) in points.iter().zip(&tf.knots).enumerate() {
            let ring = if Some(i) == self.selected {
                Stroke::new(2.0, Color32::YELLOW)
            } else {
                Stroke::new(1.0, Color32::BLACK)
            };
            painter.circle(*p, 5.0, colour_of(k.rgba), ring);
        }
        let nearest = |pos: Pos2| {
            points
                .iter()
                .enumerate()
                .map(|(i, p)| (i, p.distance(pos)))
                .filter(|&(_, d)| d <= PICK_RADIUS)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, _)| i)
        };
        if let Some(pos) = response.interact_pointer_pos() {
            if response.drag_started() {
                self.dragging = nearest(pos);
                self.selected = self.dragging.or(self.selected);
            }
            let dragged = self.dragging.filter(|&i| i < tf.knots.len());
            if let (Some(i), true) = (dragged, response.dragged()) {
                let (at, alpha) = from_screen(pos);
                // A point stays between its neighbours, so the knots stay in order.
                let lo = if i > 0 { tf.knots[i - 1].at } else { 0.0 };
                let hi = tf.knots.get(i + 1).map_or(1.0, |k| k.at);
                tf.knots[i].at = at.clamp(lo, hi);
                tf.knots[i].rgba[3] = alpha;
                changed = true;
            }
            if response.clicked() {
                match nearest(pos) {
                    Some(i) => self.selected = Some(i),
                    None => {
                        let (at, alpha) = from_screen(pos);
                        let [r, g, b, _] = tf.sample(f64::from(at)).map(|c| c as f32);
                        let i = tf.knots.partition_point(|k| k.at <= at);
                        tf.knots.insert(
                            i,
                            Knot {
                                at,
                                rgba: [r, g, b, alpha],
                            },
                        );
                        self.selected = Some(i);
                        changed = true;
                    }
                }
            }
            if response.secondary_clicked() {
                if let Some(i) = nearest(pos).filter(|_| tf.knots.len() > 1) {
                    tf.knots.remove(i);
                    self.selected = None;
                    changed = true;
                }
            }
        }
        if response.drag_stopped() {
            self.dragging = None;
        }
        self.colour_bar(ui, tf);
        changed |= self.selected_point(ui, tf);
        self.files(ui, tf) || changed
    }

    fn presets(&mut self, ui: &mut egui::Ui, tf: &mut TransferFunction) -> bool {
        let mut changed = false;
        ui.horizontal(|ui| {
            ui.label("presets");
            for name in PRESETS {
                if ui.small_button(*name).clicked() {
                    if let Ok(preset) = TransferFunction::preset(name) {
                        *tf = preset;
                        self.selected = None;
                        changed = true;
                    }
                }
            }
        });
        changed
    }

    fn colour_bar(&self, ui: &mut egui::Ui, tf: &TransferFunction) {
        let (rect, _) =
            ui.allocate_exact_size(Vec2::new(ui.available_width(), 10.0), Sense::hover());
        let steps = 64;
        let width = rect.width() / steps as f32;
        for i in 0..steps {
            let at = (i as f64 + 0.5) / steps as f64;
            let rgba = tf.sample(at).map(|c| c as f32);
            let x = rect.left() + i as f32 * width;
            let cell = Rect::from_min_max(
                Pos2::new(x, rect.top()),
                Pos2::new(x + width + 0.5, rect.bottom()),
            );
            ui.painter().rect_filled(cell, 0.0, colour_of(rgba));
        }
    }

    fn selected_point(&mut self, ui: &mut egui::Ui, tf: &mut TransferFunction) -> bool {
        let Some(knot) = self.selected.and_then(|i| tf.knots.get_mut(i)) else {
            ui.label("click a point to edit its colour");
            return false;
        };
        let mut changed = false;
        ui.horizontal(|ui| {
            let mut rgb = [knot.rgba[0], knot.rgba[1], knot.rgba[2]];
            if egui::color_picker::color_edit_button_rgb(ui, &mut rgb).changed() {
                knot.rgba[..3].copy_from_slice(&rgb);
                changed = true;
            }
            changed |= ui
                .add(
                    egui::DragValue::new(&mut knot.rgba[3])
                        .range(0.0..=1.0)
                        .speed(0.01)
                        .prefix("opacity "),
                )
                .changed();
            ui.label(format!("at {:.3}", knot.at));
        });
        changed
    }

    fn files(&mut self, ui: &mut egui::Ui, tf: &mut TransferFunction) -> bool {
        let mut changed = false;
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut self.file)
                    .hint_text("tf.txt")
                    .desired_width(120.0),
            );
            if ui.button("load").clicked() {
                match TransferFunction::load(self.file.trim()) {
                    Ok(loaded) => {
                        *tf = loaded;
                        self.selected = None;
                        self.message = Some(format!("loaded {}", self.file.trim()));
                        changed = true;
                    }
                    Err(e) => self.message = Some(e.to_string()),
                }
            }
            if ui.button("save").clicked() {
                self.message = Some(match save(self.file.trim(), tf) {
                    Ok(()) => format!("saved {}", self.file.trim()),
                    Err(e) => e,
                });
            }
        });
        if let Some(message) = &self.message {
            ui.label(message);
        }
        changed
    }
}

/// Writes `tf` to `path` in the format `--tf` reads.
pub fn save(path: &str, tf: &TransferFunction) -> Result<(), String> {
    if path.is_empty() {
        return Err("type a file name to save to".into());
    }
    std::fs::write(path, tf.to_text()).map_err(|e| format!("{path}: {e}"))
}
