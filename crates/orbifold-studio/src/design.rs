//! The design panel (seed §5.1): the number of walls and each corner's order, as nodes round a
//! circle, with the live signature, χ as an exact fraction, the geometry and the kind.
//!
//! The seed's rules for the awkward cases: one wall has no corner (order 1: the hemisphere `*`),
//! and the two corners of two walls always have the same order (`*kk`; `*k₁k₂` with k₁ ≠ k₂ is a
//! bad orbifold). A new wall adds a corner of order 2 in front, so that `*` → `*22` → `*33` →
//! `*233` → `*333` → `*2333` (the seed's sequence) is a few clicks.

use egui::{Color32, Pos2, Stroke, Ui, Vec2};
use orbifold::{Kind, OrbifoldSymbol, Signature};

/// A corner's order: a real number > 1 (integers for orbifolds), or ∞ (an ideal corner).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Corner {
    /// Order k: the corner angle is π/k.
    Order(f64),
    /// An ideal corner at infinity.
    Ideal,
}

/// The corners of a signature in the notation (`None` if it does not parse).
pub fn corners(signature: &str) -> Option<Vec<Corner>> {
    let signature: Signature = signature.parse().ok()?;
    Some(
        signature
            .corners()
            .iter()
            .map(|order| {
                if order.is_infinite() {
                    Corner::Ideal
                } else {
                    Corner::Order(order.to_f64())
                }
            })
            .collect(),
    )
}

/// The signature of these corners in the notation: digits, `(12)`, `(1.5)`, `∞`.
///
/// ```
/// use orbifold_studio::design::{Corner, signature};
/// assert_eq!(signature(&[Corner::Order(2.0), Corner::Order(12.0), Corner::Ideal]), "*2(12)∞");
/// assert_eq!(signature(&[Corner::Order(1.5), Corner::Order(3.0)]), "*(1.5)3");
/// assert_eq!(signature(&[]), "*");
/// ```
pub fn signature(corners: &[Corner]) -> String {
    let mut text = String::from("*");
    for corner in corners {
        match *corner {
            Corner::Ideal => text.push('∞'),
            Corner::Order(k) if k.fract() == 0.0 && (2.0..=9.0).contains(&k) => {
                text.push_str(&format!("{k}"));
            }
            Corner::Order(k) if k.fract() == 0.0 => text.push_str(&format!("({k})")),
            Corner::Order(k) => text.push_str(&format!("({})", round(k))),
        }
    }
    text
}

fn round(k: f64) -> f64 {
    (k * 1000.0).round() / 1000.0
}

/// The walls of a room with these corners: one for `*` (no corner), else one a corner.
pub fn walls(corners: &[Corner]) -> usize {
    corners.len().max(1)
}

/// The corners after changing the number of walls to `walls` (at least 1), by the seed's
/// rules: new corners of order 2 in front, corners removed from the front, two walls with equal
/// orders.
///
/// ```
/// use orbifold_studio::design::{Corner, with_walls};
/// let two = with_walls(&[], 2);
/// assert_eq!(two, vec![Corner::Order(2.0); 2]);
/// let three = with_walls(&[Corner::Order(3.0), Corner::Order(3.0)], 3);
/// assert_eq!(three, vec![Corner::Order(2.0), Corner::Order(3.0), Corner::Order(3.0)]);
/// assert!(with_walls(&three, 1).is_empty());
/// ```
pub fn with_walls(corners: &[Corner], walls: usize) -> Vec<Corner> {
    let walls = walls.max(1);
    if walls == 1 {
        return Vec::new();
    }
    let mut next: Vec<Corner> = corners.to_vec();
    while next.len() < walls {
        next.insert(0, Corner::Order(2.0));
    }
    while next.len() > walls {
        next.remove(0);
    }
    if walls == 2 {
        next[1] = next[0];
    }
    next
}

/// What the panel shows about a signature.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// The canonical signature.
    pub canonical: String,
    /// χ, exactly (`None` when an order is not rational).
    pub chi: String,
    /// spherical, euclidean, hyperbolic.
    pub geometry: String,
    /// orbifold, bad, non-orbifold, with the reason for a bad one.
    pub kind: String,
}

/// The summary of a symbol in the notation, or the parse error: a kaleidoscopic signature, or
/// any orbifold symbol in Conway's notation (`632`, `22×`), whose room has portals.
///
/// ```
/// use orbifold_studio::design::summary;
/// let s = summary("22×").unwrap();
/// assert_eq!(s.geometry, "euclidean");
/// assert!(s.kind.contains("portal"), "{}", s.kind);
/// ```
pub fn summary(text: &str) -> Result<Summary, String> {
    let symbol: OrbifoldSymbol = text
        .parse()
        .map_err(|e: orbifold::ParseError| e.to_string())?;
    let Some(signature) = symbol.as_kaleidoscopic() else {
        let kind = match symbol.reason() {
            Some(reason) => format!("bad orbifold: {reason}"),
            None => match orbifold::Layout::of_symbol(&symbol, &Default::default()) {
                Ok(layout) => {
                    let portals = layout
                        .edges
                        .iter()
                        .filter(|e| e.partner().is_some())
                        .count();
                    let mirrors = layout.edges.len() - portals;
                    format!("orbifold: a room of {portals} portals and {mirrors} mirrors")
                }
                Err(e) => format!("orbifold, not built: {e}"),
            },
        };
        return Ok(Summary {
            canonical: symbol.canonical().to_string(),
            chi: symbol.euler_characteristic().to_string(),
            geometry: symbol.geometry().name().to_string(),
            kind,
        });
    };
    let kind = match signature.kind() {
        Kind::Orbifold => "orbifold".to_string(),
        Kind::Bad => format!(
            "bad orbifold: {}",
            signature.reason().unwrap_or_else(|| "no polygon".into())
        ),
        Kind::NonOrbifold => "non-orbifold room (mirror images overlap)".to_string(),
    };
    Ok(Summary {
        canonical: signature.canonical().to_string(),
        chi: signature.euler_characteristic().to_string(),
        geometry: signature.geometry().name().to_string(),
        kind,
    })
}

/// A signature as the panel shows it: `∞` written `(inf)` (which the notation also reads), as
/// egui's built-in fonts have no ∞.
pub fn shown(signature: &str) -> String {
    signature.replace('∞', "(inf)")
}

/// A label with a drag value tied to it (so that screen readers and UI tests find it by name).
pub fn labelled_value<N: egui::emath::Numeric>(
    ui: &mut Ui,
    name: &str,
    value: &mut N,
    range: std::ops::RangeInclusive<N>,
    speed: f64,
) -> egui::Response {
    let label = ui.label(name);
    ui.add(egui::DragValue::new(value).range(range).speed(speed))
        .labelled_by(label.id)
}

/// The design panel. Returns the new signature when the user changed it.
pub fn show(ui: &mut Ui, current: &str) -> Option<String> {
    let mut changed = None;
    let corners_now = corners(current);
    ui.heading("Orbifold");
    let id = ui.make_persistent_id("signature text");
    let mut text: String = ui
        .data(|d| d.get_temp::<(String, String)>(id))
        .filter(|(of, _)| of == current)
        .map_or_else(|| shown(current), |(_, typed)| typed);
    ui.horizontal(|ui| {
        let label = ui.label("signature");
        let edit = ui
            .add(egui::TextEdit::singleline(&mut text).desired_width(140.0))
            .labelled_by(label.id);
        if edit.lost_focus() && text != shown(current) {
            changed = Some(text.clone());
        }
    });
    ui.data_mut(|d| d.insert_temp(id, (current.to_string(), text)));
    match summary(current) {
        Ok(s) => {
            egui::Grid::new("summary").num_columns(2).show(ui, |ui| {
                ui.label("canonical");
                ui.label(shown(&s.canonical));
                ui.end_row();
                ui.label("Euler char.");
                ui.label(format!("χ = {}", s.chi));
                ui.end_row();
                ui.label("geometry");
                ui.label(&s.geometry);
                ui.end_row();
                ui.label("kind");
                ui.label(&s.kind);
                ui.end_row();
            });
        }
        Err(e) => {
            ui.colored_label(Color32::LIGHT_RED, e);
        }
    }
    let Some(corners_now) = corners_now else {
        return changed;
    };
    let mut walls_count = walls(&corners_now);
    ui.horizontal(|ui| {
        if labelled_value(ui, "walls", &mut walls_count, 1..=24, 0.05).changed() {
            changed = Some(signature(&with_walls(&corners_now, walls_count)));
        }
    });
    // The corners as nodes round a circle with their spin boxes on them (seed Fig. 5.1); the
    // rows below name each corner and hold its ideal toggle.
    let nodes = draw_nodes(ui, &corners_now);
    let mut next = corners_now.clone();
    let mut names = Vec::with_capacity(next.len());
    egui::Grid::new("corners").num_columns(2).show(ui, |ui| {
        if next.is_empty() {
            ui.label("corner 1");
            ui.add_enabled(false, egui::Label::new("order 1 (one wall: no corner)"));
            ui.end_row();
        }
        for (i, corner) in next.iter_mut().enumerate() {
            names.push(ui.label(format!("corner {}", i + 1)).id);
            let mut ideal = *corner == Corner::Ideal;
            if ui
                .checkbox(&mut ideal, format!("ideal {}", i + 1))
                .changed()
            {
                *corner = if ideal {
                    Corner::Ideal
                } else {
                    Corner::Order(2.0)
                };
            }
            ui.end_row();
        }
    });
    for (i, (&at, &name)) in nodes.iter().zip(&names).enumerate() {
        let Corner::Order(mut k) = next[i] else {
            continue;
        };
        let spin = egui::DragValue::new(&mut k)
            .range(1.01..=1000.0)
            .speed(0.05);
        let rect = egui::Rect::from_center_size(at, Vec2::new(44.0, 20.0));
        // A child placed on the node, which leaves the panel's layout where it was.
        let mut node = ui.new_child(egui::UiBuilder::new().max_rect(rect));
        if node
            .add_sized(rect.size(), spin)
            .labelled_by(name)
            .changed()
        {
            next[i] = Corner::Order(k);
        }
    }
    if next.len() == 2 && next[0] != next[1] {
        // *kk: the two corners move together.
        let moved = usize::from(next[1] != corners_now[1]);
        next[1 - moved] = next[moved];
    }
    if next != corners_now {
        changed = Some(signature(&next));
    }
    changed
}

/// The corners as nodes round a circle, the walls as lines between them; returns where the
/// nodes are (a single grey node for the one-walled `*`, which has no corner to edit).
fn draw_nodes(ui: &mut Ui, corners: &[Corner]) -> Vec<Pos2> {
    let size = Vec2::new(ui.available_width().min(240.0), 150.0);
    let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
    let painter = ui.painter_at(rect);
    let centre = rect.center();
    let radius = 0.36 * rect.height();
    let n = corners.len().max(1);
    let node = |i: usize| -> Pos2 {
        let a = std::f32::consts::TAU * i as f32 / n as f32 - std::f32::consts::FRAC_PI_2;
        centre + radius * Vec2::angled(a)
    };
    let wall = Stroke::new(2.0, Color32::from_rgb(120, 170, 230));
    if corners.is_empty() {
        painter.circle_stroke(centre, radius, wall);
        painter.circle_filled(node(0), 11.0, Color32::from_rgb(60, 60, 70));
        painter.text(
            node(0),
            egui::Align2::CENTER_CENTER,
            "1",
            egui::FontId::proportional(12.0),
            Color32::GRAY,
        );
        return Vec::new();
    }
    for i in 0..n {
        painter.line_segment([node(i), node((i + 1) % n)], wall);
    }
    for (i, corner) in corners.iter().enumerate() {
        if *corner == Corner::Ideal {
            // An ideal corner has no order to edit: it is drawn, not spun.
            painter.circle_filled(node(i), 13.0, Color32::from_rgb(60, 60, 70));
            painter.text(
                node(i),
                egui::Align2::CENTER_CENTER,
                "inf",
                egui::FontId::proportional(12.0),
                Color32::WHITE,
            );
        }
    }
    (0..n).map(node).collect()
}
