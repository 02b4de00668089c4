#![allow(missing_docs)]
use orbifold::room::{RoomMesher, RoomOptions, Surface};
use orbifold::{Layout, LayoutOptions, Signature};
fn main() {
    let sig = std::env::args().nth(1).unwrap();
    let s: Signature = sig.parse().unwrap();
    let layout = Layout::new(&s, &LayoutOptions::default()).unwrap();
    let space = layout.space();
    let m = RoomMesher::new(&layout, &RoomOptions::default()).unwrap();
    let f = m.floor();
    let mut worst = (f64::INFINITY, 0);
    for (k, t) in f.triangles.iter().enumerate() {
        let one = Surface {
            points: f.points.clone(),
            heights: f.heights.clone(),
            triangles: vec![*t],
        };
        let q = one.quality(space);
        if q.smallest_angle < worst.0 {
            worst = (q.smallest_angle, k);
        }
    }
    let t = f.triangles[worst.1];
    println!(
        "worst {} at {:?}",
        worst.0,
        t.map(|i| (space.to_model(f.points[i as usize]), i))
    );
    for (i, c) in m.boundary.corners.iter().enumerate() {
        println!(
            "corner {i} {} {:?}",
            space.to_model(*c),
            m.boundary.sides[i]
        );
    }
}
