//! Energy: in a room that absorbs nothing, the echoes' energy per unit time is the same at
//! every time and in every geometry, c·Δt/(4πV) for a room of volume V (metres): the images in a
//! shell of thickness cΔt number (shell area)·cΔt/V, and each has energy 1/(16π²J) with J the
//! area density of the geodesic spheres whose area the shell is (Kuttruff, Room Acoustics, §5.1
//! for the flat case). Checks that spreading and the image count are consistent, and that no
//! echo is lost or counted twice.

mod common;

use orbifold_sound::Hearing;

fn energy_per_window(signature: &str, seconds: f64, windows: &[(f64, f64)], tolerance: f64) {
    let mut scene = common::lossless(common::scene(signature, seconds));
    scene.sound.min_level = -200.0;
    let hearing = Hearing::from_scene(&scene, None).unwrap();
    let response = hearing.mono(&|_, _| {});
    let layout = scene.layout().unwrap();
    let r = hearing.settings.metres_per_unit;
    let area = area(&layout);
    let volume = area * scene.room.height * r.powi(3);
    let c = hearing.settings.speed;
    for &(from, to) in windows {
        let energy: f64 = response
            .arrivals
            .iter()
            .filter(|a| (from..to).contains(&a.time))
            .map(|a| a.amplitude * a.amplitude)
            .sum();
        let expected = c * (to - from) / (4.0 * std::f64::consts::PI * volume);
        let ratio = energy / expected;
        assert!(
            (ratio - 1.0).abs() < tolerance,
            "{signature} [{from}, {to}] s: energy {energy}, expected {expected} (ratio {ratio})"
        );
    }
}

/// The polygon's intrinsic area: 2π|χ| when curved (Gauss–Bonnet), the rectangle's in E².
fn area(layout: &orbifold::Layout) -> f64 {
    let chi = layout.symbol.euler_characteristic().to_f64();
    if layout.space().kappa() != 0.0 {
        return 2.0 * std::f64::consts::PI * chi.abs();
    }
    let v: Vec<_> = layout.vertices.iter().map(|v| v.position * 2.0).collect();
    // The shoelace formula.
    let twice: f64 = (0..v.len())
        .map(|i| {
            let (a, b) = (v[i], v[(i + 1) % v.len()]);
            a.re * b.im - b.re * a.im
        })
        .sum();
    0.5 * twice.abs()
}

#[test]
fn a_lossless_shoebox_keeps_its_energy_per_unit_time() {
    energy_per_window("*2222", 0.3, &[(0.1, 0.2), (0.2, 0.3)], 0.02);
}

#[test]
fn a_lossless_hyperbolic_room_keeps_its_energy_per_unit_time() {
    energy_per_window("*444", 0.06, &[(0.03, 0.045), (0.045, 0.06)], 0.04);
}

#[test]
fn a_lossless_spherical_room_keeps_its_energy_per_unit_time_on_average() {
    // The sphere refocuses echoes; over a window longer than a trip round it the energy
    // averages out to the same rate (the focus, as wide as the listener, adds a little).
    energy_per_window("*235", 0.5, &[(0.1, 0.5)], 0.06);
}

#[test]
fn lossless_rooms_with_portals_keep_their_energy_per_unit_time() {
    // Portals pass sound on whole: the images are the group's, a shell of the cover still holds
    // (shell area)·cΔt/V of them, whatever the rotations, glides and handles. (On the sphere
    // the average depends on where the listener sits against the foci, for mirror rooms too.)
    energy_per_window("o", 0.3, &[(0.1, 0.2), (0.2, 0.3)], 0.02);
    energy_per_window("22×", 0.3, &[(0.1, 0.2), (0.2, 0.3)], 0.02);
    energy_per_window("2223", 0.06, &[(0.03, 0.045), (0.045, 0.06)], 0.04);
}
