//! Survey of layout accuracy: lays out 3000 random hyperbolic polygons (3 to 30 corners, orders
//! 2 to 20 and ∞, free parameters in (0.05, 10), random placements), measures every corner angle
//! from the corner positions alone, and reports how many miss π/k by more than 1e-9 and how far
//! the farthest corners lie from the centre.
//!
//! `cargo run --release -p orbifold --example layout_stats`
fn main() {
    use num_complex::Complex64;
    use orbifold::layout::*;
    use orbifold::{Order, Signature};
    let mut seed: u64 = 12345;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut fails, mut total, mut worst) = (0, 0, 0.0f64);
    let mut far = Vec::new();
    let samples: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(3000);
    while total < samples {
        let n = 3 + (rnd() * 28.0) as usize;
        let corners: Vec<Order> = (0..n)
            .map(|_| {
                if rnd() < 0.1 {
                    Order::Infinite
                } else {
                    Order::integer(2 + (rnd() * 19.0) as u64)
                }
            })
            .collect();
        let s = Signature::new(corners).unwrap();
        if s.geometry() != orbifold::Geometry::Hyperbolic {
            continue;
        }
        let params: Vec<f64> = (0..n.saturating_sub(3))
            .map(|_| 0.05 + rnd() * 9.95)
            .collect();
        let at = Complex64::from_polar(rnd() * 0.9, rnd() * std::f64::consts::TAU);
        let l = Layout::new(
            &s,
            &LayoutOptions {
                shape: Shape::Parameters(params),
                at,
                angle: rnd() * 6.0,
            },
        )
        .unwrap();
        let sp = l.space();
        let mut err = 0.0f64;
        let mut maxd = 0.0f64;
        for (i, v) in l.vertices.iter().enumerate() {
            if v.ideal {
                continue;
            }
            let next = l.vertices[(i + 1) % n].position;
            let prev = l.vertices[(i + n - 1) % n].position;
            let a = (sp.direction(v.position, prev) / sp.direction(v.position, next)).arg();
            err = err.max((a - v.angle).abs());
            // And between the walls' drawn geodesics at the corner.
            let tangent = |g: &orbifold::space::ModelGeodesic, towards: Complex64| {
                let t = match *g {
                    orbifold::space::ModelGeodesic::Circle { centre, .. } => {
                        Complex64::i() * (v.position - centre)
                    }
                    orbifold::space::ModelGeodesic::Line { direction, .. } => direction,
                };
                if (t * towards.conj()).re < 0.0 { -t } else { t }
            };
            let t_next = tangent(&l.edges[i].geodesic, sp.direction(v.position, next));
            let t_prev = tangent(
                &l.edges[(i + n - 1) % n].geodesic,
                sp.direction(v.position, prev),
            );
            err = err.max(((t_prev / t_next).arg() - v.angle).abs());
            maxd = maxd.max(sp.distance(l.centre, v.position));
        }
        total += 1;
        worst = worst.max(err);
        far.push(maxd);
        if err > 1e-9 {
            fails += 1;
        }
    }
    far.sort_by(|a, b| a.partial_cmp(b).unwrap());
    println!(
        "{fails}/{total} over 1e-9, worst {worst:e}, farthest corner median {:.1} p95 {:.1} max {:.1}",
        far[far.len() / 2],
        far[far.len() * 95 / 100],
        far[far.len() - 1]
    );
}
