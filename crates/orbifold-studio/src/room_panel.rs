//! Room design (seed §5.2): height and tessellation; per wall, mirrors that can be added,
//! removed, resized, coloured and given a reflectance; floor and ceiling colour or checkerboard;
//! objects (built-in shapes or a mesh file) with position, height, yaw, size, crease angle for
//! smooth shading and colour; lights
//! with position, colour and power.

use egui::{Color32, Ui};
use orbifold_scene::mesh::procedural::NAMES;
use orbifold_scene::{Color, Light, Material, MetalName, Mirror, Object, Scene, Wall};

use crate::design::labelled_value;
use crate::layout_view::wall_colour;

/// The room panel. Returns the changed scene, if the user changed it. A file to pick (a mesh,
/// an image) is asked for through [`take_pick`].
pub fn show(ui: &mut Ui, scene: &Scene) -> Option<Scene> {
    let mut next = scene.clone();
    let layout = scene.layout().ok();
    let walls = layout.as_ref().map_or(0, |l| l.edges.len());
    // The partner of each wall that is a portal (a wall the orbifold's group pairs with another).
    let partners: Vec<Option<usize>> = (0..walls)
        .map(|w| layout.as_ref().and_then(|l| l.edges[w].partner()))
        .collect();
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
    material(ui, "floor", &mut next.room.floor, Target::Floor, false);
    material(
        ui,
        "ceiling",
        &mut next.room.ceiling,
        Target::Ceiling,
        false,
    );
    material(
        ui,
        "walls",
        &mut next.room.wall_material,
        Target::Walls,
        false,
    );
    image_target(ui, &next);

    egui::CollapsingHeader::new("Walls and mirrors")
        .default_open(true)
        .show(ui, |ui| {
            for (w, &partner) in partners.iter().enumerate() {
                wall(ui, &mut next, w, partner);
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
    Marble,
    Plastic,
    Metal,
    Glass,
}

impl Surface {
    /// The kinds and their names in the panel; glass only where `glass` (objects: a room's
    /// surfaces are opaque).
    fn all(glass: bool) -> impl Iterator<Item = (Surface, &'static str)> {
        [
            (Surface::Colour, "colour"),
            (Surface::Checker, "checker"),
            (Surface::Texture, "image"),
            (Surface::Marble, "marble"),
            (Surface::Plastic, "plastic"),
            (Surface::Metal, "metal"),
            (Surface::Glass, "glass"),
        ]
        .into_iter()
        .filter(move |(s, _)| glass || *s != Surface::Glass)
    }

    fn of(material: &Material) -> Surface {
        match material {
            Material::Color { .. } => Surface::Colour,
            Material::Checker { .. } => Surface::Checker,
            Material::Texture { .. } => Surface::Texture,
            Material::Marble { .. } => Surface::Marble,
            Material::Plastic { .. } => Surface::Plastic,
            Material::Metal { .. } => Surface::Metal,
            Material::Glass { .. } => Surface::Glass,
        }
    }

    /// A material of this kind that looks like `base` where the kind has a colour (the
    /// scene format's defaults otherwise).
    fn material(self, base: Color) -> Material {
        match self {
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
            Surface::Marble => Material::Marble {
                base,
                vein: base.map(|c| c * 0.3),
                scale: 0.3,
                coordinates: Default::default(),
            },
            Surface::Plastic => Material::Plastic {
                color: base,
                roughness: 0.2,
            },
            Surface::Metal => Material::Metal {
                metal: MetalName::Silver,
                roughness: 0.1,
            },
            Surface::Glass => Material::Glass {
                tint: [1.0; 3],
                ior: 1.5,
            },
        }
    }
}

/// What a picked or dropped image goes on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Target {
    /// The floor.
    #[default]
    Floor,
    /// The ceiling.
    Ceiling,
    /// The walls without a mirror (the room's wall material).
    Walls,
    /// Object `i`.
    Object(usize),
}

impl Target {
    /// The name the panel shows.
    pub fn name(self) -> String {
        match self {
            Target::Floor => "floor".into(),
            Target::Ceiling => "ceiling".into(),
            Target::Walls => "walls".into(),
            Target::Object(i) => format!("object {i}"),
        }
    }

    /// The material it names in `scene`, if there is one.
    pub fn material_mut(self, scene: &mut Scene) -> Option<&mut Material> {
        match self {
            Target::Floor => Some(&mut scene.room.floor),
            Target::Ceiling => Some(&mut scene.room.ceiling),
            Target::Walls => Some(&mut scene.room.wall_material),
            Target::Object(i) => scene.objects.get_mut(i).map(|o| &mut o.material),
        }
    }
}

/// A file the panel asks the studio to pick (with a file dialog, between frames).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pick {
    /// A mesh for a new object.
    Mesh,
    /// An image for this surface.
    Texture(Target),
}

fn pick_id() -> egui::Id {
    egui::Id::unique("room panel pick")
}

fn target_id() -> egui::Id {
    egui::Id::unique("room panel image target")
}

/// Takes the file the panel asked for in this frame, if it asked.
pub fn take_pick(ctx: &egui::Context) -> Option<Pick> {
    ctx.data_mut(|d| {
        let pick = d.get_temp::<Pick>(pick_id());
        d.remove::<Pick>(pick_id());
        pick
    })
}

/// The surface that dropped images go on: the one chosen in the panel (the floor at first).
pub fn texture_target(ctx: &egui::Context) -> Target {
    ctx.data(|d| d.get_temp(target_id())).unwrap_or_default()
}

/// Sets the surface that dropped images go on.
pub fn set_texture_target(ctx: &egui::Context, target: Target) {
    ctx.data_mut(|d| d.insert_temp(target_id(), target));
}

/// Puts the image at `path` (as the scene should hold it) on `target` in `scene`: the surface
/// becomes an image texture, keeping its size if it already was one. Returns whether the
/// target exists.
pub fn apply_texture(scene: &mut Scene, target: Target, path: String) -> bool {
    let Some(material) = target.material_mut(scene) else {
        return false;
    };
    *material = match material {
        Material::Texture {
            scale, coordinates, ..
        } => Material::Texture {
            path,
            scale: *scale,
            coordinates: *coordinates,
        },
        _ => Material::Texture {
            path,
            scale: 0.5,
            coordinates: Default::default(),
        },
    };
    true
}

/// A new object made from the mesh file `path` (as the scene should hold it), at the room's
/// centre.
pub fn mesh_object(scene: &Scene, path: String) -> Object {
    let centre = scene
        .layout()
        .map_or(num_complex::Complex64::new(0.0, 0.0), |l| l.centre);
    Object {
        mesh: Some(path),
        at: [centre.re, centre.im],
        size: 0.4,
        ..Object::default()
    }
}

/// A surface's material: a colour, a checkerboard, an image texture, marble, plastic, metal
/// or (objects only, `glass`) glass, each with its settings.
fn material(ui: &mut Ui, name: &str, material: &mut Material, target: Target, glass: bool) {
    ui.horizontal_wrapped(|ui| {
        ui.label(name);
        let kind = Surface::of(material);
        let mut chosen = kind;
        // The plain kinds side by side, the rest in a menu: the panel stays narrow.
        let (plain, more): (Vec<_>, Vec<_>) = Surface::all(glass || kind == Surface::Glass)
            .partition(|(s, _)| matches!(s, Surface::Colour | Surface::Checker | Surface::Texture));
        for (surface, label) in plain {
            ui.selectable_value(&mut chosen, surface, format!("{name}: {label}"));
        }
        let current = more.iter().find(|(s, _)| *s == kind).map(|(_, l)| *l);
        let button = format!("{name}: {}…", current.unwrap_or("more"));
        let menu = egui::Button::new(button).selected(current.is_some());
        egui::containers::menu::MenuButton::from_button(menu).ui(ui, |ui| {
            for (surface, label) in more {
                if ui
                    .selectable_value(&mut chosen, surface, format!("{name}: {label}"))
                    .clicked()
                {
                    ui.close();
                }
            }
        });
        if chosen != kind {
            let base = orbifold_scene::geometry::representative(material);
            *material = chosen.material(base);
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
                if ui.button(format!("pick {name} image…")).clicked() {
                    ui.data_mut(|d| d.insert_temp(pick_id(), Pick::Texture(target)));
                }
                labelled_value(ui, &format!("{name} image size"), scale, 0.01..=50.0, 0.005);
            }
            Material::Marble {
                base, vein, scale, ..
            } => {
                colour(ui, &format!("{name} marble ground"), base);
                colour(ui, &format!("{name} marble veins"), vein);
                labelled_value(
                    ui,
                    &format!("{name} marble size"),
                    scale,
                    0.01..=50.0,
                    0.005,
                );
            }
            Material::Plastic { color, roughness } => {
                colour(ui, &format!("{name} colour"), color);
                labelled_value(
                    ui,
                    &format!("{name} roughness"),
                    roughness,
                    0.0..=1.0,
                    0.005,
                );
            }
            Material::Metal { metal, roughness } => {
                egui::ComboBox::from_label(format!("{name} metal"))
                    .selected_text(format!("{metal:?}").to_lowercase())
                    .show_ui(ui, |ui| {
                        for m in [
                            MetalName::Silver,
                            MetalName::Gold,
                            MetalName::Copper,
                            MetalName::Aluminium,
                        ] {
                            ui.selectable_value(metal, m, format!("{m:?}").to_lowercase());
                        }
                    });
                labelled_value(
                    ui,
                    &format!("{name} roughness"),
                    roughness,
                    0.0..=1.0,
                    0.005,
                );
            }
            Material::Glass { tint, ior } => {
                colour(ui, &format!("{name} tint"), tint);
                labelled_value(
                    ui,
                    &format!("{name} refractive index"),
                    ior,
                    1.0..=3.0,
                    0.005,
                );
            }
        }
    });
}

/// Wall `w`: its mirrors, each with extent and reflectance; for a portal (`partner`: the wall
/// it leads to), what it is, and the mirrors hung on it.
fn wall(ui: &mut Ui, scene: &mut Scene, w: usize, partner: Option<usize>) {
    let mut mirrors = scene.mirrors_of_wall(w, partner.is_some());
    let before = mirrors.clone();
    ui.horizontal(|ui| {
        let (rect, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
        ui.painter().rect_filled(rect, 2.0, wall_colour(w));
        match partner {
            Some(to) => ui.label(format!(
                "wall {w}: portal to wall {to}, {} mirror(s)",
                mirrors.len()
            )),
            None => ui.label(format!("wall {w}: {} mirror(s)", mirrors.len())),
        };
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

/// The surface that dropped images go on, chosen among the room's and the objects'.
fn image_target(ui: &mut Ui, scene: &Scene) {
    let mut target = texture_target(ui.ctx());
    if let Target::Object(i) = target
        && i >= scene.objects.len()
    {
        target = Target::Floor;
    }
    let before = target;
    egui::ComboBox::from_label("dropped images go on")
        .selected_text(target.name())
        .show_ui(ui, |ui| {
            let room = [Target::Floor, Target::Ceiling, Target::Walls];
            let objects = (0..scene.objects.len()).map(Target::Object);
            for t in room.into_iter().chain(objects) {
                ui.selectable_value(&mut target, t, t.name());
            }
        });
    if target != before || texture_target(ui.ctx()) != target {
        set_texture_target(ui.ctx(), target);
    }
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
        if ui.button("pick mesh…").clicked() {
            ui.data_mut(|d| d.insert_temp(pick_id(), Pick::Mesh));
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
            let object = mesh_object(scene, path.trim().to_string());
            scene.objects.push(object);
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
        });
        material(ui, &name, &mut object.material, Target::Object(i), true);
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
