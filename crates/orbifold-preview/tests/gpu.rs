//! The preview on a real (or software) GPU: the shader's projection against the CPU twin (and so
//! against the tracer), the image against the tracer's surface-id AOV, the copies drawn against
//! the growth series, and cheap updates against full rebuilds.
//!
//! These need a wgpu adapter. Mesa's lavapipe (Debian: mesa-vulkan-drivers) is one; CI installs
//! it and sets ORBIFOLD_REQUIRE_GPU=1, so that a missing adapter fails there instead of skipping.

use num_complex::Complex64;
use orbifold::embed::Placement;
use orbifold::growth::growth_series;
use orbifold::{Geometry, Signature};
use orbifold_preview::mesh;
use orbifold_preview::{Gpu, Preview, PreviewError, Projection, Settings};
use orbifold_scene::{Attenuation, Scene};
use orbifold_trace::aov;
use orbifold_trace::camera::Camera;
use orbifold_trace::tracer::Tracer;

fn gpu() -> Option<Gpu> {
    match Gpu::headless() {
        Ok(gpu) => Some(gpu),
        Err(e) if std::env::var_os("ORBIFOLD_REQUIRE_GPU").is_none() => {
            eprintln!("skipped: {e}");
            None
        }
        Err(e) => panic!("ORBIFOLD_REQUIRE_GPU is set but {e}"),
    }
}

/// The default room of a signature: a figure in the middle, the camera part of the way to the
/// first corner, looking at the figure a little from above.
fn scene(signature: &str, depth: u32) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    scene.preview.depth = depth;
    let layout = scene.layout().unwrap();
    let c = layout.centre;
    scene.objects.truncate(1);
    scene.objects[0].at = [c.re, c.im];
    let corner = layout.vertices[0].position;
    let eye = c + (corner - c) * 0.45;
    scene.camera.at = [eye.re, eye.im];
    let bearing = layout.space().direction(eye, c).arg().to_degrees();
    scene.camera.yaw = bearing + 15.0;
    scene.camera.pitch = -18.0;
    scene.camera.height = 0.6;
    scene
}

const SIGNATURES: [&str; 3] = ["*235", "*2222", "*22222"];

#[test]
fn the_shader_puts_every_vertex_where_the_cpu_projection_does() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    let (width, height) = (320, 240);
    for sig in SIGNATURES {
        let scene = scene(sig, 1);
        preview.load(&scene, None).unwrap();
        let layout = scene.layout().unwrap();
        let mesher = scene.room_mesher(&layout).unwrap();
        let (room, _) = mesh::room(
            &scene,
            &layout,
            &mesher,
            scene.objects.len() as u32,
            &mut Default::default(),
        );
        let view = preview.view().unwrap();
        let landed = preview.vertex_pixels(width, height).unwrap();
        assert!(
            landed.len() > 30,
            "{sig}: only {} vertices in view",
            landed.len()
        );
        let mut worst: f64 = 0.0;
        for &(v, x, y) in &landed {
            let vertex = room.vertices[v as usize];
            let p = glam::DVec3::from(vertex.position.map(f64::from));
            let at = (0..view.images())
                .filter_map(|image| view.project(p, vertex.height.into(), image, width, height))
                .map(|a| {
                    (a.x - f64::from(x) - 0.5)
                        .abs()
                        .max((a.y - f64::from(y) - 0.5).abs())
                })
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(at);
        }
        // Half a pixel, and a hair for the shader's single precision.
        assert!(
            worst <= 0.5 + 0.02,
            "{sig}: a vertex landed {worst} pixels from its projection"
        );
    }
}

#[test]
fn the_preview_sees_what_the_tracer_sees() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    let (width, height) = (160, 120);
    // Mirror rooms, and rooms with portals: cone points (632; 3*2 on the sphere; 4*3 in H²,
    // next to mirrors) and glides (22×), whose copies are the tiles of their groups.
    for sig in SIGNATURES.into_iter().chain(["632", "22×", "3*2", "4*3"]) {
        let depth = 5;
        let mut scene = scene(sig, depth);
        // Portals open to their edges: a frame's thin bands would put most pixels that differ
        // by rasterising their edges.
        scene.room.portal_frame = 0.0;
        preview.load(&scene, None).unwrap();
        // Every object at full detail: this test holds the projection to the tracer.
        let mut settings = preview.settings();
        settings.lod = false;
        preview.set_settings(settings).unwrap();
        let frame = preview.render(width, height).unwrap();
        let tracer = Tracer::from_scene(&scene, None).unwrap();
        let camera = Camera::new(tracer.space(), &scene.camera);
        // A ray that crosses n walls sees a copy of word length n (in S²×R the whole group is
        // drawn, and rays may go round).
        let bounces = if tracer.space().kappa() > 0.0 {
            60
        } else {
            depth as usize
        };
        let aovs = aov::render(&tracer, &camera, width, height, bounces);
        let same = frame
            .ids
            .iter()
            .zip(&aovs.surface)
            .filter(|(a, b)| a == b)
            .count();
        let share = same as f64 / frame.ids.len() as f64;
        if let Some(dir) = std::env::var_os("DEBUG_DIR") {
            let colour = |id: i32| -> [u8; 3] {
                match id {
                    -1 => [0, 0, 0],
                    0 => [200, 150, 100],
                    1 => [60, 60, 160],
                    1000 => [255, 255, 255],
                    w => [((w * 70) % 255) as u8, 200, ((w * 130) % 255) as u8],
                }
            };
            let mut img = image::RgbImage::new(width * 3, height);
            for k in 0..(width * height) as usize {
                let (x, y) = (k as u32 % width, k as u32 / width);
                img.put_pixel(x, y, image::Rgb(colour(frame.ids[k])));
                img.put_pixel(x + width, y, image::Rgb(colour(aovs.surface[k])));
                let d = if frame.ids[k] == aovs.surface[k] {
                    [0, 0, 0]
                } else {
                    [255, 0, 0]
                };
                img.put_pixel(x + 2 * width, y, image::Rgb(d));
            }
            img.save(std::path::Path::new(&dir).join(format!("{}.png", sig.replace('*', "s"))))
                .unwrap();
        }
        let seen: std::collections::BTreeSet<i32> = frame.ids.iter().copied().collect();
        assert!(
            seen.contains(&0) && seen.contains(&1000),
            "{sig}: sees {seen:?}"
        );
        eprintln!("{sig}: {:.2} % of pixels agree", 100.0 * share);
        assert!(
            share > 0.97,
            "{sig}: only {:.2} % of pixels agree",
            100.0 * share
        );
    }
}

#[test]
fn the_copies_drawn_are_the_tiles_up_to_the_depth() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    for (sig, depth) in [
        ("*2222", 6),
        ("*22222", 4),
        ("*237", 9),
        ("*235", 3),
        ("*∞∞∞", 5),
    ] {
        let scene = scene(sig, depth);
        preview.load(&scene, None).unwrap();
        let mut settings = preview.settings();
        settings.cull = false;
        settings.lod = false;
        preview.set_settings(settings).unwrap();
        preview.render(64, 48).unwrap();
        let stats = preview.stats();
        let signature: Signature = sig.parse().unwrap();
        let expected: u128 = if signature.geometry() == Geometry::Spherical {
            // Spherical groups are finite: all of them, whatever the depth.
            growth_series(&signature, 64).unwrap().iter().sum()
        } else {
            growth_series(&signature, depth as usize)
                .unwrap()
                .iter()
                .sum()
        };
        assert_eq!(stats.copies as u128, expected, "{sig}");
        let images = if signature.geometry() == Geometry::Spherical {
            // Two a turn round the sphere: the short and the long way.
            2 * settings.turns as usize
        } else {
            1
        };
        assert_eq!(preview.view().unwrap().images() as usize, images);
        assert_eq!(stats.instances, stats.copies * images, "{sig}");
        assert_eq!(stats.triangles, stats.instances * stats.triangles_per_copy);
        // Culling never drops the room itself, and keeps no more than there are.
        settings.cull = true;
        preview.set_settings(settings).unwrap();
        preview.render(64, 48).unwrap();
        assert!((1..=stats.instances).contains(&preview.stats().instances));
    }
}

#[test]
fn the_copies_of_a_room_with_portals_are_the_tiles_of_its_group() {
    // Cone points, a glide, a mirror boundary: the preview draws the group's tiles up to the
    // depth (all of a spherical group's), as the certified cover counts them.
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    for (symbol, depth) in [("632", 4), ("22×", 5), ("4*3", 3), ("332", 2), ("3*2", 2)] {
        let scene = scene(symbol, depth);
        preview.load(&scene, None).unwrap();
        let mut settings = preview.settings();
        settings.cull = false;
        settings.lod = false;
        preview.set_settings(settings).unwrap();
        preview.render(64, 48).unwrap();
        let parsed: orbifold::OrbifoldSymbol = symbol.parse().unwrap();
        let bound = if parsed.geometry() == Geometry::Spherical {
            orbifold::cover::Bound::All
        } else {
            orbifold::cover::Bound::Depth(depth as usize)
        };
        let cover = orbifold::pairing::cover::GroupCover::enumerate(&parsed, bound, false).unwrap();
        let expected: u64 = cover.counts_by_depth.iter().sum();
        assert_eq!(preview.stats().copies as u64, expected, "{symbol}");
        if let Some(order) = parsed.group_order() {
            assert_eq!(
                expected as u128, order,
                "{symbol}: the whole spherical group"
            );
        }
    }
}

/// The share of pixels whose surface ids agree.
fn agreement(a: &orbifold_preview::Frame, b: &orbifold_preview::Frame) -> f64 {
    let same = a.ids.iter().zip(&b.ids).filter(|(x, y)| x == y).count();
    same as f64 / a.ids.len() as f64
}

/// The colours-only frame (what the studio reads back) is the colour picture of the full frame.
#[test]
fn colours_alone_are_the_pictures_colours() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    for sig in SIGNATURES {
        preview.load(&scene(sig, 2), None).unwrap();
        let colours = preview.render_colors(120, 90).unwrap();
        let frame = preview.render(120, 90).unwrap();
        assert_eq!(colours.len(), 120 * 90 * 4, "{sig}");
        assert!(colours == frame.rgba, "{sig}: the colours differ");
    }
    assert!(matches!(
        preview.render_colors(0, 10),
        Err(PreviewError::Size(0, 10))
    ));
}

#[test]
fn cheap_updates_draw_what_a_fresh_load_draws() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu.clone());
    let mut fresh = Preview::new(gpu);
    let (w, h) = (160, 120);
    let mut scene = scene("*22222", 3);
    preview.load(&scene, None).unwrap();
    let before = preview.render(w, h).unwrap();

    // Move the figure: one entry of the part table.
    let object = &mut scene.objects[0];
    object.at = [object.at[0] + 0.08, object.at[1] + 0.05];
    object.yaw = 40.0;
    let placement = Placement {
        at: Complex64::new(object.at[0], object.at[1]),
        height: object.height,
        yaw: object.yaw.to_radians(),
    };
    preview.set_object_placement(0, &placement).unwrap();
    let moved = preview.render(w, h).unwrap();
    fresh.load(&scene, None).unwrap();
    let reference = fresh.render(w, h).unwrap();
    assert!(agreement(&moved, &reference) > 0.999);
    assert!(agreement(&moved, &before) < 0.99, "the figure did not move");

    // Turn the camera.
    scene.camera.yaw += 25.0;
    preview.set_camera(&scene.camera);
    fresh.load(&scene, None).unwrap();
    assert!(agreement(&preview.render(w, h).unwrap(), &fresh.render(w, h).unwrap()) > 0.999);

    // A deeper cover.
    scene.preview.depth = 5;
    let mut settings = preview.settings();
    settings.depth = 5;
    preview.set_settings(settings).unwrap();
    fresh.load(&scene, None).unwrap();
    assert!(agreement(&preview.render(w, h).unwrap(), &fresh.render(w, h).unwrap()) > 0.999);
    assert_eq!(preview.stats(), fresh.stats());

    // New free parameters: the room is rebuilt, the figure stays where it was moved.
    scene.orbifold.parameters = vec![0.9, 1.3];
    preview.set_room(&scene).unwrap();
    fresh.load(&scene, None).unwrap();
    assert!(agreement(&preview.render(w, h).unwrap(), &fresh.render(w, h).unwrap()) > 0.999);
}

#[test]
fn straight_rays_change_curved_rooms_only() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    let (w, h) = (160, 120);
    let mut frames = Vec::new();
    for sig in ["*333", "*2352"] {
        let scene = scene(sig, 4);
        preview.load(&scene, None).unwrap();
        let curved = preview.render(w, h).unwrap();
        let mut settings = preview.settings();
        settings.projection = Projection::Straight;
        preview.set_settings(settings).unwrap();
        let straight = preview.render(w, h).unwrap();
        settings.projection = Projection::Curved;
        preview.set_settings(settings).unwrap();
        frames.push(agreement(&curved, &straight));
    }
    assert!(frames[0] > 0.995, "Euclidean: {}", frames[0]);
    assert!(frames[1] < 0.95, "hyperbolic: {}", frames[1]);
}

/// Levels of detail thin out the far copies in H² (which shrink across the line of sight) and
/// the images far round the sphere (which the projection flattens: heights shrink with distance,
/// widths do not), and the surface ids of the picture hardly change.
#[test]
fn levels_of_detail_draw_fewer_triangles_and_nearly_the_same_picture() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    for (signature, depth) in [("*2352", 5), ("*222", 0)] {
        let mut scene = scene(signature, depth);
        scene.objects[0].shape = "torus".into();
        preview.load(&scene, None).unwrap();
        let (w, h) = (320, 240);
        let detailed = {
            let mut settings = preview.settings();
            settings.lod = false;
            preview.set_settings(settings).unwrap();
            preview.render(w, h).unwrap()
        };
        let full = preview.stats();
        let mut settings = preview.settings();
        settings.lod = true;
        preview.set_settings(settings).unwrap();
        let simplified = preview.render(w, h).unwrap();
        let lod = preview.stats();
        assert_eq!(lod.instances, full.instances);
        assert!(
            (lod.triangles as f64) < 0.85 * full.triangles as f64,
            "{signature}: {} of {} triangles",
            lod.triangles,
            full.triangles
        );
        let share = agreement(&detailed, &simplified);
        assert!(
            share > 0.99,
            "{signature}: only {:.2} % of pixels agree",
            100.0 * share
        );
    }
}

#[test]
fn attenuation_darkens_copies_not_the_room() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    let scene = scene("*2222", 4);
    preview.load(&scene, None).unwrap();
    let brightness = |preview: &mut Preview, attenuation| {
        let settings = Settings {
            attenuation,
            ..preview.settings()
        };
        preview.set_settings(settings).unwrap();
        let frame = preview.render(160, 120).unwrap();
        frame.rgba.iter().map(|&c| f64::from(c)).sum::<f64>()
    };
    let universal = brightness(&mut preview, Attenuation::Universal);
    let orbifold = brightness(&mut preview, Attenuation::Orbifold);
    let reflectance = brightness(&mut preview, Attenuation::Reflectance);
    assert!(orbifold < reflectance && reflectance < universal);
}

#[test]
fn bad_requests_get_errors() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    assert_eq!(preview.render(64, 48).unwrap_err(), PreviewError::NoScene);
    preview.load(&scene("*333", 2), None).unwrap();
    assert!(matches!(
        preview.render(0, 48),
        Err(PreviewError::Size(0, 48))
    ));
    assert!(matches!(
        preview.render(1 << 20, 48),
        Err(PreviewError::Size(..))
    ));
    let far = Placement {
        at: Complex64::new(0.0, 0.0),
        height: 0.0,
        yaw: 0.0,
    };
    assert!(matches!(
        preview.set_object_placement(7, &far),
        Err(PreviewError::Scene(_))
    ));
    let mut bad = scene("*333", 2);
    bad.orbifold.signature = "*23".into();
    assert!(matches!(
        preview.load(&bad, None),
        Err(PreviewError::Scene(_))
    ));
    // The preview still draws the last good scene.
    assert!(preview.render(64, 48).is_ok());
}

/// For every pixel where both the preview and the tracer see the room's own floor (no mirror
/// between), the preview's colour against the pattern's albedo at the point the tracer's ray
/// hits (its position AOV): the ratio of the red and blue channels, which the headlight's
/// shading (one factor for all three) leaves alone. Returns the share of such pixels within 10 %
/// and their number.
fn floor_pattern_agreement(
    preview: &mut Preview,
    scene: &Scene,
    base: Option<&std::path::Path>,
    albedo: impl Fn(f64, f64) -> [f64; 3],
) -> (f64, usize) {
    let (width, height) = (160, 120);
    preview.load(scene, base).unwrap();
    assert!(
        preview.unread_textures().is_empty(),
        "{:?}",
        preview.unread_textures()
    );
    let frame = preview.render(width, height).unwrap();
    let tracer = Tracer::from_scene(scene, base).unwrap();
    let camera = Camera::new(tracer.space(), &scene.camera);
    let aovs = aov::render(&tracer, &camera, width, height, 4);
    let linear = |k: usize| orbifold_scene::color::linear_from_srgb8(frame.rgba[k]);
    let (mut seen, mut agree) = (0, 0);
    for k in 0..(width * height) as usize {
        if frame.ids[k] != 0 || aovs.surface[k] != 0 || aovs.bounces[k] != 0 {
            continue;
        }
        let [x, y, _] = aovs.position[k].map(f64::from);
        let a = albedo(x, y);
        let (r, b) = (linear(4 * k), linear(4 * k + 2));
        seen += 1;
        if ((r / b) / (a[0] / a[2]) - 1.0).abs() < 0.1 {
            agree += 1;
        }
    }
    (agree as f64 / seen.max(1) as f64, seen)
}

/// Marble and image textures are drawn where the renderer puts them (they were drawn in one
/// representative colour): the preview's shader runs the renderer's marble, hash and all, and
/// looks images up as the renderer does.
#[test]
fn textures_are_drawn_where_the_renderer_puts_them() {
    let Some(gpu) = gpu() else { return };
    let mut preview = Preview::new(gpu);
    let (ground, vein) = ([0.9, 0.5, 0.3], [0.3, 0.5, 0.9]);
    for (sig, size) in [("*2222", 0.4), ("*235", 0.15), ("*237", 0.1)] {
        let mut marbled = scene(sig, 1);
        // Looking down at the room's own floor.
        marbled.camera.pitch = -50.0;
        marbled.room.floor = orbifold_scene::Material::Marble {
            base: ground,
            vein,
            scale: size,
            coordinates: Default::default(),
        };
        let marble = |x: f64, y: f64| {
            let p = glam::DVec3::new(x, y, 0.0);
            orbifold_render::textures::marble(p, ground, vein, 1.0 / size)
        };
        let (share, seen) = floor_pattern_agreement(&mut preview, &marbled, None, marble);
        eprintln!(
            "{sig} marble: {:.1} % of {seen} floor pixels agree",
            100.0 * share
        );
        assert!(
            seen > 500 && share > 0.95,
            "{sig} marble: {share} of {seen}"
        );
    }
    // Four texels, each a colour whose red and blue differ from the others'.
    let dir = std::env::temp_dir().join(format!("orbifold-preview-image-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let texels = [
        [230, 60, 60],
        [60, 150, 230],
        [120, 230, 60],
        [230, 200, 160],
    ];
    let image = image::RgbImage::from_fn(2, 2, |i, j| image::Rgb(texels[(2 * j + i) as usize]));
    image.save(dir.join("four.png")).unwrap();
    let scale = 0.3;
    let texel = |x: f64, y: f64| {
        let (u, v) = ((x / scale).rem_euclid(1.0), (y / scale).rem_euclid(1.0));
        let (i, j) = ((u * 2.0) as usize, ((1.0 - v) * 2.0) as usize);
        texels[2 * j.min(1) + i.min(1)].map(orbifold_scene::color::linear_from_srgb8)
    };
    for sig in ["*2222", "*235"] {
        let mut imaged = scene(sig, 1);
        imaged.camera.pitch = -50.0;
        imaged.room.floor = orbifold_scene::Material::Texture {
            path: "four.png".into(),
            scale,
            coordinates: Default::default(),
        };
        let (share, seen) = floor_pattern_agreement(&mut preview, &imaged, Some(&dir), texel);
        eprintln!(
            "{sig} image: {:.1} % of {seen} floor pixels agree",
            100.0 * share
        );
        assert!(seen > 500 && share > 0.95, "{sig} image: {share} of {seen}");
    }
    // An image that cannot be read is named, and its floor drawn in its plain colour.
    let mut missing = scene("*2222", 1);
    missing.room.floor = orbifold_scene::Material::Texture {
        path: "nowhere.png".into(),
        scale,
        coordinates: Default::default(),
    };
    preview.load(&missing, Some(&dir)).unwrap();
    assert_eq!(preview.unread_textures().len(), 1);
    assert!(preview.render(64, 48).is_ok());
    std::fs::remove_dir_all(&dir).ok();
}
