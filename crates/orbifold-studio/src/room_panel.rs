//! Room design (seed §5.2): height and tessellation; per wall, mirrors that can be added,
//! removed, resized, coloured and given a reflectance; floor and ceiling colour or checkerboard;
//! objects (built-in shapes or a mesh file) with position, height, yaw, size, crease angle for
//! smooth shading and colour; lights
//! with position, colour and power.

use egui::{Color32, Ui};
use orbifold_scene::mesh::procedural::NAMES;
use orbifold_scene::{Color, Light, Material, Mirror, Object, Scene, Wall};

use crate::design::labelled_value;
use crate::layout_view::wall_colour;

/// The room panel. Returns the changed scene, if the user changed it.
pub fn show(ui: &mut Ui, scene: &Scene) -> Option<Scene> {
    let mut next = scene.clone();
    let walls = scene.layout().map_or(0, |l| l.edges.len());
    ui.heading("Room");
    egui::Grid::new("room").num_columns(2).show(ui, |ui| {
        labelled_value(ui, "height", &mut next.room.height, 0.05..=20.0, 0.01);
        ui.end_row();
        labelled_value(
            ui,
            "resolution",
            &mut next.room.resolution,
            0.01..=1.0,
            0.002,
        );
        ui.end_row();
    });
    material(ui, "floor", &mut next.room.floor);
    material(ui, "ceiling", &mut next.room.ceiling);

    egui::CollapsingHeader::new("Walls and mirrors")
        .default_open(true)
        .show(ui, |ui| {
            for w in 0..walls {
                wall(ui, &mut next, w);
            }
        });
    egui::CollapsingHeader::new("Objects")
        .default_open(true)
        .show(ui, |ui| objects(ui, &mut next));
    egui::CollapsingHeader::new("Lights")
        .default_open(true)
        .show(ui, |ui| lights(ui, &mut next));
    (next != *scene).then_some(next)
}

fn colour(ui: &mut Ui, name: &str, color: &mut Color) {
    let mut rgb = color.map(|c| c as f32);
    let label = ui.label(name);
    if ui
        .color_edit_button_rgb(&mut rgb)
        .labelled_by(label.id)
        .changed()
    {
        *color = rgb.map(f64::from);
    }
}

/// The kinds of surface the panel edits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Surface {
    Colour,
    Checker,
    Texture,
}

/// A surface's material: a colour, a checkerboard or an image texture (other materials keep
/// their settings and show their representative colour).
fn material(ui: &mut Ui, name: &str, material: &mut Material) {
    ui.horizontal_wrapped(|ui| {
        ui.label(name);
        let kind = match material {
            Material::Checker { .. } => Some(Surface::Checker),
            Material::Texture { .. } => Some(Surface::Texture),
            Material::Color { .. } => Some(Surface::Colour),
            _ => None,
        };
        if let Some(kind) = kind {
            let mut chosen = kind;
            ui.selectable_value(&mut chosen, Surface::Colour, format!("{name}: colour"));
            ui.selectable_value(&mut chosen, Surface::Checker, format!("{name}: checker"));
            ui.selectable_value(&mut chosen, Surface::Texture, format!("{name}: image"));
            if chosen != kind {
                let base = orbifold_scene::geometry::representative(material);
                *material = match chosen {
                    Surface::Colour => Material::Color { color: base },
                    Surface::Checker => Material::Checker {
                        colors: [base, base.map(|c| c * 0.6)],
                        size: 0.1,
                        coordinates: Default::default(),
                    },
                    Surface::Texture => Material::Texture {
                        path: String::new(),
                        scale: 0.5,
                        coordinates: Default::default(),
                    },
                };
            }
        }
        match material {
            Material::Color { color } => colour(ui, &format!("{name} colour"), color),
            Material::Checker { colors, size, .. } => {
                colour(ui, &format!("{name} colour 1"), &mut colors[0]);
                colour(ui, &format!("{name} colour 2"), &mut colors[1]);
                labelled_value(ui, &format!("{name} square"), size, 0.005..=5.0, 0.002);
            }
            Material::Texture { path, scale, .. } => {
                let label = ui.label(format!("{name} image file"));
                ui.add(
                    egui::TextEdit::singleline(path)
                        .hint_text("PNG or JPEG")
                        .desired_width(140.0),
                )
                .labelled_by(label.id);
                labelled_value(ui, &format!("{name} image size"), scale, 0.01..=50.0, 0.005);
            }
            other => {
                let c = orbifold_scene::geometry::representative(other);
                ui.label(format!("(set in the scene file; shown as {c:.2?})"));
            }
        }
    });
}

/// Wall `w`: its mirrors, each with extent and reflectance.
fn wall(ui: &mut Ui, scene: &mut Scene, w: usize) {
    let mut mirrors = scene.wall_mirrors(w);
    let before = mirrors.clone();
    ui.horizontal(|ui| {
        let (rect, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
        ui.painter().rect_filled(rect, 2.0, wall_colour(w));
        ui.label(format!("wall {w}: {} mirror(s)", mirrors.len()));
        if ui.button(format!("add mirror to wall {w}")).clicked() {
            mirrors.push(Mirror {
                reflectance: scene.room.reflectance,
                ..Mirror::default()
            });
        }
    });
    let mut remove = None;
    for (j, m) in mirrors.iter_mut().enumerate() {
        ui.horizontal_wrapped(|ui| {
            ui.add_space(14.0);
            let prefix = format!("mirror {w}.{j}");
            labelled_value(ui, &format!("{prefix} from"), &mut m.from, 0.0..=1.0, 0.005);
            labelled_value(ui, &format!("{prefix} to"), &mut m.to, 0.0..=1.0, 0.005);
            labelled_value(
                ui,
                &format!("{prefix} bottom"),
                &mut m.bottom,
                0.0..=20.0,
                0.005,
            );
            let mut top = m.top.unwrap_or(scene.room.height);
            if labelled_value(ui, &format!("{prefix} top"), &mut top, 0.0..=20.0, 0.005).changed() {
                m.top = Some(top);
            }
            colour(ui, &format!("{prefix} reflectance"), &mut m.reflectance);
            if ui.button(format!("remove mirror {w}.{j}")).clicked() {
                remove = Some(j);
            }
        });
        // Keep the extent ordered.
        m.to = m.to.max(m.from);
    }
    if let Some(j) = remove {
        mirrors.remove(j);
    }
    if mirrors != before {
        set_wall_mirrors(scene, w, mirrors);
    }
}

/// Gives wall `w` exactly these mirrors (as a `[[walls]]` entry of the scene).
pub fn set_wall_mirrors(scene: &mut Scene, w: usize, mirrors: Vec<Mirror>) {
    match scene.walls.iter_mut().find(|x| x.index == w) {
        Some(wall) => wall.mirrors = mirrors,
        None => scene.walls.push(Wall {
            index: w,
            material: None,
            mirrors,
        }),
    }
    scene.walls.sort_by_key(|x| x.index);
}

fn objects(ui: &mut Ui, scene: &mut Scene) {
    let centre = scene
        .layout()
        .map_or(num_complex::Complex64::new(0.0, 0.0), |l| l.centre);
    ui.horizontal(|ui| {
        let id = ui.make_persistent_id("new object shape");
        let mut shape: String = ui
            .data(|d| d.get_temp(id))
            .unwrap_or_else(|| "sphere".into());
        egui::ComboBox::from_label("shape")
            .selected_text(&shape)
            .show_ui(ui, |ui| {
                for name in NAMES {
                    ui.selectable_value(&mut shape, name.to_string(), name);
                }
            });
        ui.data_mut(|d| d.insert_temp(id, shape.clone()));
        if ui.button("add object").clicked() {
            scene.objects.push(Object {
                shape,
                at: [centre.re, centre.im],
                size: 0.3,
                ..Object::default()
            });
        }
    });
    ui.horizontal(|ui| {
        let id = ui.make_persistent_id("new object mesh");
        let mut path: String = ui.data(|d| d.get_temp(id)).unwrap_or_default();
        let label = ui.label("mesh file");
        ui.add(
            egui::TextEdit::singleline(&mut path)
                .hint_text("OBJ, PLY, glTF")
                .desired_width(150.0),
        )
        .labelled_by(label.id);
        if ui
            .add_enabled(
                !path.trim().is_empty(),
                egui::Button::new("add mesh object"),
            )
            .clicked()
        {
            scene.objects.push(Object {
                mesh: Some(path.trim().to_string()),
                at: [centre.re, centre.im],
                size: 0.4,
                ..Object::default()
            });
        }
        ui.data_mut(|d| d.insert_temp(id, path));
    });
    let mut remove = None;
    for (i, object) in scene.objects.iter_mut().enumerate() {
        let name = object.name.clone().unwrap_or_else(|| format!("object {i}"));
        ui.separator();
        ui.horizontal_wrapped(|ui| {
            let what = object.mesh.as_deref().unwrap_or(object.shape.as_str());
            ui.label(format!("{name} ({what})"));
            if ui.button(format!("remove {name}")).clicked() {
                remove = Some(i);
            }
        });
        ui.horizontal_wrapped(|ui| {
            labelled_value(
                ui,
                &format!("{name} x"),
                &mut object.at[0],
                -50.0..=50.0,
                0.005,
            );
            labelled_value(
                ui,
                &format!("{name} y"),
                &mut object.at[1],
                -50.0..=50.0,
                0.005,
            );
            labelled_value(
                ui,
                &format!("{name} height"),
                &mut object.height,
                0.0..=20.0,
                0.005,
            );
            labelled_value(
                ui,
                &format!("{name} yaw"),
                &mut object.yaw,
                -360.0..=360.0,
                1.0,
            );
            labelled_value(
                ui,
                &format!("{name} size"),
                &mut object.size,
                0.01..=20.0,
                0.005,
            );
            labelled_value(
                ui,
                &format!("{name} crease"),
                &mut object.crease,
                0.0..=180.0,
                1.0,
            );
            if let Material::Color { color } = &mut object.material {
                colour(ui, &format!("{name} colour"), color);
            }
        });
    }
    if let Some(i) = remove {
        scene.objects.remove(i);
    }
}

fn lights(ui: &mut Ui, scene: &mut Scene) {
    let centre = scene
        .layout()
        .map_or(num_complex::Complex64::new(0.0, 0.0), |l| l.centre);
    if ui.button("add light").clicked() {
        scene.lights.push(Light {
            at: [centre.re, centre.im],
            height: 0.9 * scene.room.height,
            ..Light::default()
        });
    }
    let mut remove = None;
    for (i, light) in scene.lights.iter_mut().enumerate() {
        ui.separator();
        ui.horizontal_wrapped(|ui| {
            let name = format!("light {i}");
            ui.colored_label(
                Color32::from_rgb(250, 220, 120),
                format!("{name} ({:?})", light.kind),
            );
            labelled_value(
                ui,
                &format!("{name} x"),
                &mut light.at[0],
                -50.0..=50.0,
                0.005,
            );
            labelled_value(
                ui,
                &format!("{name} y"),
                &mut light.at[1],
                -50.0..=50.0,
                0.005,
            );
            labelled_value(
                ui,
                &format!("{name} height"),
                &mut light.height,
                0.0..=20.0,
                0.005,
            );
            labelled_value(
                ui,
                &format!("{name} power"),
                &mut light.power,
                0.0..=10000.0,
                0.5,
            );
            colour(ui, &format!("{name} colour"), &mut light.color);
            if ui.button(format!("remove {name}")).clicked() {
                remove = Some(i);
            }
        });
    }
    if let Some(i) = remove {
        scene.lights.remove(i);
    }
}
