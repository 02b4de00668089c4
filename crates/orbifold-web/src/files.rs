//! Files as the browser hands them over (a name and bytes), and the files the web studio hands
//! back as downloads.

use orbifold_scene::Scene;

/// The `localStorage` key under which unsaved work is kept.
pub const RECOVERY_KEY: &str = "orbifold-studio/recovery";

/// What a file given to the page (picked or dropped) is, by its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A scene (`.toml`): opened in place of the document.
    Scene,
    /// A mesh (`.obj`, `.ply`, `.gltf`, `.glb`).
    Mesh,
    /// A texture picture (`.png`, `.jpg`, `.jpeg`, `.exr`, `.hdr`).
    Texture,
    /// Anything else.
    Other,
}

/// The kind of a file by its extension, ignoring case.
///
/// ```
/// use orbifold_web::files::{Kind, kind};
/// assert_eq!(kind("room.TOML"), Kind::Scene);
/// assert_eq!(kind("bunny.obj"), Kind::Mesh);
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
        "png" | "jpg" | "jpeg" | "exr" | "hdr" => Kind::Texture,
        _ => Kind::Other,
    }
}

/// Reads a scene file's bytes, with every error at its line as `orbifold scene check` shows
/// them.
pub fn scene(name: &str, bytes: &[u8]) -> Result<Scene, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| format!("{name} is not UTF-8 text: {e}"))?;
    Scene::from_toml(text, Some(std::path::Path::new(name))).map_err(|errors| {
        errors
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("\n")
    })
}

/// Why a file of this kind cannot be used by the web studio as it is, or `None` for a scene.
/// Meshes and textures are named by the scene and read from the disk beside it, which a page
/// cannot reach.
pub fn refusal(name: &str) -> Option<String> {
    match kind(name) {
        Kind::Scene => None,
        Kind::Mesh | Kind::Texture => Some(format!(
            "{name}: the web studio cannot use meshes or textures yet (a scene reads them from \
             the disk beside it); use the desktop studio or a built-in shape"
        )),
        Kind::Other => Some(format!("{name}: not a scene file (.toml)")),
    }
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
        let scene = scene("fig-1.2-333.toml", text.as_bytes()).unwrap();
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
        let again = scene("room.toml", original.to_toml().as_bytes()).unwrap();
        assert_eq!(again, original);
    }

    #[test]
    fn meshes_and_textures_are_refused_with_a_reason() {
        assert_eq!(refusal("a.toml"), None);
        assert!(refusal("bunny.PLY").unwrap().contains("meshes or textures"));
        assert!(refusal("wood.jpg").unwrap().contains("meshes or textures"));
        assert!(refusal("README").unwrap().contains("not a scene"));
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
