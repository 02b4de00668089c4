//! The tiling renderer: folding invariants and pictures.

use num_complex::Complex64;
use orbifold::cover::reflection;
use orbifold::layout::{Layout, LayoutOptions};
use orbifold_picture::tiling::{Coloring, Model, Motif, View, fold_point, render};
use proptest::prelude::*;

fn layout(sig: &str) -> Layout {
    Layout::new(&sig.parse().unwrap(), &LayoutOptions::default()).unwrap()
}

fn mirror(layout: &Layout, wall: usize, z: Complex64) -> Complex64 {
    let space = layout.space();
    space.to_model(reflection(space, layout.edges[wall].wall) * space.to_ambient(z))
}

proptest! {
    /// Folding is idempotent, lands inside the polygon, and a point and its mirror image in a
    /// wall fold to the same point with depths that differ by exactly one.
    #[test]
    fn folding_invariants(
        sig in prop::sample::select(vec!["*237", "*2222222", "*2323", "*∞∞∞", "*333", "*2222", "*235", "*22222"]),
        r in 0.0f64..0.97,
        theta in 0.0f64..std::f64::consts::TAU,
        wall in 0usize..3,
    ) {
        let l = layout(sig);
        let scale = if l.geometry == orbifold::Geometry::Euclidean { 3.0 } else { 1.0 };
        let z = Complex64::from_polar(r * scale, theta);
        let Some((inside, depth, _)) = fold_point(&l, z, 400) else { return Ok(()) };
        let (again, zero, last) = fold_point(&l, inside, 400).unwrap();
        prop_assert!((again - inside).norm() < 1e-9);
        prop_assert_eq!((zero, last), (0, None));
        let space = l.space();
        let p = space.to_ambient(inside);
        for e in &l.edges {
            prop_assert!(e.wall.dot(p) > -1e-9 * p.length());
        }
        let image = mirror(&l, wall % l.edges.len(), z);
        if let Some((inside2, depth2, _)) = fold_point(&l, image, 400) {
            prop_assert!((inside2 - inside).norm() < 1e-7, "{sig}: {inside} vs {inside2}");
            prop_assert_eq!(depth.abs_diff(depth2), 1);
        }
    }
}

#[test]
fn pictures_have_the_right_size_and_background() {
    let l = layout("*237");
    let picture = render(&l, &View::new(l.geometry, 96), None).unwrap();
    assert_eq!(picture.rgba.len(), 96 * 96 * 4);
    // The corner pixel is outside the Poincaré disk.
    assert_eq!(&picture.rgba[..4], &[255, 255, 255, 255]);
    // The centre is inside the base tile (depth 0, even).
    let centre = (48 * 96 + 48) * 4;
    assert_ne!(&picture.rgba[centre..centre + 4], &[255, 255, 255, 255]);
}

#[test]
fn pixel_colours_follow_the_fold() {
    // A two-colour motif: every pixel shows one of its colours; the parity picture shows the
    // even colour exactly where the fold takes an even number of reflections.
    let l = layout("*2222222");
    let (w, h) = (8u32, 8u32);
    let rgba: Vec<u8> = (0..w * h)
        .flat_map(|i| {
            if i % w < w / 2 {
                [255, 0, 0, 255]
            } else {
                [0, 0, 255, 255]
            }
        })
        .collect();
    let motif = Motif {
        rgba,
        width: w,
        height: h,
    };
    let mut view = View::new(l.geometry, 201);
    view.edges = false;
    let with_motif = render(&l, &view, Some(&motif)).unwrap();
    view.coloring = Coloring::Parity;
    let parity = render(&l, &view, None).unwrap();
    let mut checked = 0;
    for (i, j) in [(120, 100), (100, 130), (80, 90), (140, 140)] {
        let s = Complex64::new(
            (i as f64 + 0.5 - 100.5) / 100.5,
            (100.5 - (j as f64 + 0.5)) / 100.5,
        );
        let a = fold_point(&l, s, 200).unwrap();
        let k = (j * 201 + i) * 4;
        assert!(with_motif.rgba[k] == 255 || with_motif.rgba[k + 2] == 255);
        let expected_even = a.1.is_multiple_of(2);
        let even_colour = [233, 196, 106];
        assert_eq!(parity.rgba[k..k + 3] == even_colour, expected_even);
        checked += 1;
    }
    assert_eq!(checked, 4);
}

#[test]
fn every_model_renders_its_geometry_only() {
    let h = layout("*2∞∞");
    for model in [Model::Poincare, Model::Klein, Model::HalfPlane] {
        let mut view = View::new(h.geometry, 48);
        view.model = model;
        render(&h, &view, None).unwrap();
    }
    let mut view = View::new(h.geometry, 48);
    view.model = Model::Sphere;
    assert!(render(&h, &view, None).is_err());
    let s = layout("*234");
    for model in [Model::Stereographic, Model::Sphere] {
        let mut view = View::new(s.geometry, 48);
        view.model = model;
        render(&s, &view, None).unwrap();
    }
}
