//! Embeds the example scenes of `examples/scenes/` for the studio's examples browser, so that
//! the browser works wherever the binary is (and in a build without a file system).

use std::path::PathBuf;

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let folder = manifest.join("../../examples/scenes");
    // Adding or removing a scene changes the folder; `include_str!` follows each file's text.
    println!("cargo:rerun-if-changed={}", folder.display());
    let mut names: Vec<PathBuf> = std::fs::read_dir(&folder)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    let mut code = String::from("/// The example scenes: (file name without `.toml`, text).\n");
    code.push_str("pub(crate) const EXAMPLES: &[(&str, &str)] = &[\n");
    for path in &names {
        let stem = path.file_stem().unwrap_or_default().to_string_lossy();
        let absolute = path.canonicalize().unwrap_or_else(|_| path.clone());
        code.push_str(&format!(
            "    ({stem:?}, include_str!({:?})),\n",
            absolute.display().to_string()
        ));
    }
    code.push_str("];\n");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("set by cargo"));
    std::fs::write(out.join("examples.rs"), code).expect("OUT_DIR is writable");
}
