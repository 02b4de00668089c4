//! Files as the browser hands them over (a name and bytes), and the files the web studio hands
//! back as downloads or keeps in the browser's storage.
//!
//! A page has no disk: a mesh or an image dropped on it (or picked in the browser's file
//! picker) is given to [`orbifold_scene::files`] under its name, and the scene names it by that
//! name, so that the preview, the render and the exports read it as the desktop reads a file
//! beside the scene. Unsaved work is kept in `localStorage`: the scene's TOML under
//! [`RECOVERY_KEY`] and each given file it needs under [`FILE_KEY_PREFIX`] and its name, in
//! base64 ([`base64`], [`from_base64`]), as long as the browser's storage holds them.

use std::path::{Path, PathBuf};

use orbifold_scene::Scene;

/// The `localStorage` key under which unsaved work is kept.
pub const RECOVERY_KEY: &str = "orbifold-studio/recovery";

/// The `localStorage` keys of the given files that unsaved work needs: this, then the file's
/// name; the value is the file's bytes in base64.
pub const FILE_KEY_PREFIX: &str = "orbifold-studio/file/";

/// What a file given to the page (picked or dropped) is, by its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A scene (`.toml`): opened in place of the document.
    Scene,
    /// A mesh (`.obj`, `.ply`, `.gltf`, `.glb`).
    Mesh,
    /// A texture picture (`.png`, `.jpg`, `.jpeg`: what the renderer's texture reader decodes).
    Texture,
    /// A glTF file's external buffer (`.bin`), kept for the `.gltf` files that name it.
    Buffer,
    /// Anything else.
    Other,
}

/// The kind of a file by its extension, ignoring case.
///
/// ```
/// use orbifold_web::files::{Kind, kind};
/// assert_eq!(kind("room.TOML"), Kind::Scene);
/// assert_eq!(kind("bunny.obj"), Kind::Mesh);
/// assert_eq!(kind("wood.JPG"), Kind::Texture);
/// assert_eq!(kind("scene.bin"), Kind::Buffer);
/// assert_eq!(kind("notes.txt"), Kind::Other);
/// ```
pub fn kind(name: &str) -> Kind {
    let extension = name
        .rsplit_once('.')
        .map(|(_, e)| e.to_ascii_lowercase())
        .unwrap_or_default();
    match extension.as_str() {
        "toml" => Kind::Scene,
        "obj" | "ply" | "gltf" | "glb" => Kind::Mesh,
        "png" | "jpg" | "jpeg" => Kind::Texture,
        "bin" => Kind::Buffer,
        _ => Kind::Other,
    }
}

/// Reads a scene file's bytes, with every error at its line as `orbifold scene check` shows
/// them. The files it names need not have been given yet: they come back as a list, to be
/// asked for (a scene opened in the browser finds its meshes and images only once they are
/// dropped on the page).
///
/// ```
/// use std::path::PathBuf;
/// let text = "[[objects]]\nmesh = \"bunny.obj\"\n";
/// let (scene, missing) = orbifold_web::files::scene("room.toml", text.as_bytes()).unwrap();
/// assert_eq!(scene.objects[0].mesh.as_deref(), Some("bunny.obj"));
/// assert_eq!(missing, [PathBuf::from("bunny.obj")]);
/// ```
pub fn scene(name: &str, bytes: &[u8]) -> Result<(Scene, Vec<PathBuf>), String> {
    let text = std::str::from_utf8(bytes).map_err(|e| format!("{name} is not UTF-8 text: {e}"))?;
    Scene::from_toml_missing_files(text, Some(Path::new(name))).map_err(|errors| {
        errors
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("\n")
    })
}

/// Reads unsaved work kept in `localStorage` (the text of its scene): the scene, and the files
/// it names that have not been given. A recovered document has no file of its own, so the
/// names are taken as they are written.
///
/// ```
/// use orbifold_scene::Scene;
/// let (scene, missing) = orbifold_web::files::recovered(&Scene::default().to_toml()).unwrap();
/// assert_eq!(scene, Scene::default());
/// assert!(missing.is_empty());
/// assert!(orbifold_web::files::recovered("[room]\nheight = -1\n").is_err());
/// ```
pub fn recovered(text: &str) -> Result<(Scene, Vec<PathBuf>), String> {
    Scene::from_toml_missing_files(text, None).map_err(|errors| {
        errors
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("\n")
    })
}

/// Why the web studio does not take a file, or `None` for the kinds it takes: scenes, meshes,
/// glTF buffers and images.
///
/// ```
/// use orbifold_web::files::refusal;
/// assert_eq!(refusal("bunny.ply"), None);
/// assert!(refusal("notes.txt").unwrap().contains("notes.txt"));
/// ```
pub fn refusal(name: &str) -> Option<String> {
    match kind(name) {
        Kind::Scene | Kind::Mesh | Kind::Texture | Kind::Buffer => None,
        Kind::Other => Some(format!(
            "cannot take {name}: drop a scene (.toml), a mesh (.obj, .ply, .gltf, .glb, with a \
             glTF file's .bin buffers) or an image (.png, .jpg)"
        )),
    }
}

/// A list of names for a message: "a", "a and b", "a, b and c".
///
/// ```
/// use std::path::PathBuf;
/// use orbifold_web::files::listed;
/// let names = [PathBuf::from("a.obj"), PathBuf::from("b.png"), PathBuf::from("c.bin")];
/// assert_eq!(listed(&names[..1]), "a.obj");
/// assert_eq!(listed(&names), "a.obj, b.png and c.bin");
/// ```
pub fn listed(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    match names.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}

/// The given files ([`orbifold_scene::files`]) that `scene`, kept with `base` as its folder,
/// needs to be restored: the files it names that were given, and every given glTF buffer
/// (`.bin`: the `.gltf` files name them, not the scene).
///
/// ```
/// use std::path::{Path, PathBuf};
/// use orbifold_scene::{Scene, files};
/// files::provide("needed-example.obj", b"v 0 0 0".to_vec());
/// let mut scene = Scene::default();
/// assert!(!orbifold_web::files::needed(&scene, None).contains(&PathBuf::from("needed-example.obj")));
/// scene.objects[0].mesh = Some("needed-example.obj".into());
/// assert!(orbifold_web::files::needed(&scene, None).contains(&PathBuf::from("needed-example.obj")));
/// files::forget(Path::new("needed-example.obj"));
/// ```
pub fn needed(scene: &Scene, base: Option<&Path>) -> Vec<PathBuf> {
    let given = orbifold_scene::files::provided_paths();
    let named = scene
        .named_files()
        .into_iter()
        .map(|name| base.map_or_else(|| PathBuf::from(&name), |b| b.join(&name)));
    let mut needed: Vec<PathBuf> = named
        .filter(|path| orbifold_scene::files::provided(path).is_some())
        .collect();
    for path in given {
        if kind(&path.to_string_lossy()) == Kind::Buffer && !needed.contains(&path) {
            needed.push(path);
        }
    }
    needed
}

/// `bytes` in standard base64, padded: how a file is kept in `localStorage`, which holds text.
///
/// ```
/// assert_eq!(orbifold_web::files::base64(b"orbifold"), "b3JiaWZvbGQ=");
/// ```
pub fn base64(bytes: &[u8]) -> String {
    orbifold_scene::base64::encode(bytes)
}

/// The bytes of standard base64 `text` (padding optional), or `None` when it is not base64.
///
/// ```
/// use orbifold_web::files::{base64, from_base64};
/// assert_eq!(from_base64("b3JiaWZvbGQ=").unwrap(), b"orbifold");
/// assert_eq!(from_base64(&base64(&[0, 255, 7])).unwrap(), [0, 255, 7]);
/// assert_eq!(from_base64("not base64!"), None);
/// ```
pub fn from_base64(text: &str) -> Option<Vec<u8>> {
    // A single character left over is no whole byte: text that was not written as base64.
    if text.trim_end_matches('=').len() % 4 == 1 {
        return None;
    }
    orbifold_scene::base64::decode(text.trim_end_matches('=').as_bytes())
}

/// A rendered picture (RGBA8, as the render job shows it) as PNG bytes, for a download.
pub fn png(width: u32, height: u32, rgba: Vec<u8>) -> Result<Vec<u8>, String> {
    let image = image::RgbaImage::from_raw(width, height, rgba)
        .ok_or_else(|| format!("the picture is not {width}×{height} RGBA"))?;
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(|e| e.to_string())?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_reads_from_its_bytes_and_a_bad_one_says_where() {
        let text = include_str!("../../../examples/scenes/fig-1.2-333.toml");
        let (scene, missing) = scene("fig-1.2-333.toml", text.as_bytes()).unwrap();
        assert!(missing.is_empty());
        assert_eq!(scene.orbifold.signature, "*333");
        let error = scene_error("room.toml", b"[orbifold]\nsignature = 3\n");
        // The file, line and column of the wrong value.
        assert!(error.starts_with("room.toml:2:13:"), "{error}");
        assert!(scene_error("room.toml", &[0xff, 0xfe]).contains("UTF-8"));
    }

    fn scene_error(name: &str, bytes: &[u8]) -> String {
        scene(name, bytes).expect_err("the scene is wrong")
    }

    #[test]
    fn the_saved_scene_reads_back() {
        let mut original = Scene::default();
        original.room.height = 1.75;
        let (again, _) = scene("room.toml", original.to_toml().as_bytes()).unwrap();
        assert_eq!(again, original);
    }

    #[test]
    fn scenes_meshes_images_and_buffers_are_taken_and_other_files_refused() {
        for name in [
            "a.toml",
            "bunny.PLY",
            "b.obj",
            "c.gltf",
            "d.glb",
            "wood.jpg",
            "e.png",
            "f.bin",
        ] {
            assert_eq!(refusal(name), None, "{name}");
        }
        for name in ["README", "sky.exr", "notes.txt"] {
            let reason = refusal(name).unwrap();
            assert!(reason.contains(name) && reason.contains(".obj"), "{reason}");
        }
    }

    #[test]
    fn a_scene_that_names_files_not_given_opens_and_lists_them() {
        orbifold_scene::files::provide("web-unit/given.obj", b"v 0 0 0".to_vec());
        let mut original = Scene::default();
        original.objects[0].mesh = Some("given.obj".into());
        original.room.floor = orbifold_scene::Material::Texture {
            path: "gone.png".into(),
            scale: 0.5,
            coordinates: Default::default(),
        };
        let text = original.to_toml();
        let (again, missing) = scene("web-unit/room.toml", text.as_bytes()).unwrap();
        assert_eq!(again, original);
        assert_eq!(missing, [PathBuf::from("web-unit/gone.png")]);
        let needed = needed(&again, Some(Path::new("web-unit")));
        assert!(needed.contains(&PathBuf::from("web-unit/given.obj")));
        assert!(!needed.contains(&PathBuf::from("web-unit/gone.png")));
        orbifold_scene::files::forget(Path::new("web-unit/given.obj"));
    }

    #[test]
    fn base64_round_trips_every_length_and_refuses_other_text() {
        let bytes: Vec<u8> = (0..=255).rev().collect();
        for n in 0..40 {
            let text = base64(&bytes[..n]);
            assert_eq!(text.len() % 4, 0);
            assert_eq!(from_base64(&text).unwrap(), &bytes[..n], "{n} bytes");
        }
        assert_eq!(base64(b"Ma"), "TWE=");
        assert_eq!(base64(b"M"), "TQ==");
        assert_eq!(from_base64("TQ").unwrap(), b"M");
        assert_eq!(from_base64("T"), None);
        assert_eq!(from_base64("TW-="), None);
    }

    #[test]
    fn a_picture_becomes_a_png_of_its_size() {
        let rgba: Vec<u8> = (0..4 * 3 * 2).map(|i| i as u8).collect();
        let bytes = png(3, 2, rgba.clone()).unwrap();
        let back = image::load_from_memory(&bytes).unwrap().to_rgba8();
        assert_eq!((back.width(), back.height()), (3, 2));
        assert_eq!(back.into_raw(), rgba);
        assert!(png(3, 3, vec![0; 8]).is_err());
    }
}
