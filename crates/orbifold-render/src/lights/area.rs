//! Area lights: Lambertian emitters over meshes of intrinsically flat triangles — the sphere and
//! rectangle lights of a scene, embedded in the room as the scene's objects are — and the area
//! element of such a triangle, by which points are drawn on it uniformly in area.

use std::f64::consts::PI;
use std::sync::Arc;

use glam::DVec3;
use orbifold::embed::Placement;
use orbifold::space::Space;
use orbifold_scene::color::Rgb;
use orbifold_scene::geometry::{Fit, embed_object};
use orbifold_scene::mesh::TriangleMesh;
use orbifold_trace::accel::{Bvh, Instance};

use super::emitter::Emitter;
use super::facing::Facing;
use crate::sampler::Distribution1d;

/// A Lambertian emitter of total power `power` over `mesh` (object coordinates), embedded as
/// `fit` says ([`embed_object`], as the scene's objects are) and placed at `placement`.
pub(super) fn area_emitter(
    space: Space,
    mesh: &TriangleMesh,
    fit: Fit,
    placement: &Placement,
    power: Rgb,
    two_sided: bool,
) -> Result<Emitter, String> {
    let embedded = embed_object(space, mesh, fit)?;
    let bvh = Bvh::build(space, &embedded.points, &embedded.heights, &mesh.triangles);
    mesh_emitter(
        space,
        Instance::from_placement(space, Arc::new(bvh), placement),
        power,
        two_sided,
    )
}

/// A Lambertian emitter of total power `power` over the mesh of `instance`.
pub(crate) fn mesh_emitter(
    space: Space,
    instance: Instance,
    power: Rgb,
    two_sided: bool,
) -> Result<Emitter, String> {
    let (points, heights, triangles) = instance.bvh.mesh();
    let areas: Vec<f64> = triangles
        .iter()
        .map(|t| {
            let p = t.map(|i| points[i as usize]);
            let h = t.map(|i| heights[i as usize]);
            0.5 * area_jacobian(space, &p, &h, [1.0 / 3.0; 3])
        })
        .collect();
    let total_area: f64 = areas.iter().sum();
    let triangle_distribution = Distribution1d::new(&areas).ok_or("the light has no area")?;
    Ok(Emitter::Area {
        // A Lambertian emitter of area A and radiance L sends out πAL.
        radiance: power.map(|p| p / (PI * total_area)),
        instance,
        areas,
        triangle_distribution,
        facing: None,
        total_area,
        two_sided,
    })
}

impl Emitter {
    /// The emitter with [`Facing`] for a sphere light's mesh.
    pub(super) fn with_facing(self, space: Space) -> Emitter {
        match self {
            Emitter::Area {
                radiance,
                instance,
                areas,
                triangle_distribution,
                total_area,
                two_sided,
                ..
            } => Emitter::Area {
                facing: Facing::new(space, &instance, &areas),
                radiance,
                instance,
                areas,
                triangle_distribution,
                total_area,
                two_sided,
            },
            other => other,
        }
    }
}

/// The mesh of a rectangle light facing `axis` (local frame), `size` = [width, height], in object
/// coordinates (Y up) as [`embed_object`] takes them, centred at the origin; and its lowest local
/// height.
pub(super) fn rectangle_mesh(axis: DVec3, size: [f64; 2]) -> (TriangleMesh, f64) {
    let right = if axis.truncate().length() < 1e-9 {
        DVec3::X
    } else {
        axis.cross(DVec3::Z).normalize()
    };
    // (right, up, axis) right-handed, so that right × up = axis: the front faces the axis.
    let up = axis.cross(right);
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .map(|(a, b)| right * (0.5 * size[0] * a) + up * (0.5 * size[1] * b));
    // Wound counter-clockwise seen from the front.
    let lowest = corners.iter().map(|c| c.z).fold(f64::INFINITY, f64::min);
    let mesh = TriangleMesh {
        positions: corners.iter().map(|c| [c.x, c.z, -c.y]).collect(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    (mesh, lowest)
}

/// The area element of the intrinsically flat triangle at barycentrics `w`, per unit of
/// (w₁, w₂): |∂X/∂w₁ ∧ ∂X/∂w₂| in the product metric, X(w) = (normalise(Σ wᵢpᵢ), Σ wᵢhᵢ).
pub fn area_jacobian(space: Space, points: &[DVec3; 3], heights: &[f64; 3], w: [f64; 3]) -> f64 {
    let q = points[0] * w[0] + points[1] * w[1] + points[2] * w[2];
    // normalise(q) = q/|q|_κ, and for κ = 0 q/q_z (the plane z = 1).
    let norm = if space.kappa() == 0.0 {
        q.z
    } else {
        space.point_dot(q, q).abs().sqrt()
    };
    if norm == 0.0 {
        return 0.0;
    }
    let n = q / norm;
    let k = space.kappa();
    // d normalise(q) = (v − κ⟨n, v⟩n)/|q| (E²: z is fixed at 1 and v has z = 0).
    let project = |v: DVec3| (v - n * (k * space.point_dot(n, v))) / norm;
    let a = (project(points[1] - points[0]), heights[1] - heights[0]);
    let b = (project(points[2] - points[0]), heights[2] - heights[0]);
    let dot = |x: (DVec3, f64), y: (DVec3, f64)| space.point_dot(x.0, y.0) + x.1 * y.1;
    (dot(a, a) * dot(b, b) - dot(a, b).powi(2)).max(0.0).sqrt()
}
