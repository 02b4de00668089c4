//! Counts the echoes of rooms given by signature and times them (a quick look; the benchmark
//! measures): `cargo run --release -p orbifold-sound --example count -- '*2222' '*444'`.
fn main() {
    for sig in std::env::args().skip(1) {
        tiles_only(&sig);
        let mut scene = orbifold_scene::Scene::default();
        scene.orbifold.signature = sig.clone();
        let layout = scene.layout().expect("a signature that can be laid out");
        let c = layout.centre;
        scene.lights[0].at = [c.re, c.im];
        scene.objects.clear();
        scene.camera.at = [c.re * 0.5 + 0.5 * layout.vertices[0].position.re, c.im * 0.5 + 0.5 * layout.vertices[0].position.im];
        let hearing = orbifold_sound::Hearing::from_scene(&scene).expect("a scene that can be heard");
        let t = std::time::Instant::now();
        let r = hearing.mono(&|_, _| {});
        let e = t.elapsed();
        println!(
            "{sig}: {} arrivals, {} paths, {} lost, {e:?}, first {:?}",
            r.arrivals.len(),
            r.paths.len(),
            r.lost,
            r.arrivals.first().map(|a| (a.time, a.amplitude))
        );
    }
}

#[allow(dead_code)]
fn tiles_only(sig: &str) {
    let layout = orbifold::Layout::new(&sig.parse().unwrap(), &Default::default()).unwrap();
    let room = orbifold_trace::room::AnalyticRoom::all_mirrors(&layout, 1.0, [1.0; 3]).unwrap();
    let c = room.space.to_ambient(layout.centre);
    let t = std::time::Instant::now();
    let n = orbifold_sound::image_source::tiles(&room, c, c, 9.9).len();
    println!("{sig}: {n} tiles in {:?}, radius {}", t.elapsed(), orbifold_sound::image_source::room_radius(&room, c));
}
