//! The layout view (seed §5.1): the polygon in its model (Poincaré disk, stereographic or
//! Euclidean plane), edges coloured, the free parameters, the shape presets, and the placement
//! arrow: drag in the view to move the polygon, drag with Shift (or the right button) to turn it.
//! The room's objects (white rings) and lights (yellow dots) are shown where they stand and are
//! placed by dragging them: the layout view is also the room's top view.

use egui::{Color32, Pos2, Stroke, Ui, Vec2};
use num_complex::Complex64;
use orbifold::layout::ParameterMeaning;
use orbifold::space::ModelGeodesic;
use orbifold::{Geometry, Layout};
use orbifold_scene::{Scene, ShapeName};

use crate::design::labelled_value;

/// Colours of the walls, in order (the same in the room panel).
pub fn wall_colour(i: usize) -> Color32 {
    const COLOURS: [Color32; 8] = [
        Color32::from_rgb(230, 90, 80),
        Color32::from_rgb(90, 180, 90),
        Color32::from_rgb(80, 140, 230),
        Color32::from_rgb(230, 180, 60),
        Color32::from_rgb(180, 100, 220),
        Color32::from_rgb(60, 200, 200),
        Color32::from_rgb(240, 130, 190),
        Color32::from_rgb(150, 150, 150),
    ];
    COLOURS[i % COLOURS.len()]
}

/// What a drag in the layout view holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Item {
    Object(usize),
    Light(usize),
}

/// Points along wall `i` of the layout, in model coordinates.
pub fn wall_points(layout: &Layout, i: usize) -> Vec<Complex64> {
    let space = layout.space();
    let edge = &layout.edges[i];
    let ends = (
        edge.from.map(|v| layout.vertices[v].position),
        edge.to.map(|v| layout.vertices[v].position),
    );
    let inside = |z: Complex64| {
        let p = if space.geometry() == Geometry::Hyperbolic && z.norm() >= 1.0 {
            return false;
        } else {
            space.to_ambient(z)
        };
        layout.edges.iter().all(|e| e.wall.dot(p) > -1e-6)
    };
    match (edge.geodesic, ends) {
        (ModelGeodesic::Line { point, direction }, (Some(a), Some(b))) => {
            let _ = (point, direction);
            (0..=32)
                .map(|k| a + (b - a) * (f64::from(k) / 32.0))
                .collect()
        }
        (ModelGeodesic::Circle { centre, radius }, (Some(a), Some(b))) => {
            let (t0, mut t1) = ((a - centre).arg(), (b - centre).arg());
            if t1 < t0 {
                t1 += std::f64::consts::TAU;
            }
            // Of the two arcs between the ends, the one whose middle is on the polygon.
            let arc = |from: f64, to: f64| -> Vec<Complex64> {
                (0..=64)
                    .map(|k| {
                        centre
                            + Complex64::from_polar(
                                radius,
                                from + (to - from) * f64::from(k) / 64.0,
                            )
                    })
                    .collect()
            };
            let first = arc(t0, t1);
            if inside(first[32]) {
                first
            } else {
                arc(t1, t0 + std::f64::consts::TAU)
            }
        }
        (ModelGeodesic::Circle { centre, radius }, _) => (0..=128)
            .map(|k| {
                centre + Complex64::from_polar(radius, std::f64::consts::TAU * f64::from(k) / 128.0)
            })
            .filter(|&z| inside(z))
            .collect(),
        (ModelGeodesic::Line { point, direction }, _) => (-32..=32)
            .map(|k| point + direction * (f64::from(k) / 8.0))
            .collect(),
    }
}

/// A drag value for a shape parameter that stays inside its open range `(low, high)`: a value
/// dragged or typed is kept a little inside the ends (a polygon at an end is degenerate), and
/// one read from a file is shown as it is, never moved by showing it. The step is a two-hundredth
/// of a bounded range, or a hundredth of the value.
pub fn parameter_drag(value: &mut f64, (low, high): (f64, f64)) -> egui::DragValue<'_> {
    let (inner_low, inner_high, speed) = if high.is_finite() {
        let margin = (high - low) * 1e-3;
        (low + margin, high - margin, (high - low) / 200.0)
    } else {
        let low = if low > 0.0 { low * 1.001 } else { low + 1e-3 };
        (low, 1e6, (value.abs() / 100.0).max(1e-3))
    };
    egui::DragValue::new(value)
        .range(inner_low..=inner_high)
        .clamp_existing_to_range(false)
        .speed(speed)
        .max_decimals(4)
}

/// The layout view and its controls. Returns the changed scene, if the user changed it.
pub fn show(ui: &mut Ui, scene: &Scene) -> Option<Scene> {
    let mut next = scene.clone();
    ui.heading("Layout");
    let layout = match scene.layout() {
        Ok(layout) => layout,
        Err(e) => {
            ui.colored_label(Color32::LIGHT_RED, e);
            return None;
        }
    };
    ui.horizontal(|ui| {
        ui.label("shape");
        ui.selectable_value(&mut next.orbifold.shape, ShapeName::Default, "seed default");
        ui.selectable_value(&mut next.orbifold.shape, ShapeName::Incircle, "incircle");
    });
    if next.orbifold.shape != scene.orbifold.shape {
        next.orbifold.parameters.clear();
    }
    let mut highlight = None;
    if !layout.parameters.is_empty() && next.orbifold.shape == ShapeName::Default {
        let mut values = layout.parameters.clone();
        let meaning = layout.parameter_meaning.describe(layout.vertices.len());
        egui::Grid::new("parameters").num_columns(2).show(ui, |ui| {
            for (i, v) in values.iter_mut().enumerate() {
                let range = layout
                    .parameter_ranges
                    .get(i)
                    .copied()
                    .unwrap_or((0.0, f64::INFINITY));
                let label = ui.label(format!("parameter {}", i + 1));
                let r = ui
                    .add(parameter_drag(v, range))
                    .labelled_by(label.id)
                    .on_hover_text(&meaning);
                if r.hovered() || r.dragged() || r.has_focus() {
                    highlight = Some(i);
                }
                ui.end_row();
            }
        });
        if values != layout.parameters {
            next.orbifold.parameters = values;
        }
    } else if layout.parameters.is_empty() {
        ui.label("the polygon is rigid: no free parameters");
    }
    ui.horizontal(|ui| {
        labelled_value(ui, "x", &mut next.orbifold.at[0], -0.95..=0.95, 0.005);
        labelled_value(ui, "y", &mut next.orbifold.at[1], -0.95..=0.95, 0.005);
        labelled_value(ui, "turn", &mut next.orbifold.angle, -360.0..=360.0, 0.5);
    });
    draw(ui, &layout, &mut next, highlight);
    (next != *scene).then_some(next)
}

/// Where the arrow on portal `i` goes and which way it points (screen units): at the middle of
/// the wall's drawn points, along it, so that the pairing takes the partner's arrow onto this
/// one's, as textbooks draw side pairings. The lower of the pair points from its first corner to
/// its second; the pairing takes the partner's first corner to this wall's second one, unless it
/// reverses orientation (a glide), which keeps them.
fn portal_arrow(layout: &Layout, i: usize, points: &[Pos2]) -> Option<(Pos2, Vec2)> {
    let partner = layout.edges[i].partner()?;
    let reverses = layout.edges[i].neighbour.determinant() < 0.0;
    let forward = orbifold::pairing::arrow_runs_forward(i, partner, reverses);
    let middle = points.len() / 2;
    let (a, b) = (
        points.get(middle.saturating_sub(1))?,
        points.get(middle.max(1))?,
    );
    let along = (*b - *a).normalized();
    if !along.is_finite() {
        return None;
    }
    let at = a.lerp(*b, 0.5);
    Some((at, if forward { along } else { -along }))
}

/// The walls a free parameter controls, and the cut between them (model points along their
/// common perpendicular), for parameter `j` (0-based).
pub fn parameter_cut(layout: &Layout, j: usize) -> (Vec<usize>, Vec<Complex64>) {
    let n = layout.edges.len();
    match layout.parameter_meaning {
        ParameterMeaning::AspectRatio => (vec![0, 1], Vec::new()),
        ParameterMeaning::WallDistances if j + 1 < n => {
            let (a, b) = (n - 1, j + 1);
            let space = layout.space();
            let (nu, mu) = (layout.edges[a].wall, layout.edges[b].wall);
            // The common perpendicular's form is orthogonal to both under the dual form; its
            // feet lie on it and on each wall.
            let g = |v: glam::DVec3| glam::DVec3::new(v.x, v.y, space.kappa() * v.z);
            let perpendicular = g(nu.cross(mu));
            let foot = |wall: glam::DVec3| {
                let p = perpendicular.cross(wall);
                let p = if p.z < 0.0 { -p } else { p };
                (space.point_dot(p, p) * space.kappa() > 0.0).then(|| space.normalize_point(p))
            };
            let cut = match (foot(nu), foot(mu)) {
                (Some(p), Some(q)) => (0..=24)
                    .map(|k| space.to_model(space.interpolate(p, q, f64::from(k) / 24.0)))
                    .collect(),
                _ => Vec::new(),
            };
            (vec![a, b], cut)
        }
        _ => (Vec::new(), Vec::new()),
    }
}

/// Draws the polygon in its model; dragging moves or turns it.
fn draw(ui: &mut Ui, layout: &Layout, scene: &mut Scene, highlight: Option<usize>) {
    let side = ui.available_width().clamp(160.0, 420.0);
    let (rect, response) = ui.allocate_exact_size(Vec2::splat(side), egui::Sense::drag());
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "top view"));
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 4.0, Color32::from_gray(24));
    let space = layout.space();
    // The view: the unit disk fills it for the hyperbolic plane; the others are scaled to the
    // polygon.
    let extent = match space.geometry() {
        Geometry::Hyperbolic => 1.05,
        _ => {
            layout
                .vertices
                .iter()
                .map(|v| v.position.norm())
                .fold(0.6, f64::max)
                * 1.3
        }
    };
    let scale = 0.5 * side as f64 / extent;
    let to_screen = |z: Complex64| -> Pos2 {
        rect.center() + Vec2::new((z.re * scale) as f32, (-z.im * scale) as f32)
    };
    if space.geometry() == Geometry::Hyperbolic {
        painter.circle_stroke(rect.center(), scale as f32, Stroke::new(1.0, Color32::GRAY));
    }
    let (controlled, cut) = highlight.map_or_else(Default::default, |j| parameter_cut(layout, j));
    for i in 0..layout.edges.len() {
        let points: Vec<Pos2> = wall_points(layout, i).into_iter().map(to_screen).collect();
        let width = if controlled.contains(&i) { 5.0 } else { 2.5 };
        match layout.edges[i].partner() {
            None => {
                painter.add(egui::Shape::line(
                    points,
                    Stroke::new(width, wall_colour(i)),
                ));
            }
            Some(partner) => {
                // A portal: dashed, in the colour of its pair, with the textbooks' arrow.
                let colour = wall_colour(i.min(partner));
                painter.add(egui::Shape::dashed_line(
                    &points,
                    Stroke::new(width, colour),
                    7.0,
                    4.0,
                ));
                if let Some((at, direction)) = portal_arrow(layout, i, &points) {
                    painter.arrow(
                        at - direction * 7.0,
                        direction * 14.0,
                        Stroke::new(2.5, colour),
                    );
                }
            }
        }
    }
    if !cut.is_empty() {
        let points: Vec<Pos2> = cut.into_iter().map(to_screen).collect();
        painter.add(egui::Shape::dashed_line(
            &points,
            Stroke::new(2.0, Color32::WHITE),
            6.0,
            4.0,
        ));
    }
    for v in &layout.vertices {
        painter.circle_filled(to_screen(v.position), 3.0, Color32::WHITE);
    }
    // The placement arrow at the centre, along the polygon's heading.
    let c = to_screen(layout.centre);
    let heading = Vec2::angled(-(layout.heading as f32)) * 28.0;
    painter.arrow(c, heading, Stroke::new(2.0, Color32::YELLOW));
    let from_screen = |p: Pos2| -> Complex64 {
        let d = p - rect.center();
        Complex64::new(f64::from(d.x) / scale, -f64::from(d.y) / scale)
    };
    // Objects (white rings) and lights (yellow dots), placed by dragging.
    for o in &scene.objects {
        let p = to_screen(Complex64::new(o.at[0], o.at[1]));
        painter.circle_stroke(p, 6.0, Stroke::new(2.0, Color32::WHITE));
    }
    for l in &scene.lights {
        let p = to_screen(Complex64::new(l.at[0], l.at[1]));
        painter.circle_filled(p, 4.0, Color32::from_rgb(250, 220, 120));
    }
    let held = ui.make_persistent_id("layout view: dragged item");
    if response.drag_started()
        && let Some(pointer) = response.interact_pointer_pos()
    {
        let near = |at: [f64; 2]| to_screen(Complex64::new(at[0], at[1])).distance(pointer) < 10.0;
        let item = scene
            .objects
            .iter()
            .position(|o| near(o.at))
            .map(Item::Object)
            .or_else(|| {
                scene
                    .lights
                    .iter()
                    .position(|l| near(l.at))
                    .map(Item::Light)
            });
        ui.data_mut(|d| d.insert_temp(held, item));
    }
    let item: Option<Item> = ui.data(|d| d.get_temp(held)).flatten();
    if response.dragged()
        && let (Some(item), Some(pointer)) = (item, response.interact_pointer_pos())
    {
        let z = from_screen(pointer);
        let inside = space.kappa() >= 0.0 || z.norm() < 0.999;
        if inside {
            match item {
                Item::Object(i) => scene.objects[i].at = [z.re, z.im],
                Item::Light(i) => scene.lights[i].at = [z.re, z.im],
            }
        }
    } else if response.dragged() {
        let delta = response.drag_delta();
        let turning =
            ui.input(|i| i.modifiers.shift) || response.dragged_by(egui::PointerButton::Secondary);
        if turning {
            scene.orbifold.angle += f64::from(delta.x) * 0.5;
        } else {
            let moved = Complex64::new(
                scene.orbifold.at[0] + f64::from(delta.x) / scale,
                scene.orbifold.at[1] - f64::from(delta.y) / scale,
            );
            let limit = if space.kappa() < 0.0 { 0.9 } else { 5.0 };
            let moved = if moved.norm() > limit {
                moved / moved.norm() * limit
            } else {
                moved
            };
            scene.orbifold.at = [moved.re, moved.im];
        }
    }
}
