//! The layout view's geometry: the cut a free parameter controls is the common perpendicular
//! of its two walls.

use orbifold::{Layout, LayoutOptions};
use orbifold_studio::layout_view::{parameter_cut, wall_points};

#[test]
fn the_cut_of_a_parameter_is_the_common_perpendicular_of_its_walls() {
    for sig in ["*22222", "*2333", "*2222222", "*23456"] {
        let layout = Layout::new(&sig.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let space = layout.space();
        for j in 0..layout.parameters.len() {
            let (walls, cut) = parameter_cut(&layout, j);
            assert_eq!(walls.len(), 2, "{sig} parameter {j}");
            assert!(!cut.is_empty(), "{sig} parameter {j}: no cut");
            let (nu, mu) = (layout.edges[walls[0]].wall, layout.edges[walls[1]].wall);
            let (p, q) = (
                space.to_ambient(cut[0]),
                space.to_ambient(*cut.last().unwrap()),
            );
            assert!(
                nu.dot(p).abs() < 1e-9 && mu.dot(q).abs() < 1e-9,
                "{sig}: feet off the walls"
            );
            // Ultraparallel walls: −⟨ν, μ⟩ = cosh of their distance, the cut's length.
            let length = space.ambient_distance(p, q);
            let expected = (-space.wall_dot(nu, mu)).acosh();
            assert!(
                (length - expected).abs() < 1e-7,
                "{sig}: {length} vs {expected}"
            );
        }
    }
}

#[test]
fn wall_points_run_along_the_walls() {
    for sig in ["*22222", "*235", "*333", "*∞∞∞", "*2223"] {
        let layout = Layout::new(&sig.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let space = layout.space();
        for (i, edge) in layout.edges.iter().enumerate() {
            let points = wall_points(&layout, i);
            assert!(points.len() > 2, "{sig} wall {i}");
            for z in points.iter().filter(|z| z.norm() < 0.999) {
                let on = edge.wall.dot(space.to_ambient(*z)).abs();
                assert!(on < 1e-9, "{sig} wall {i}: {on}");
            }
        }
    }
}
