//! Mesh quality of room floors, both methods, for the signatures given (default: a few of every
//! kind): `cargo run --release -p orbifold --example room_quality -- '*2223' '*∞∞∞'`.

use orbifold::room::{FloorMethod, RoomMesher, RoomOptions};
use orbifold::{Layout, LayoutOptions, Signature};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut signatures: Vec<String> = std::env::args().skip(1).collect();
    if signatures.is_empty() {
        signatures = [
            "*",
            "*22",
            "*235",
            "*333",
            "*2223",
            "*22222",
            "*∞∞∞",
            "*23456789(10)(11)",
        ]
        .map(String::from)
        .into();
    }
    println!("signature            method     triangles  longest edge  smallest angle  area error");
    for text in signatures {
        let signature: Signature = text.parse()?;
        let layout = Layout::new(&signature, &LayoutOptions::default())?;
        for (method, name) in [
            (FloorMethod::Contour, "contour"),
            (FloorMethod::Geodesic, "geodesic"),
        ] {
            let options = RoomOptions {
                method,
                ..RoomOptions::default()
            };
            let mesher = RoomMesher::new(&layout, &options)?;
            let floor = mesher.floor();
            let q = floor.quality(layout.space());
            let error = floor.horizontal_area(layout.space()) - mesher.meshed_area();
            println!(
                "{text:<20} {name:<10} {:>9}  {:>12.4}  {:>13.3}°  {error:>10.1e}",
                q.triangles, q.largest_edge, q.smallest_angle
            );
        }
    }
    Ok(())
}
