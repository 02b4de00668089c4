//! Documents: atomic save and reopen, the recovery copy of unsaved work, recent files.

use orbifold_scene::Scene;
use orbifold_studio::document::{self, Document};

/// A fresh, empty folder for a test's files, removed when the test ends (also when it fails).
fn folder(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("orbifold-studio-{name}-"))
        .tempdir()
        .unwrap()
}

#[test]
fn unsaved_work_is_kept_for_recovery_until_it_is_saved() {
    let tmp = folder("recovery");
    let dir = tmp.path();
    let recovery = dir.join("recovery.toml");
    let mut doc = Document::new(Some(recovery.clone()));
    doc.write_recovery().unwrap();
    assert!(
        !recovery.exists(),
        "nothing to recover from an unchanged document"
    );
    doc.edit(|scene| {
        scene.orbifold.signature = "*2333".into();
        scene.room.height = 1.7;
    });
    doc.write_recovery().unwrap();
    // A crash here: the next start finds the work.
    let recovered = document::recovered(&recovery).expect("a recovery copy");
    assert_eq!(&recovered, doc.scene());
    // Saving removes it.
    doc.save_as(&dir.join("room.toml")).unwrap();
    assert!(!recovery.exists());
    assert!(!doc.is_dirty());
    let reopened = Document::open(&dir.join("room.toml"), None).unwrap();
    assert_eq!(reopened.scene(), doc.scene());
}

#[test]
fn saving_without_a_file_asks_for_one_and_a_bad_folder_is_an_error() {
    let mut doc = Document::new(None);
    assert!(doc.save().unwrap_err().contains("Save As"));
    let error = doc
        .save_as(std::path::Path::new("/nonexistent/folder/room.toml"))
        .unwrap_err();
    assert!(error.contains("/nonexistent/folder/room.toml"), "{error}");
    assert_eq!(doc.path(), None);
}

#[test]
fn a_broken_scene_file_is_refused_with_its_line() {
    let tmp = folder("broken");
    let dir = tmp.path();
    let path = dir.join("broken.toml");
    std::fs::write(&path, "[room]\nheight = -1\n").unwrap();
    let error = Document::open(&path, None).unwrap_err();
    assert!(error.contains("height"), "{error}");
}

#[test]
fn recent_files_are_newest_first_without_repeats() {
    let tmp = folder("recent");
    let dir = tmp.path();
    let files: Vec<_> = (0..12).map(|k| dir.join(format!("{k}.toml"))).collect();
    for f in &files {
        Scene::default().save(f).unwrap();
        document::remember(dir, f).unwrap();
    }
    document::remember(dir, &files[3]).unwrap();
    let recent = document::recent_files(dir);
    assert_eq!(recent.len(), document::RECENT);
    assert_eq!(recent[0], files[3].canonicalize().unwrap());
    assert_eq!(recent[1], files[11].canonicalize().unwrap());
    let mut unique = recent.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), recent.len());
}
