//! Scene files: `Scene::from_toml` on arbitrary text never panics, and a scene it accepts
//! survives `to_toml` and a second `from_toml` unchanged (and its TOML is a fixed point).

#![no_main]

use libfuzzer_sys::fuzz_target;
use orbifold_scene::Scene;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let scene = match Scene::from_toml(text, None) {
        Ok(scene) => scene,
        Err(errors) => {
            assert!(!errors.is_empty(), "from_toml failed without saying why");
            for e in &errors {
                let _ = e.to_string();
            }
            return;
        }
    };
    let written = scene.to_toml();
    let again = Scene::from_toml(&written, None).unwrap_or_else(|errors| {
        let messages: Vec<String> = errors.iter().map(ToString::to_string).collect();
        panic!(
            "an accepted scene does not read back.\ninput:\n{text}\nwritten:\n{written}\nerrors: {messages:#?}"
        )
    });
    assert_eq!(
        again, scene,
        "the scene changes in a TOML round trip.\ninput:\n{text}\nwritten:\n{written}"
    );
    assert_eq!(again.to_toml(), written, "to_toml is not a fixed point");
});
