//! The studio driven through its real widgets, headlessly (egui_kittest): the design panel's
//! walls and corner orders change χ and the geometry; a free parameter changes the polygon;
//! mirrors, objects and lights added through the panels survive save and reopen; undo and redo;
//! snapshots of the main screens.

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use orbifold_scene::Scene;
use orbifold_studio::document::Document;
use orbifold_studio::{Studio, app::Tab};

fn harness(scene: Scene) -> Harness<'static, Studio> {
    let studio = Studio::new(Document::with_scene(scene, None, None), None);
    Harness::builder()
        // Tall enough for every row of the room panel without scrolling.
        .with_size(egui::vec2(1440.0, 1400.0))
        .build_ui_state(|ui, studio: &mut Studio| studio.ui(ui), studio)
}

fn set(harness: &mut Harness<'static, Studio>, name: &str, value: f64) {
    harness
        .get_by_role_and_label(Role::SpinButton, name)
        .set_value_accesskit(value);
    harness.run();
}

fn shows(harness: &Harness<'static, Studio>, text: &str) -> bool {
    harness.query_by_label(text).is_some()
}

#[test]
fn stepping_through_the_seeds_sequence_updates_chi_and_the_geometry() {
    let mut scene = Scene::default();
    scene.orbifold.signature = "*".into();
    let mut harness = harness(scene);
    assert!(shows(&harness, "χ = 1"), "the hemisphere *: χ = 1");
    // * → *22 → *33 → *233 → *333 → *2333 (seed §5.1).
    let steps: [(&str, f64, &str, &str, &str); 5] = [
        ("walls", 2.0, "*22", "χ = 1/2", "spherical"),
        ("corner 1", 3.0, "*33", "χ = 1/3", "spherical"),
        ("walls", 3.0, "*233", "χ = 1/12", "spherical"),
        ("corner 1", 3.0, "*333", "χ = 0", "euclidean"),
        ("walls", 4.0, "*2333", "χ = -1/4", "hyperbolic"),
    ];
    for (widget, value, signature, chi, geometry) in steps {
        set(&mut harness, widget, value);
        let scene = harness.state().document.scene();
        assert_eq!(scene.orbifold.signature, signature);
        assert!(shows(&harness, chi), "{signature}: {chi} not shown");
        assert!(
            shows(&harness, geometry),
            "{signature}: {geometry} not shown"
        );
    }
    // Two walls: the corners move together.
    set(&mut harness, "walls", 2.0);
    set(&mut harness, "corner 2", 5.0);
    assert_eq!(harness.state().document.scene().orbifold.signature, "*55");
    assert!(shows(&harness, "orbifold"));
    // A non-integer order: a room that is not an orbifold.
    set(&mut harness, "walls", 3.0);
    set(&mut harness, "corner 1", 2.5);
    assert_eq!(
        harness.state().document.scene().orbifold.signature,
        "*(2.5)55"
    );
    assert!(
        harness
            .query_all_by_label_contains("non-orbifold")
            .next()
            .is_some()
    );
}

#[test]
fn a_free_parameter_changes_the_polygon() {
    let mut harness = harness(Scene::default());
    let before = harness.state().document.scene().layout().unwrap();
    set(&mut harness, "parameter 1", 2.2);
    let scene = harness.state().document.scene().clone();
    assert_eq!(scene.orbifold.parameters[0], 2.2);
    let after = scene.layout().unwrap();
    let moved = before
        .vertices
        .iter()
        .zip(&after.vertices)
        .map(|(a, b)| (a.position - b.position).norm())
        .fold(0.0, f64::max);
    assert!(moved > 0.01, "the polygon did not change ({moved})");
    // The incircle preset has no free parameters.
    harness.get_by_label("incircle").click();
    harness.run();
    assert!(harness.query_by_label("parameter 1").is_none());
}

#[test]
fn mirrors_objects_and_lights_added_in_the_panels_survive_save_and_reopen() {
    let mut harness = harness(Scene::default());
    harness.get_by_label("add mirror to wall 1").click();
    harness.run();
    harness.get_by_label("add object").click();
    harness.run();
    harness.get_by_label("add light").click();
    harness.run();
    set(&mut harness, "object 1 yaw", 30.0);
    set(&mut harness, "light 1 power", 55.0);
    set(&mut harness, "mirror 1.1 bottom", 0.25);
    let scene = harness.state().document.scene().clone();
    assert_eq!(scene.wall_mirrors(1).len(), 2);
    assert_eq!(scene.wall_mirrors(1)[1].bottom, 0.25);
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.objects[1].yaw, 30.0);
    assert_eq!(scene.lights.len(), 2);
    assert_eq!(scene.lights[1].power, 55.0);

    // Save through the Save As dialog (Ctrl+S on a new document opens it).
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-studio-ui-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let path = dir.join("room.toml");
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    harness.run();
    harness
        .get_by_role_and_label(Role::TextInput, "file")
        .set_text_value_accesskit(path.to_str().unwrap());
    harness.run();
    harness.get_by_label("Save").click();
    harness.run();
    assert_eq!(harness.state().document.path(), Some(path.as_path()));
    assert!(!harness.state().document.is_dirty());

    // Reopen in a fresh studio.
    let reopened = Document::open(&path, None).unwrap();
    assert_eq!(reopened.scene(), &scene);
    let mut other = self::harness(Scene::default());
    other.state_mut().open(&path);
    other.run();
    assert_eq!(other.state().document.scene(), &scene);
}

#[test]
fn objects_are_placed_by_dragging_in_the_top_view_and_a_drag_is_one_undo_step() {
    let mut harness = harness(Scene::default());
    // The default room's figure stands at the centre of the Poincaré disk, which is the centre
    // of the top view.
    let view = harness.get_by_label("top view").rect();
    let start = view.center();
    let end = start + egui::vec2(24.0, -12.0);
    harness.hover_at(start);
    harness.run();
    harness.drag_at(start);
    harness.run();
    for k in 1..=6 {
        harness.hover_at(start + (end - start) * (k as f32 / 6.0));
        harness.run();
    }
    harness.drop_at(end);
    harness.run();
    let at = harness.state().document.scene().objects[0].at;
    assert!(at[0] > 0.01 && at[1] > 0.005, "the figure is at {at:?}");
    // The light stayed, and the polygon did not move.
    assert_eq!(harness.state().document.scene().orbifold.at, [0.0, 0.0]);
    harness.get_by_label("undo").click();
    harness.run();
    assert_eq!(harness.state().document.scene().objects[0].at, [0.0, 0.0]);
}

#[test]
fn a_mesh_file_becomes_an_object_and_a_broken_one_is_reported() {
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-studio-mesh-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let obj = dir.join("tetrahedron.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let mut harness = harness(Scene::default());
    let add = |harness: &mut Harness<'static, Studio>, path: &str| {
        harness
            .get_by_role_and_label(Role::TextInput, "mesh file")
            .set_text_value_accesskit(path);
        harness.run();
        harness.get_by_label("add mesh object").click();
        harness.run();
    };
    add(&mut harness, obj.to_str().unwrap());
    let scene = harness.state().document.scene();
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.objects[1].mesh.as_deref(), obj.to_str());
    assert_eq!(harness.state().view.error, None);
    // A file that is not there: the preview says so, nothing panics, and undo brings the
    // preview back.
    add(&mut harness, dir.join("missing.obj").to_str().unwrap());
    let error = harness.state().view.error.clone().unwrap_or_default();
    assert!(error.contains("missing.obj"), "{error}");
    harness.get_by_label("undo").click();
    harness.run();
    assert_eq!(harness.state().view.error, None);
}

#[test]
fn floors_and_ceilings_are_colours_checkerboards_or_images() {
    let mut harness = harness(Scene::default());
    harness.get_by_label("ceiling: checker").click();
    harness.run();
    harness.get_by_label("floor: image").click();
    harness.run();
    harness
        .get_by_role_and_label(Role::TextInput, "floor image file")
        .set_text_value_accesskit("wood.png");
    harness.run();
    set(&mut harness, "floor image size", 0.25);
    let room = &harness.state().document.scene().room;
    assert!(matches!(
        room.ceiling,
        orbifold_scene::Material::Checker { .. }
    ));
    match &room.floor {
        orbifold_scene::Material::Texture { path, scale, .. } => {
            assert_eq!((path.as_str(), *scale), ("wood.png", 0.25));
        }
        other => panic!("the floor is {other:?}"),
    }
}

#[test]
fn typing_in_a_field_is_one_undo_step() {
    let mut harness = harness(Scene::default());
    harness.get_by_label("floor: image").click();
    harness.run();
    let field = harness.get_by_role_and_label(Role::TextInput, "floor image file");
    field.focus();
    harness.run();
    for part in ["wo", "od", ".png"] {
        harness
            .get_by_role_and_label(Role::TextInput, "floor image file")
            .type_text(part);
        harness.run();
    }
    harness.key_press(egui::Key::Escape);
    harness.run();
    let floor = |h: &Harness<'static, Studio>| h.state().document.scene().room.floor.clone();
    assert!(
        matches!(floor(&harness), orbifold_scene::Material::Texture { ref path, .. } if path == "wood.png")
    );
    harness.get_by_label("undo").click();
    harness.run();
    assert!(
        matches!(floor(&harness), orbifold_scene::Material::Texture { ref path, .. } if path.is_empty())
    );
    harness.get_by_label("undo").click();
    harness.run();
    assert_eq!(floor(&harness), Scene::default().room.floor);
}

#[test]
fn an_object_s_crease_angle_is_set_in_the_room_panel() {
    let mut harness = harness(Scene::default());
    assert_eq!(harness.state().document.scene().objects[0].crease, 60.0);
    set(&mut harness, "object 0 crease", 0.0);
    assert_eq!(harness.state().document.scene().objects[0].crease, 0.0);
    // The field keeps to the angles a scene file may hold.
    set(&mut harness, "object 0 crease", 400.0);
    assert_eq!(harness.state().document.scene().objects[0].crease, 180.0);
}

#[test]
fn undo_and_redo_walk_the_history() {
    let mut harness = harness(Scene::default());
    let original = harness.state().document.scene().clone();
    set(&mut harness, "height", 1.5);
    harness.get_by_label("add light").click();
    harness.run();
    assert_eq!(harness.state().document.scene().lights.len(), 2);
    harness.get_by_label("undo").click();
    harness.run();
    assert_eq!(harness.state().document.scene().lights.len(), 1);
    assert_eq!(harness.state().document.scene().room.height, 1.5);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run();
    assert_eq!(harness.state().document.scene(), &original);
    harness.get_by_label("redo").click();
    harness.run();
    assert_eq!(harness.state().document.scene().room.height, 1.5);
    harness.key_press_modifiers(
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    harness.run();
    assert_eq!(harness.state().document.scene().lights.len(), 2);
}

#[test]
fn the_tiling_and_render_tabs_show_their_pictures() {
    let mut harness = harness(Scene::default());
    harness.get_by_label("tiling").click();
    harness.run();
    assert_eq!(harness.state().tab, Tab::Tiling);
    harness.get_by_label("render").click();
    harness.run();
    // Framed as the 3D view by default: the render takes the shape the view last drew.
    set(&mut harness, "render width", 64.0);
    let [w, h] = harness
        .state()
        .view
        .drawn_size()
        .expect("the 3D view was drawn");
    let height = ((64.0 * h as f64 / w as f64).round() as u32).clamp(16, 4096);
    assert_eq!(harness.state().render_size(), (64, height));
    assert!(harness.query_by_label("render height").is_none());
    // Unframed, the height is the user's.
    harness.get_by_label("frame as the 3D view").click();
    harness.run();
    set(&mut harness, "render width", 32.0);
    set(&mut harness, "render height", 24.0);
    assert_eq!(harness.state().render_size(), (32, 24));
    set(&mut harness, "render samples", 2.0);
    harness.get_by_label("Render").click();
    harness.run();
    for _ in 0..600 {
        if harness.query_by_label_contains("2 / 2 samples").is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
        harness.run_steps(1);
    }
    assert!(harness.query_by_label_contains("2 / 2 samples").is_some());
}

fn snapshot_harness(scene: Scene) -> Option<Harness<'static, Studio>> {
    if std::env::var_os("ORBIFOLD_REQUIRE_GPU").is_none()
        && orbifold_preview::Gpu::headless().is_err()
    {
        eprintln!("skipped: no wgpu adapter for snapshots");
        return None;
    }
    let studio = Studio::new(Document::with_scene(scene, None, None), None);
    Some(
        Harness::builder()
            .with_size(egui::vec2(1280.0, 800.0))
            .wgpu()
            .build_ui_state(|ui, studio: &mut Studio| studio.ui(ui), studio),
    )
}

/// The 3D view is drawn by the preview on its own device; a few pixels at triangle edges may
/// round differently on another CPU's software rasteriser.
fn tolerant() -> egui_kittest::SnapshotOptions {
    egui_kittest::SnapshotOptions::new().max_failed_pixels(40)
}

/// The main screen as a picture, rendered by wgpu on whatever adapter there is (Mesa's
/// lavapipe in CI). `UPDATE_SNAPSHOTS=true cargo test -p orbifold-studio` writes it again.
#[test]
fn the_default_room_matches_its_snapshot() {
    let Some(mut harness) = snapshot_harness(Scene::default()) else {
        return;
    };
    harness.run();
    harness.snapshot_options("studio-default-room", &tolerant());
}

/// The tiling tab of a hyperbolic orbifold.
#[test]
fn the_tiling_tab_matches_its_snapshot() {
    let mut scene = Scene::default();
    scene.orbifold.signature = "*2333".into();
    let Some(mut harness) = snapshot_harness(scene) else {
        return;
    };
    harness.get_by_label("tiling").click();
    harness.run();
    harness.snapshot_options("studio-tiling-2333", &tolerant());
}

#[test]
fn a_conway_symbol_typed_in_the_design_panel_builds_a_room_with_portals() {
    let mut harness = harness(Scene::default());
    let field = harness.get_by_role_and_label(Role::TextInput, "signature");
    field.focus();
    harness.run();
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::A);
    harness
        .get_by_role_and_label(Role::TextInput, "signature")
        .type_text("632");
    harness.run();
    harness.key_press(egui::Key::Enter);
    harness.run();
    let scene = harness.state().document.scene().clone();
    assert_eq!(scene.orbifold.signature, "632");
    let layout = scene.layout().unwrap();
    assert!(layout.edges.iter().all(|e| e.partner().is_some()));
    // The panel says what the room is made of, and the things stand inside it.
    assert!(
        harness
            .query_all_by_label_contains("4 portals and 0 mirrors")
            .next()
            .is_some()
    );
    // The room panel names each wall's partner.
    assert!(
        harness
            .query_all_by_label_contains("wall 0: portal to wall 3")
            .next()
            .is_some()
    );
    let inside = |at: [f64; 2]| {
        let p = layout
            .space()
            .to_ambient(num_complex::Complex64::new(at[0], at[1]));
        layout.edges.iter().all(|e| e.wall.dot(p) > 0.0)
    };
    assert!(scene.objects.iter().all(|o| inside(o.at)));
    assert!(inside(scene.camera.at) || inside(harness.state().view.camera.at));
    // The tiling tab draws the group's tiling.
    harness.get_by_label("tiling").click();
    harness.run();
    assert_eq!(harness.state().tab, Tab::Tiling);
}
