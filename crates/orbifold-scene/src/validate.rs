//! Semantic checks of a scene: ranges, references, and the orbifold itself.

use std::path::Path;

use num_complex::Complex64;
use orbifold::layout::Layout;

use crate::document::{Color, LightKind, Material, Scene};
use crate::sound::Sound;

/// The built-in object shapes.
pub const SHAPES: [&str; 9] = [
    "sphere", "torus", "cube", "figure", "letter-p", "letter-q", "letter-b", "letter-d", "letter-f",
];

/// Problems, each as (key, message).
type Problems = Vec<(String, String)>;

/// Every problem with `scene`; `base` resolves relative file names.
pub(crate) fn validate(scene: &Scene, base: Option<&Path>) -> Problems {
    let mut p = Problems::new();
    let layout = match scene.layout() {
        Ok(layout) => Some(layout),
        Err(message) => {
            let key = if scene.orbifold.parameters.is_empty() {
                "orbifold.signature"
            } else {
                "orbifold.parameters"
            };
            p.push((key.into(), message));
            None
        }
    };
    finite(&mut p, "orbifold.at", &scene.orbifold.at);
    finite(&mut p, "orbifold.angle", &[scene.orbifold.angle]);
    let room = &scene.room;
    let mut height = room.height;
    if !(height.is_finite() && height > 0.0) {
        p.push((
            "room.height".into(),
            format!("the room's height must be a positive number, not {height}"),
        ));
        // Heights of things in the room cannot be checked against it.
        height = f64::INFINITY;
    }
    unit_color(&mut p, "room.reflectance", &room.reflectance);
    room_material(&mut p, "room.wall_material", &room.wall_material, base);
    room_material(&mut p, "room.floor", &room.floor, base);
    room_material(&mut p, "room.ceiling", &room.ceiling, base);
    positive(&mut p, "room.resolution", room.resolution);
    if let Some(d) = room.cusp_distance {
        positive(&mut p, "room.cusp_distance", d);
    }
    if !(room.portal_frame.is_finite() && room.portal_frame >= 0.0) {
        p.push((
            "room.portal_frame".into(),
            format!(
                "the portals' frame must be a width of 0 or more, not {}",
                room.portal_frame
            ),
        ));
    }
    unit_color(
        &mut p,
        "room.portal_transmittance",
        &room.portal_transmittance,
    );
    walls(&mut p, scene, layout.as_ref(), base);
    let inside = |at: [f64; 2]| {
        layout
            .as_ref()
            .is_none_or(|l| crate::placement::is_inside(l, at))
    };
    for (i, o) in scene.objects.iter().enumerate() {
        let key = format!("objects[{i}]");
        match &o.mesh {
            Some(mesh) => file_exists(&mut p, &format!("{key}.mesh"), mesh, base),
            None if !SHAPES.contains(&o.shape.as_str()) => p.push((
                format!("{key}.shape"),
                format!(
                    "unknown shape {:?}; the built-in shapes are {}",
                    o.shape,
                    SHAPES.join(", ")
                ),
            )),
            None => {}
        }
        position(&mut p, &format!("{key}.at"), o.at, &inside);
        range(
            &mut p,
            &format!("{key}.height"),
            o.height,
            0.0,
            height,
            "between the floor and the ceiling",
        );
        finite(&mut p, &format!("{key}.yaw"), &[o.yaw]);
        positive(&mut p, &format!("{key}.size"), o.size);
        range(
            &mut p,
            &format!("{key}.crease"),
            o.crease,
            0.0,
            180.0,
            "an angle in degrees from 0 (flat faces) to 180",
        );
        material(&mut p, &format!("{key}.material"), &o.material, base);
    }
    for (i, l) in scene.lights.iter().enumerate() {
        let key = format!("lights[{i}]");
        position(&mut p, &format!("{key}.at"), l.at, &inside);
        range(
            &mut p,
            &format!("{key}.height"),
            l.height,
            0.0,
            height,
            "between the floor and the ceiling",
        );
        if !l.color.iter().all(|c| c.is_finite() && *c >= 0.0) {
            p.push((
                format!("{key}.color"),
                "colour channels must be non-negative numbers".into(),
            ));
        }
        if !(l.power.is_finite() && l.power >= 0.0) {
            p.push((
                format!("{key}.power"),
                format!("power must be a non-negative number, not {}", l.power),
            ));
        }
        finite(&mut p, &format!("{key}.yaw"), &[l.yaw]);
        range(
            &mut p,
            &format!("{key}.pitch"),
            l.pitch,
            -90.0,
            90.0,
            "in degrees, from −90 to 90",
        );
        range(
            &mut p,
            &format!("{key}.cone"),
            l.cone,
            0.0,
            90.0,
            "a half-angle in degrees, from 0 to 90",
        );
        positive(&mut p, &format!("{key}.radius"), l.radius);
        for (j, s) in l.size.iter().enumerate() {
            positive(&mut p, &format!("{key}.size[{j}]"), *s);
        }
    }
    let c = &scene.camera;
    position(&mut p, "camera.at", c.at, &inside);
    if let Some(layout) = &layout {
        camera_outside_lights(&mut p, scene, layout);
    }
    range(
        &mut p,
        "camera.height",
        c.height,
        0.0,
        height,
        "between the floor and the ceiling",
    );
    finite(&mut p, "camera.yaw", &[c.yaw]);
    range(
        &mut p,
        "camera.pitch",
        c.pitch,
        -90.0,
        90.0,
        "in degrees, from −90 to 90",
    );
    if !(c.fov.is_finite() && c.fov > 0.0 && c.fov < 180.0) {
        p.push((
            "camera.fov".into(),
            format!(
                "the field of view must be between 0 and 180 degrees, not {}",
                c.fov
            ),
        ));
    }
    if scene.preview.depth > 64 {
        p.push((
            "preview.depth".into(),
            format!("must be at most 64, not {}", scene.preview.depth),
        ));
    }
    sound(&mut p, &scene.sound, height, &inside);
    let r = &scene.render;
    for (key, value, max) in [
        ("render.width", r.width, 16384),
        ("render.height", r.height, 16384),
        ("render.samples", r.samples, 1 << 20),
        ("render.max_depth", r.max_depth, 100_000),
    ] {
        if value == 0 || value > max {
            p.push((
                key.into(),
                format!("must be between 1 and {max}, not {value}"),
            ));
        }
    }
    p
}

/// The `[sound]` table: positive scales, a sample rate that audio files can hold, a level below
/// the direct sound, places inside the room and absorption coefficients in [0, 1].
fn sound(p: &mut Problems, s: &Sound, height: f64, inside: &dyn Fn([f64; 2]) -> bool) {
    positive(p, "sound.metres_per_unit", s.metres_per_unit);
    positive(p, "sound.speed", s.speed);
    range(
        p,
        "sound.seconds",
        s.seconds,
        1e-3,
        60.0,
        "the response's length in seconds",
    );
    if !(8_000..=384_000).contains(&s.sample_rate) {
        p.push((
            "sound.sample_rate".into(),
            format!(
                "must be between 8000 and 384000 samples per second, not {}",
                s.sample_rate
            ),
        ));
    }
    range(
        p,
        "sound.min_level",
        s.min_level,
        -200.0,
        -1.0,
        "decibels below the direct sound at one metre",
    );
    positive(p, "sound.listener_size", s.listener_size);
    positive(p, "sound.ear_distance", s.ear_distance);
    for (key, place) in [("sound.source", s.source), ("sound.listener", s.listener)] {
        if let Some(place) = place {
            position(p, &format!("{key}.at"), place.at, inside);
            range(
                p,
                &format!("{key}.height"),
                place.height,
                0.0,
                height,
                "between the floor and the ceiling",
            );
        }
    }
    for (key, a) in [
        ("sound.mirror_absorption", s.mirror_absorption),
        ("sound.wall_absorption", s.wall_absorption),
        ("sound.floor_absorption", s.floor_absorption),
        ("sound.ceiling_absorption", s.ceiling_absorption),
    ] {
        if !a
            .bands()
            .iter()
            .all(|&x| x.is_finite() && (0.0..=1.0).contains(&x))
        {
            p.push((
                key.into(),
                "absorption coefficients must be between 0 and 1".into(),
            ));
        }
    }
}

fn walls(p: &mut Problems, scene: &Scene, layout: Option<&Layout>, base: Option<&Path>) {
    let count = layout.map(|l| l.edges.len());
    let mut seen = std::collections::HashSet::new();
    for (i, w) in scene.walls.iter().enumerate() {
        let key = format!("walls[{i}]");
        if let Some(n) = count
            && w.index >= n
        {
            p.push((
                format!("{key}.index"),
                format!(
                    "wall {} does not exist: the room has walls 0 to {}",
                    w.index,
                    n - 1
                ),
            ));
        }
        if !seen.insert(w.index) {
            p.push((
                format!("{key}.index"),
                format!("wall {} is described twice", w.index),
            ));
        }
        if let Some(m) = &w.material {
            room_material(p, &format!("{key}.material"), m, base);
        }
        for (j, m) in w.mirrors.iter().enumerate() {
            let key = format!("{key}.mirrors[{j}]");
            if !(m.from.is_finite()
                && m.to.is_finite()
                && 0.0 <= m.from
                && m.from < m.to
                && m.to <= 1.0)
            {
                p.push((
                    format!("{key}.from"),
                    format!("a mirror spans a part of its wall, from ≥ 0 to ≤ 1 with from < to, not {} to {}", m.from, m.to),
                ));
            }
            let room_height = if scene.room.height > 0.0 {
                scene.room.height
            } else {
                f64::INFINITY
            };
            let top = m.top.unwrap_or(room_height);
            if !(m.bottom.is_finite() && 0.0 <= m.bottom && m.bottom < top && top <= room_height) {
                p.push((
                    format!("{key}.bottom"),
                    format!(
                        "a mirror's height runs from bottom ≥ 0 to top ≤ the room's height {} with bottom < top, not {} to {}",
                        scene.room.height, m.bottom, top
                    ),
                ));
            }
            unit_color(p, &format!("{key}.reflectance"), &m.reflectance);
        }
    }
}

/// A camera inside a sphere light sees only the light's inner side: a white picture, or a
/// puzzling one. The distance is the product space's, √(d² + Δh²), with d the intrinsic
/// distance in the plane.
fn camera_outside_lights(p: &mut Problems, scene: &Scene, layout: &Layout) {
    let c = &scene.camera;
    let space = layout.space();
    let z = |at: [f64; 2]| Complex64::new(at[0], at[1]);
    for (i, l) in scene.lights.iter().enumerate() {
        if l.kind != LightKind::Sphere {
            continue;
        }
        let across = space.distance(z(c.at), z(l.at));
        let distance = across.hypot(c.height - l.height);
        if distance < l.radius {
            p.push((
                "camera.at".into(),
                format!(
                    "the camera is inside lights[{i}], a sphere of radius {} around ({}, {}) at \
                     height {} ({distance:.3} from its centre): move the camera or make the \
                     light smaller",
                    l.radius, l.at[0], l.at[1], l.height
                ),
            ));
        }
    }
}

fn position(p: &mut Problems, key: &str, at: [f64; 2], inside: &dyn Fn([f64; 2]) -> bool) {
    if !at.iter().all(|x| x.is_finite()) {
        p.push((key.into(), "coordinates must be finite numbers".into()));
    } else if !inside(at) {
        p.push((
            key.into(),
            format!("({}, {}) is not inside the room", at[0], at[1]),
        ));
    }
}

fn finite(p: &mut Problems, key: &str, values: &[f64]) {
    if !values.iter().all(|x| x.is_finite()) {
        p.push((key.into(), "must be a finite number".into()));
    }
}

fn positive(p: &mut Problems, key: &str, value: f64) {
    if !(value.is_finite() && value > 0.0) {
        p.push((
            key.into(),
            format!("must be a positive number, not {value}"),
        ));
    }
}

fn range(p: &mut Problems, key: &str, value: f64, low: f64, high: f64, what: &str) {
    if !(value.is_finite() && low <= value && value <= high) {
        p.push((
            key.into(),
            format!("{value} is out of range: {what} ({low} to {high})"),
        ));
    }
}

fn unit_color(p: &mut Problems, key: &str, color: &Color) {
    if !color
        .iter()
        .all(|c| c.is_finite() && (0.0..=1.0).contains(c))
    {
        p.push((
            key.into(),
            format!("every channel must be between 0 and 1, not {color:?}"),
        ));
    }
}

fn file_exists(p: &mut Problems, key: &str, name: &str, base: Option<&Path>) {
    let path = base.map_or_else(|| Path::new(name).to_path_buf(), |b| b.join(name));
    if !crate::files::exists(&path) {
        p.push((key.into(), crate::files::missing_message(&path)));
    }
}

/// A room surface is one side of the room's boundary: light cannot pass through it.
fn room_material(p: &mut Problems, key: &str, m: &Material, base: Option<&Path>) {
    if matches!(m, Material::Glass { .. }) {
        p.push((
            key.into(),
            "glass is for objects: a room's walls, floor and ceiling are opaque".into(),
        ));
    }
    material(p, key, m, base);
}

fn material(p: &mut Problems, key: &str, m: &Material, base: Option<&Path>) {
    match m {
        Material::Color { color } => unit_color(p, &format!("{key}.color"), color),
        Material::Checker { colors, size, .. } => {
            unit_color(p, &format!("{key}.colors[0]"), &colors[0]);
            unit_color(p, &format!("{key}.colors[1]"), &colors[1]);
            positive(p, &format!("{key}.size"), *size);
        }
        Material::Texture { path, scale, .. } => {
            file_exists(p, &format!("{key}.path"), path, base);
            positive(p, &format!("{key}.scale"), *scale);
        }
        Material::Glass { tint, ior } => {
            unit_color(p, &format!("{key}.tint"), tint);
            range(
                p,
                &format!("{key}.ior"),
                *ior,
                1.0,
                4.0,
                "index of refraction",
            );
        }
        Material::Metal { roughness, .. } => {
            range(
                p,
                &format!("{key}.roughness"),
                *roughness,
                0.0,
                1.0,
                "GGX α",
            );
        }
        Material::Plastic { color, roughness } => {
            unit_color(p, &format!("{key}.color"), color);
            range(
                p,
                &format!("{key}.roughness"),
                *roughness,
                0.0,
                1.0,
                "GGX α",
            );
        }
        Material::Marble {
            base: ground,
            vein,
            scale,
            ..
        } => {
            unit_color(p, &format!("{key}.base"), ground);
            unit_color(p, &format!("{key}.vein"), vein);
            positive(p, &format!("{key}.scale"), *scale);
        }
    }
}
