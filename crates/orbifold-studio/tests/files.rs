//! Files in and out of the studio, driven through its real widgets (egui_kittest): the file
//! dialogs (answered by a scripted fake of `FileDialogs`), files dropped on the window, the
//! examples browser, and the materials of the room panel.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use orbifold_scene::{Material, MetalName, Scene};
use orbifold_studio::Studio;
use orbifold_studio::dialogs::{FileDialogs, Request};
use orbifold_studio::document::Document;
use orbifold_studio::room_panel::Target;

/// What the fake was asked, in order, with the suggested name of save dialogs.
type Asked = Rc<RefCell<Vec<(Request, Option<PathBuf>)>>>;

/// File dialogs that answer from a script: each question takes the next answer (`None` is the
/// user cancelling), and every question is recorded.
struct Scripted {
    answers: VecDeque<Option<PathBuf>>,
    asked: Asked,
    /// Whether they say they hand saved files over themselves, as the browser's downloads do.
    hands_over: bool,
}

impl Scripted {
    fn answer(&mut self, request: Request, suggested: Option<&Path>) -> Option<PathBuf> {
        self.asked
            .borrow_mut()
            .push((request, suggested.map(Path::to_path_buf)));
        self.answers.pop_front().flatten()
    }
}

impl FileDialogs for Scripted {
    fn open_scene(&mut self) -> Option<PathBuf> {
        self.answer(Request::OpenScene, None)
    }
    fn save_scene(&mut self, suggested: &Path) -> Option<PathBuf> {
        self.answer(Request::SaveScene, Some(suggested))
    }
    fn save_picture(&mut self, suggested: &Path) -> Option<PathBuf> {
        self.answer(Request::SavePicture, Some(suggested))
    }
    fn pick_mesh(&mut self) -> Option<PathBuf> {
        self.answer(Request::PickMesh, None)
    }
    fn pick_texture(&mut self) -> Option<PathBuf> {
        self.answer(Request::PickTexture, None)
    }
    fn hands_files_over(&self) -> bool {
        self.hands_over
    }
}

/// A studio on `scene` whose dialogs answer `answers` in turn.
fn harness(scene: Scene, answers: Vec<Option<PathBuf>>) -> (Harness<'static, Studio>, Asked) {
    harness_on(Document::with_scene(scene, None, None), answers, false)
}

/// A studio on `document` whose dialogs answer `answers` in turn and, with `hands_over`, say
/// that they hand saved files over themselves.
fn harness_on(
    document: Document,
    answers: Vec<Option<PathBuf>>,
    hands_over: bool,
) -> (Harness<'static, Studio>, Asked) {
    let asked = Asked::default();
    let mut studio = Studio::new(document, None);
    studio.dialogs = Some(Box::new(Scripted {
        answers: answers.into(),
        asked: asked.clone(),
        hands_over,
    }));
    let harness = Harness::builder()
        .with_size(egui::vec2(1440.0, 1600.0))
        .build_ui_state(|ui, studio: &mut Studio| studio.ui(ui), studio);
    (harness, asked)
}

fn folder(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("orbifold-studio-files-{name}-"))
        .tempdir()
        .unwrap()
}

const TETRAHEDRON: &str =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// A 2×2 PNG.
fn write_png(path: &Path) {
    image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 120, 40, 255]))
        .save(path)
        .unwrap();
}

fn click_menu(harness: &mut Harness<'static, Studio>, item: &str) {
    harness.get_by_label("File").click();
    harness.run();
    harness.get_by_label(item).click();
    harness.run();
}

/// A file dropped on the window, as the native backend hands it over.
#[derive(Debug)]
struct DroppedPath(PathBuf);

impl egui::DroppedFile for DroppedPath {
    fn path(&self) -> &Path {
        &self.0
    }
    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

fn drop_file(harness: &mut Harness<'static, Studio>, path: &Path) {
    harness
        .input_mut()
        .dropped_files
        .push(std::sync::Arc::new(DroppedPath(path.to_path_buf())));
    harness.run();
}

#[test]
fn open_and_save_as_go_through_the_file_dialogs() {
    let tmp = folder("save");
    let saved = tmp.path().join("mine.toml");
    let mut other = Scene::default();
    other.orbifold.signature = "*333".into();
    let existing = tmp.path().join("other.toml");
    other.save(&existing).unwrap();
    let (mut harness, asked) = harness(
        Scene::default(),
        vec![None, Some(saved.clone()), Some(existing.clone())],
    );
    // Ctrl+S on a new document asks where; cancelling saves nothing.
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    harness.run();
    assert_eq!(harness.state().document.path(), None);
    assert!(!saved.exists());
    // Save As: the dialog's answer becomes the document's file.
    click_menu(&mut harness, "Save As…");
    assert_eq!(harness.state().document.path(), Some(saved.as_path()));
    assert_eq!(Scene::load(&saved).unwrap(), Scene::default());
    // Open: the chosen file replaces the document.
    click_menu(&mut harness, "Open…");
    assert_eq!(harness.state().document.path(), Some(existing.as_path()));
    assert_eq!(harness.state().document.scene().orbifold.signature, "*333");
    let asked = asked.borrow();
    let requests: Vec<Request> = asked.iter().map(|(r, _)| *r).collect();
    assert_eq!(
        requests,
        [Request::SaveScene, Request::SaveScene, Request::OpenScene]
    );
    assert_eq!(asked[0].1.as_deref(), Some(Path::new("room.toml")));
}

#[test]
fn the_render_tab_s_picture_is_saved_as_png_or_exr_through_the_dialog() {
    let tmp = folder("picture");
    let png = tmp.path().join("picture.png");
    let exr = tmp.path().join("picture.exr");
    let (mut harness, asked) =
        harness(Scene::default(), vec![Some(png.clone()), Some(exr.clone())]);
    harness.get_by_label("render").click();
    harness.run();
    harness.get_by_label("frame as the 3D view").click();
    harness.run();
    for (name, value) in [
        ("render width", 24.0),
        ("render height", 16.0),
        ("render samples", 1.0),
    ] {
        harness
            .get_by_role_and_label(Role::SpinButton, name)
            .set_value_accesskit(value);
        harness.run();
    }
    harness.get_by_label("Render").click();
    harness.run();
    // Until the render is done (its Render button is back), so that the buttons stay put.
    for _ in 0..600 {
        if harness.query_by_label_contains("1 / 1 samples").is_some()
            && harness.query_by_label("Render").is_some()
        {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
        harness.run_steps(1);
    }
    for _ in 0..2 {
        harness.get_by_label("Save picture…").click_accesskit();
        harness.run();
    }
    assert!(png.is_file(), "{}", harness.state().status);
    assert_eq!(image::open(&png).unwrap().width(), 24);
    // OpenEXR's magic number: the HDR image, not a PNG under another name.
    let hdr = std::fs::read(&exr).unwrap();
    assert_eq!(hdr[..4], [0x76, 0x2f, 0x31, 0x01]);
    assert_eq!(
        asked.borrow()[0],
        (Request::SavePicture, Some("render.png".into()))
    );
}

#[test]
fn picked_meshes_become_objects_and_picked_images_go_on_their_surface() {
    let tmp = folder("pick");
    let mesh = tmp.path().join("tetrahedron.obj");
    std::fs::write(&mesh, TETRAHEDRON).unwrap();
    let png = tmp.path().join("wood.png");
    write_png(&png);
    let (mut harness, asked) = harness(
        Scene::default(),
        vec![Some(mesh.clone()), None, Some(png.clone())],
    );
    harness.get_by_label("pick mesh…").click();
    harness.run();
    let scene = harness.state().document.scene().clone();
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.objects[1].mesh.as_deref(), mesh.to_str());
    assert_eq!(harness.state().view.error, None);
    // The ceiling as an image: its pick button asks; cancelling changes nothing, then a file.
    harness.get_by_label("ceiling: image").click();
    harness.run();
    let before = harness.state().document.scene().clone();
    harness.get_by_label("pick ceiling image…").click();
    harness.run();
    assert_eq!(harness.state().document.scene(), &before);
    harness.get_by_label("pick ceiling image…").click();
    harness.run();
    match &harness.state().document.scene().room.ceiling {
        Material::Texture { path, .. } => assert_eq!(Path::new(path), png),
        other => panic!("the ceiling is {other:?}"),
    }
    assert!(harness.state().document.scene().check(None).is_ok());
    assert_eq!(asked.borrow().len(), 3);
}

#[test]
fn dropped_files_open_add_or_paint() {
    let tmp = folder("drop");
    let mesh = tmp.path().join("tetrahedron.obj");
    std::fs::write(&mesh, TETRAHEDRON).unwrap();
    let png = tmp.path().join("stone.png");
    write_png(&png);
    let mut saved = Scene::default();
    saved.orbifold.signature = "*2333".into();
    let scene_file = tmp.path().join("dropped.toml");
    saved.save(&scene_file).unwrap();
    let (mut harness, asked) = harness(Scene::default(), vec![]);
    // A scene opens.
    drop_file(&mut harness, &scene_file);
    assert_eq!(harness.state().document.path(), Some(scene_file.as_path()));
    assert_eq!(harness.state().document.scene().orbifold.signature, "*2333");
    // A mesh becomes an object; the scene's folder makes its name relative.
    drop_file(&mut harness, &mesh);
    let objects = &harness.state().document.scene().objects;
    assert_eq!(objects.len(), 2);
    assert_eq!(objects[1].mesh.as_deref(), Some("tetrahedron.obj"));
    // An image goes on the floor at first, then on the surface the panel names.
    drop_file(&mut harness, &png);
    assert!(matches!(
        &harness.state().document.scene().room.floor,
        Material::Texture { path, .. } if path == "stone.png"
    ));
    assert!(harness.query_by_label("dropped images go on").is_some());
    orbifold_studio::room_panel::set_texture_target(&harness.ctx, Target::Object(1));
    drop_file(&mut harness, &png);
    assert!(matches!(
        &harness.state().document.scene().objects[1].material,
        Material::Texture { path, .. } if path == "stone.png"
    ));
    assert!(
        harness
            .state()
            .document
            .scene()
            .check(Some(tmp.path()))
            .is_ok()
    );
    // Anything else is refused with a message, and nothing changes.
    let before = harness.state().document.scene().clone();
    drop_file(&mut harness, &tmp.path().join("notes.txt"));
    assert_eq!(harness.state().document.scene(), &before);
    assert!(harness.state().status.contains("notes.txt"));
    assert!(asked.borrow().is_empty(), "dropping asks nothing");
}

#[test]
fn an_example_opens_as_an_untitled_copy_and_saving_asks_where() {
    let tmp = folder("example");
    let copy = tmp.path().join("copy.toml");
    let (mut harness, asked) = harness(Scene::default(), vec![Some(copy.clone())]);
    // The browser repaints while thumbnails are being made: step instead of waiting to settle.
    harness.get_by_label("File").click();
    harness.run();
    harness.get_by_label("Examples…").click();
    harness.run_steps(2);
    assert!(harness.state().examples.open);
    // Every example is listed; the thumbnails come in the background, the first soon.
    let examples = orbifold_studio::examples_browser::examples();
    assert!(examples.len() >= 40, "{} examples", examples.len());
    for example in &examples {
        assert!(
            harness.query_all_by_label(example.name).next().is_some(),
            "{} is not listed",
            example.name
        );
    }
    for _ in 0..2400 {
        if harness.state().examples.has_thumbnail(0) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
        harness.run_steps(1);
    }
    assert!(harness.state().examples.has_thumbnail(0), "no thumbnail");
    harness.get_by_label("fig-1.2-444").click();
    harness.run_steps(2);
    let example = examples.iter().find(|e| e.name == "fig-1.2-444").unwrap();
    assert_eq!(harness.state().document.scene(), &example.scene().unwrap());
    assert_eq!(harness.state().document.path(), None, "an untitled copy");
    assert!(!harness.state().examples.open);
    // Saving asks where (never the example's own file).
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    harness.run();
    assert_eq!(asked.borrow()[0].0, Request::SaveScene);
    assert_eq!(harness.state().document.path(), Some(copy.as_path()));
    assert_eq!(Scene::load(&copy).unwrap(), example.scene().unwrap());
}

#[test]
fn marble_plastic_metal_and_glass_are_edited_in_the_room_panel() {
    let (mut harness, _) = harness(Scene::default(), vec![]);
    let set = |harness: &mut Harness<'static, Studio>, name: &str, value: f64| {
        harness
            .get_by_role_and_label(Role::SpinButton, name)
            .set_value_accesskit(value);
        harness.run();
    };
    // Colour, checker and image side by side; the others in the surface's menu.
    let choose = |harness: &mut Harness<'static, Studio>, menu: &str, kind: &str| {
        harness.get_by_label(menu).click();
        harness.run();
        harness.get_by_label(kind).click();
        harness.run();
    };
    choose(&mut harness, "floor: more…", "floor: marble");
    set(&mut harness, "floor marble size", 0.7);
    choose(&mut harness, "walls: more…", "walls: plastic");
    set(&mut harness, "walls roughness", 0.35);
    choose(&mut harness, "object 0: more…", "object 0: metal");
    harness
        .get_by_role_and_label(Role::ComboBox, "object 0 metal")
        .click();
    harness.run();
    harness.get_by_label("gold").click();
    harness.run();
    set(&mut harness, "object 0 roughness", 0.05);
    let scene = harness.state().document.scene().clone();
    assert!(matches!(scene.room.floor, Material::Marble { scale, .. } if scale == 0.7));
    assert!(
        matches!(scene.room.wall_material, Material::Plastic { roughness, .. } if roughness == 0.35)
    );
    assert_eq!(
        scene.objects[0].material,
        Material::Metal {
            metal: MetalName::Gold,
            roughness: 0.05
        }
    );
    // Glass is offered for objects only (a room's surfaces are opaque).
    harness.get_by_label("floor: marble…").click();
    harness.run();
    assert!(harness.query_by_label("floor: plastic").is_some());
    assert!(harness.query_by_label("floor: glass").is_none());
    harness.key_press(egui::Key::Escape);
    harness.run();
    choose(&mut harness, "object 0: metal…", "object 0: glass");
    set(&mut harness, "object 0 refractive index", 1.33);
    let scene = harness.state().document.scene().clone();
    assert!(matches!(scene.objects[0].material, Material::Glass { ior, .. } if ior == 1.33));
    assert!(scene.check(None).is_ok());
    // What the panel made reads back from the file.
    assert_eq!(Scene::from_toml(&scene.to_toml(), None).unwrap(), scene);
}

#[test]
fn a_signature_only_file_opens_with_the_camera_in_the_room() {
    let tmp = folder("minimal");
    let file = tmp.path().join("square.toml");
    std::fs::write(&file, "[orbifold]\nsignature = \"*444\"\n").unwrap();
    let document = Document::open(&file, None).unwrap();
    let layout = document.scene().layout().unwrap();
    assert!(orbifold_scene::placement::is_inside(
        &layout,
        document.scene().camera.at
    ));
    let (mut harness, _) = harness(Scene::default(), vec![Some(file.clone())]);
    click_menu(&mut harness, "Open…");
    assert_eq!(harness.state().document.path(), Some(file.as_path()));
    assert_eq!(harness.state().view.error, None);
}

#[test]
fn without_file_dialogs_a_picked_file_is_typed_in_the_studio_s_own_window() {
    let tmp = folder("typed");
    let mesh = tmp.path().join("tetrahedron.obj");
    std::fs::write(&mesh, TETRAHEDRON).unwrap();
    let png = tmp.path().join("wood.png");
    write_png(&png);
    let studio = Studio::new(Document::with_scene(Scene::default(), None, None), None);
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1440.0, 1600.0))
        .build_ui_state(|ui, studio: &mut Studio| studio.ui(ui), studio);
    let type_in = |harness: &mut Harness<'static, Studio>, path: &Path, action: &str| {
        harness
            .get_by_role_and_label(Role::TextInput, "file")
            .set_text_value_accesskit(path.to_str().unwrap());
        harness.run();
        harness.get_by_label(action).click();
        harness.run();
    };
    harness.get_by_label("pick mesh…").click();
    harness.run();
    type_in(&mut harness, &mesh, "Add mesh");
    assert_eq!(
        harness.state().document.scene().objects[1].mesh.as_deref(),
        mesh.to_str()
    );
    harness.get_by_label("floor: image").click();
    harness.run();
    harness.get_by_label("pick floor image…").click();
    harness.run();
    type_in(&mut harness, &png, "Use image");
    assert!(matches!(
        &harness.state().document.scene().room.floor,
        Material::Texture { path, .. } if Path::new(path) == png
    ));
}

#[test]
fn dialogs_that_answer_later_and_hand_files_over_as_a_browser_does() {
    let tmp = folder("later");
    let mesh = tmp.path().join("tetrahedron.obj");
    std::fs::write(&mesh, TETRAHEDRON).unwrap();
    let png = tmp.path().join("wood.png");
    write_png(&png);
    let file = tmp.path().join("room.toml");
    Scene::default().save(&file).unwrap();
    let document = Document::open(&file, None).unwrap();
    // Every dialog returns at once with nothing: the browser's picker answers later.
    let (mut harness, asked) = harness_on(document, vec![None; 4], true);
    // A file nobody asked for is not taken as an answer.
    assert!(!harness.state_mut().answer(Request::PickMesh, &mesh));
    harness.get_by_label("pick mesh…").click();
    harness.run();
    assert_eq!(harness.state().document.scene().objects.len(), 1);
    // The answer for another question is not taken either; the mesh's is, once.
    assert!(!harness.state_mut().answer(Request::PickTexture, &png));
    assert!(harness.state_mut().answer(Request::PickMesh, &mesh));
    assert!(!harness.state_mut().answer(Request::PickMesh, &mesh));
    harness.run();
    let scene = harness.state().document.scene().clone();
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.objects[1].mesh.as_deref(), Some("tetrahedron.obj"));
    // An image picked later goes on the surface whose button asked for it.
    harness.get_by_label("ceiling: image").click();
    harness.run();
    harness.get_by_label("pick ceiling image…").click();
    harness.run();
    assert!(harness.state_mut().answer(Request::PickTexture, &png));
    match &harness.state().document.scene().room.ceiling {
        Material::Texture { path, .. } => assert_eq!(path, "wood.png"),
        other => panic!("the ceiling is {other:?}"),
    }
    // Save, though the document has its file, asks the dialogs (a download), and the studio
    // writes nothing itself.
    let before = std::fs::read_to_string(&file).unwrap();
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    harness.run();
    assert_eq!(std::fs::read_to_string(&file).unwrap(), before);
    let requests: Vec<Request> = asked.borrow().iter().map(|(r, _)| *r).collect();
    assert_eq!(
        requests,
        [Request::PickMesh, Request::PickTexture, Request::SaveScene]
    );
    assert_eq!(asked.borrow()[2].1.as_deref(), Some(file.as_path()));
}
