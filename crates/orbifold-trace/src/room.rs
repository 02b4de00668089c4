//! The analytic mirror room (seed 8.2): the prism polygon × [0, height] whose walls, floor and
//! ceiling are intersected in closed form, never meshed.
//!
//! A ray from inside leaves the (convex) prism through exactly one face. Each wall is the zero
//! set of a linear form ν, so along the ray's horizontal geodesic ν·x(σ) = C(σ)(ν·p) + S(σ)(ν·u)
//! and the crossing is one `atan2`, division or `atanh` ([`line_crossing`]); floor and ceiling are
//! linear in the arc length. Partial mirrors are looked up by the hit's arc length along its
//! wall (as a fraction of the wall's meshed length, so that exports, the preview and the tracer
//! agree) and its height.

use glam::{DMat3, DVec3};
use num_complex::Complex64;
use orbifold::Layout;
use orbifold::cover::reflection;
use orbifold::room::RoomMesher;
use orbifold::space::Space;
use orbifold_scene::{Color, Scene};

use crate::geodesic::{Ray, line_crossing};

/// How a wall's crossing is found once the wall is known to be the nearest.
#[derive(Clone, Copy, Debug)]
enum WallCrossing {
    /// [`line_crossing`] of the linear form's values at the ray's origin and along it.
    Line(f64, f64),
    /// Already found (σ).
    Found(f64),
}

/// A key that grows with the σ of [`line_crossing`]`(space, a, b)` and is `None` exactly when
/// it is: tanh σ in H² (a division where σ needs an `atanh`), σ in E², −cos σ in S² (a square
/// root where σ needs an `atan2`).
#[inline]
fn crossing_key(space: Space, a: f64, b: f64) -> Option<f64> {
    let a = a.max(0.0);
    let k = space.kappa();
    if k > 0.0 {
        // σ = atan2(a, −b) ∈ [0, π] with a ≥ 0, so cos σ = −b/r; for a = b = 0 the sign of
        // zero decides (atan2(0, −0) = π, atan2(0, +0) = 0), as it does for b/r's sign.
        let r = (a * a + b * b).sqrt();
        return Some(if r > 0.0 { b / r } else { 1f64.copysign(b) });
    }
    if b >= 0.0 {
        return None;
    }
    let ratio = a / -b;
    (k == 0.0 || ratio < 1.0).then_some(ratio)
}

/// (C_κ(σ), S_κ(σ)) at the σ of [`line_crossing`]`(space, a, b)` without σ's inverse function:
/// a C(σ) + b S(σ) = 0 puts (C, S) along (−b, a), scaled to C² + κS² = 1 by
/// r = √(b² + κa²) (for κ < 0 as (−b − a)(a − b), without the cancellation). `None` where r is
/// 0 (S², a ray along the line).
#[inline]
fn crossing_cos_sin(space: Space, a: f64, b: f64) -> Option<(f64, f64)> {
    let a = a.max(0.0);
    let k = space.kappa();
    let r2 = if k < 0.0 {
        (-b - a) * (a - b)
    } else {
        b * b + k * a * a
    };
    let r = r2.sqrt();
    (r > 0.0).then(|| (-b / r, a / r))
}

/// A rectangular mirror on a wall: fractions of the wall's length × heights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MirrorRect {
    /// Where it starts along the wall (fraction of the length).
    pub from: f64,
    /// Where it ends along the wall.
    pub to: f64,
    /// Lower edge height.
    pub bottom: f64,
    /// Upper edge height.
    pub top: f64,
    /// Reflectance per channel.
    pub reflectance: Color,
}

impl MirrorRect {
    /// Whether the wall point at fraction `along` and height `height` is on this mirror.
    pub fn covers(&self, along: f64, height: f64) -> bool {
        self.from <= along && along <= self.to && self.bottom <= height && height <= self.top
    }
}

/// The default width of a portal's frame: the solid band along a portal's edges (its corners,
/// floor and ceiling) that shows people where the room ends.
pub const DEFAULT_PORTAL_FRAME: f64 = 0.02;

/// A wall glued to another by the orbifold's group: what reaches it goes on from its partner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Portal {
    /// The partner wall.
    pub partner: usize,
    /// g, with g(P) the tile across this wall (the layout edge's `neighbour`): what a path
    /// that crosses it multiplies its chain of tiles by.
    pub across: DMat3,
    /// g⁻¹, the pairing that takes this wall onto the partner: what moves a ray that crosses.
    pub back: DMat3,
    /// Whether g reverses orientation (a glide reflection): left and right swap on the way.
    pub reverses: bool,
    /// The share of light it passes on, per channel.
    pub transmittance: Color,
    /// The width of the solid frame along its edges (intrinsic length; 0 for none).
    pub frame: f64,
}

/// What a wall does at a point where a ray meets it, when the ray goes on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Passage {
    /// The mirror's index on the wall, for a mirror; `None` for a portal.
    pub mirror: Option<usize>,
    /// The portal's partner wall, for a portal.
    pub portal_to: Option<usize>,
    /// What it passes on: the mirror's reflectance, or the portal's transmittance.
    pub throughput: Color,
    /// g: the tile the ray goes on into, in the universal cover, is g(P).
    pub across: DMat3,
    /// g⁻¹: the ray, moved back into the room, goes on as `back` × the ray.
    pub back: DMat3,
    /// Whether g reverses orientation (a mirror, or a glide).
    pub reverses: bool,
    /// The linear form of the geodesic a mirror reflects in ([`AnalyticRoom::wall_form_at`]).
    pub mirror_form: DVec3,
}

/// One wall of the analytic room.
#[derive(Clone, Debug, PartialEq)]
pub struct RoomWall {
    /// The wall's linear form, positive inside, normalised (ν₁² + ν₂² + κν₃² = 1).
    pub form: DVec3,
    /// Where its arc length starts (its first corner, or the cusp cut for an ideal one).
    pub start: DVec3,
    /// Unit tangent at `start`, pointing along the wall (counter-clockwise around the room).
    pub tangent: DVec3,
    /// Its meshed intrinsic length (to the cusp cuts for ideal ends), the unit of mirror
    /// fractions.
    pub length: f64,
    /// Whether the wall is a closed great circle (the single wall of `*`).
    pub closed: bool,
    /// Its mirrors; the first that covers a point wins.
    pub mirrors: Vec<MirrorRect>,
    /// For a wall paired with another by the group, the portal (mirrors on it, if any, win).
    pub portal: Option<Portal>,
    /// The other walls on the same geodesic: a fundamental polygon may have a corner of angle π
    /// (a cone point of order 2 halfway along a side), and a crossing of the line is then told
    /// apart by where along it it lies.
    pub same_line: Vec<usize>,
    /// Straight-ray mode ([`AnalyticRoom::flattened`]): the curved plane whose model this wall is
    /// drawn in. The room's own plane is then the flat one, the wall is the model curve of
    /// `form` (a circle or a line), and `start`, `tangent` and `length` are measured in the
    /// curved plane.
    pub drawn_in: Option<Space>,
}

/// The model curve of the wall ν of a plane of curvature κ, −κν₃|z|² + 2(ν₁x + ν₂y) + ν₃ = 0,
/// as a function of the model point z: positive inside the room (the same sign as ν·p).
fn model_curve(kappa: f64, nu: DVec3, z: Complex64) -> f64 {
    -kappa * nu.z * z.norm_sqr() + 2.0 * (nu.x * z.re + nu.y * z.im) + nu.z
}

/// What part of the room a ray met.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RoomSurface {
    /// The floor, height 0.
    Floor,
    /// The ceiling.
    Ceiling,
    /// Wall `i` (the edge index of the layout).
    Wall(usize),
}

/// Where a ray leaves the room.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoomHit {
    /// Arc length from the ray's origin.
    pub s: f64,
    /// The face.
    pub surface: RoomSurface,
    /// Ambient horizontal position.
    pub point: DVec3,
    /// The ray's unit horizontal tangent there (before any reflection): with `point`, what
    /// [`Ray::continued`] needs to go on from the exit.
    pub tangent: DVec3,
    /// Height.
    pub height: f64,
}

/// The prism over a laid-out polygon, with its mirrors.
///
/// ```
/// use orbifold::{Layout, LayoutOptions};
/// use orbifold_trace::geodesic::Ray;
/// use orbifold_trace::room::{AnalyticRoom, RoomSurface};
/// use num_complex::Complex64;
/// let layout = Layout::new(&"*333".parse()?, &LayoutOptions::default())?;
/// let room = AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3])?;
/// let ray = Ray::from_model(layout.space(), Complex64::new(0.0, 0.0), 0.5, 0.0, 0.0);
/// let hit = room.exit(&ray).unwrap();
/// assert!(matches!(hit.surface, RoomSurface::Wall(_)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct AnalyticRoom {
    /// The plane.
    pub space: Space,
    /// The height of the ceiling.
    pub height: f64,
    /// The walls, in the layout's edge order.
    pub walls: Vec<RoomWall>,
}

impl AnalyticRoom {
    /// The room of a layout with the given mirrors per wall (`mirrors[i]` for wall `i`, missing
    /// entries meaning no mirror). Ideal walls are measured to the default cusp cut.
    pub fn new(
        layout: &Layout,
        height: f64,
        cusp_distance: Option<f64>,
        mirrors: &[Vec<MirrorRect>],
    ) -> Result<AnalyticRoom, String> {
        if !(height.is_finite() && height > 0.0) {
            return Err(format!("the room's height must be positive, not {height}"));
        }
        let options = orbifold::room::RoomOptions {
            height,
            resolution: 1.0,
            cusp_distance,
            ..Default::default()
        };
        let mesher = RoomMesher::new(layout, &options).map_err(|e| e.to_string())?;
        let space = layout.space();
        let closed = layout.vertices.is_empty();
        let walls = layout
            .edges
            .iter()
            .enumerate()
            .map(|(i, edge)| {
                let start = mesher
                    .wall_point(i, 0.0)
                    .ok_or_else(|| format!("wall {i} has no points"))?;
                let length = mesher.wall_length(i).unwrap_or(0.0);
                // The inner normal Gν is the left of the direction of travel: t = −J(Gν).
                let normal = DVec3::new(edge.wall.x, edge.wall.y, space.kappa() * edge.wall.z);
                let tangent = -space.quarter_turn(start, normal);
                Ok(RoomWall {
                    form: edge.wall,
                    start,
                    tangent: tangent / space.point_dot(tangent, tangent).sqrt(),
                    length,
                    closed,
                    mirrors: mirrors.get(i).cloned().unwrap_or_default(),
                    portal: edge.partner().map(|partner| Portal {
                        partner,
                        across: edge.neighbour,
                        back: layout.edges[partner].neighbour,
                        reverses: edge.neighbour.determinant() < 0.0,
                        transmittance: [1.0; 3],
                        frame: DEFAULT_PORTAL_FRAME,
                    }),
                    same_line: Vec::new(),
                    drawn_in: None,
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        let forms: Vec<DVec3> = walls.iter().map(|w| w.form).collect();
        let mut walls = walls;
        for (i, wall) in walls.iter_mut().enumerate() {
            wall.same_line = (0..forms.len())
                .filter(|&j| j != i && (forms[j] - forms[i]).length() < 1e-9)
                .collect();
        }
        Ok(AnalyticRoom {
            space,
            height,
            walls,
        })
    }

    /// The room with every mirror wall of the orbifold a full mirror of the given reflectance
    /// and every paired wall a portal (what `orbifold trace SIG` uses).
    pub fn all_mirrors(
        layout: &Layout,
        height: f64,
        reflectance: Color,
    ) -> Result<AnalyticRoom, String> {
        let full = MirrorRect {
            from: 0.0,
            to: 1.0,
            bottom: 0.0,
            top: height,
            reflectance,
        };
        let mirrors: Vec<Vec<MirrorRect>> = layout
            .edges
            .iter()
            .map(|e| match e.partner() {
                None => vec![full],
                Some(_) => Vec::new(),
            })
            .collect();
        AnalyticRoom::new(layout, height, None, &mirrors)
    }

    /// The room of a scene: its layout, height, cusp cut and the mirrors of every wall.
    pub fn from_scene(scene: &Scene, layout: &Layout) -> Result<AnalyticRoom, String> {
        let height = scene.room.height;
        let mirrors: Vec<Vec<MirrorRect>> = (0..layout.edges.len())
            .map(|i| {
                scene
                    .mirrors_of_wall(i, layout.edges[i].partner().is_some())
                    .iter()
                    .map(|m| MirrorRect {
                        from: m.from,
                        to: m.to,
                        bottom: m.bottom,
                        top: m.top.unwrap_or(height).min(height),
                        reflectance: m.reflectance,
                    })
                    .collect()
            })
            .collect();
        let mut room = AnalyticRoom::new(layout, height, scene.room.cusp_distance, &mirrors)?;
        for portal in room.walls.iter_mut().filter_map(|w| w.portal.as_mut()) {
            portal.transmittance = scene.room.portal_transmittance;
            portal.frame = scene.room.portal_frame;
        }
        Ok(room)
    }

    /// What wall `wall` does to a ray that meets it at `point`, `height`, if the ray goes on:
    /// reflects it (a mirror there), or carries it through to the partner wall (a portal,
    /// outside its frame). `None` where the wall is solid.
    ///
    /// ```
    /// use orbifold::{Layout, LayoutOptions};
    /// use orbifold_trace::room::AnalyticRoom;
    /// let layout = Layout::of_symbol(&"632".parse()?, &LayoutOptions::default())?;
    /// let room = AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3])?;
    /// let wall = &room.walls[0];
    /// let middle = room.space.exp(wall.start, wall.tangent * (0.5 * wall.length));
    /// let passage = room.passage(0, middle, 0.5).unwrap();
    /// // A rotation about a cone point: the ray goes on from the partner wall, unmirrored.
    /// assert!(passage.mirror.is_none() && !passage.reverses);
    /// assert_eq!(passage.portal_to, Some(room.walls[0].portal.unwrap().partner));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn passage(&self, wall: usize, point: DVec3, height: f64) -> Option<Passage> {
        if let Some((index, mirror)) = self.mirror_at(wall, point, height) {
            let form = self.wall_form_at(wall, point);
            let reflection = reflection(self.space, form);
            return Some(Passage {
                mirror_form: form,
                mirror: Some(index),
                portal_to: None,
                throughput: mirror.reflectance,
                across: reflection,
                back: reflection,
                reverses: true,
            });
        }
        let portal = self.walls[wall].portal?;
        if self.in_portal_frame(wall, point, height) {
            return None;
        }
        let (across, back) = match self.walls[wall].drawn_in {
            None => (portal.across, portal.back),
            Some(curved) => {
                let back = self.drawn_map(curved, &portal.back, portal.reverses, point);
                (back.inverse(), back)
            }
        };
        Some(Passage {
            mirror: None,
            portal_to: Some(portal.partner),
            throughput: portal.transmittance,
            across,
            back,
            reverses: portal.reverses,
            mirror_form: self.walls[wall].form,
        })
    }

    /// Straight-ray mode: the model picture of the curved plane's isometry `m` near the flat
    /// ambient point `point`, as the flat similarity that agrees with it there to first order
    /// (the value and the derivative of a Möbius map of the model, or of its conjugate when `m`
    /// reverses orientation). A portal thus sends a straight ray on from the model point of the
    /// partner wall, turned as the model map turns directions there, as a mirror reflects it
    /// across the tangent of its model circle; in a Euclidean room the map is the isometry
    /// itself.
    fn drawn_map(&self, curved: Space, m: &DMat3, reverses: bool, point: DVec3) -> DMat3 {
        let map = |z: Complex64| curved.to_model(*m * curved.to_ambient(z));
        let z0 = self.space.to_model(point);
        // ∂f/∂x by central differences: the derivative of a holomorphic f, and the a of an
        // antiholomorphic f(z0 + u) ≈ f(z0) + a·ū alike (the error is O(h²) + O(ε/h), about
        // 1e-10 relative).
        let h = 1e-5 * (1.0 + z0.norm());
        let a = (map(z0 + h) - map(z0 - h)) / (2.0 * h);
        let linear = if reverses {
            DMat3::from_cols(
                DVec3::new(a.re, a.im, 0.0),
                DVec3::new(a.im, -a.re, 0.0),
                DVec3::Z,
            )
        } else {
            DMat3::from_cols(
                DVec3::new(a.re, a.im, 0.0),
                DVec3::new(-a.im, a.re, 0.0),
                DVec3::Z,
            )
        };
        // Flat ambient points are (2x, 2y, 1) for the model point x + iy.
        let image = self.space.to_ambient(map(z0));
        let moved = linear * point;
        DMat3::from_cols(
            linear.x_axis,
            linear.y_axis,
            DVec3::new(image.x - moved.x, image.y - moved.y, 1.0),
        )
    }

    /// Whether a point of a portal wall lies on its solid frame: within the frame's width of
    /// the wall's ends (intrinsic length along the wall), of the floor or of the ceiling.
    pub fn in_portal_frame(&self, wall: usize, point: DVec3, height: f64) -> bool {
        let w = &self.walls[wall];
        let Some(portal) = w.portal else {
            return false;
        };
        if portal.frame <= 0.0 {
            return false;
        }
        if height < portal.frame || height > self.height - portal.frame {
            return true;
        }
        if w.closed || !w.length.is_finite() {
            return false;
        }
        let along = self.along(wall, point) * w.length;
        along < portal.frame || along > w.length - portal.frame
    }

    /// Where a ray from inside the room leaves it: the nearest of the floor, the ceiling and the
    /// walls. `None` when it never does (a horizontal ray running out through an ideal corner).
    pub fn exit(&self, ray: &Ray) -> Option<RoomHit> {
        let space = self.space;
        let mut best: Option<(f64, RoomSurface)> = None;
        if ray.sin_elevation > 0.0 {
            let s = ((self.height - ray.height) / ray.sin_elevation).max(0.0);
            best = Some((s, RoomSurface::Ceiling));
        } else if ray.sin_elevation < 0.0 {
            let s = (-ray.height / ray.sin_elevation).max(0.0);
            best = Some((s, RoomSurface::Floor));
        }
        let mut wall_cos_sin = None;
        if ray.cos_elevation > 0.0 {
            // The nearest wall by a key that grows with σ, so that only its crossing needs an
            // inverse function (`atanh` in H², `atan2` in S²).
            let mut nearest: Option<(f64, usize, WallCrossing)> = None;
            for (i, wall) in self.walls.iter().enumerate() {
                let (key, crossing) = match wall.drawn_in {
                    None => {
                        let (a, b) = (wall.form.dot(ray.origin), wall.form.dot(ray.direction));
                        let Some(key) = crossing_key(space, a, b) else {
                            continue;
                        };
                        (key, WallCrossing::Line(a, b))
                    }
                    Some(curved) => {
                        // Straight-ray mode: the room is flat, where the key is σ itself.
                        debug_assert_eq!(space.kappa(), 0.0, "curved walls are drawn in E²");
                        let Some(sigma) = self.model_crossing(curved.kappa(), wall.form, ray)
                        else {
                            continue;
                        };
                        (sigma, WallCrossing::Found(sigma))
                    }
                };
                if nearest.is_none_or(|(k, _, _)| key < k) {
                    nearest = Some((key, i, crossing));
                }
            }
            let sigma = nearest.and_then(|(_, i, crossing)| {
                let sigma = match crossing {
                    WallCrossing::Line(a, b) => line_crossing(space, a, b)?,
                    WallCrossing::Found(sigma) => sigma,
                };
                Some((sigma, i, crossing))
            });
            if let Some((sigma, i, crossing)) = sigma {
                let s = sigma / ray.cos_elevation;
                if best.is_none_or(|(t, _)| s < t) {
                    best = Some((s, RoomSurface::Wall(i)));
                    if let WallCrossing::Line(a, b) = crossing {
                        wall_cos_sin = crossing_cos_sin(space, a, b);
                    }
                }
            }
        }
        let (s, surface) = best?;
        let (point, tangent, height) = match (surface, wall_cos_sin) {
            // The wall's crossing knows C(σ) and S(σ) without σ: no second transcendental.
            (RoomSurface::Wall(_), Some((c, sn))) => (
                ray.origin * c + ray.direction * sn,
                ray.direction * c - ray.origin * (space.kappa() * sn),
                ray.height + s * ray.sin_elevation,
            ),
            _ => ray.point_and_tangent_at(space, s),
        };
        let height = match surface {
            RoomSurface::Floor => 0.0,
            RoomSurface::Ceiling => self.height,
            RoomSurface::Wall(_) => height.clamp(0.0, self.height),
        };
        let surface = match surface {
            RoomSurface::Wall(i) if !self.walls[i].same_line.is_empty() => {
                RoomSurface::Wall(self.wall_on_line_at(i, point))
            }
            other => other,
        };
        Some(RoomHit {
            s,
            surface,
            point,
            tangent,
            height,
        })
    }

    /// Of wall `i` and the walls on its line, the one whose stretch holds `point` (a point of
    /// the line): the crossing of walls that meet at a straight corner is the same for all of
    /// them, and only where it lies along the line tells them apart.
    fn wall_on_line_at(&self, i: usize, point: DVec3) -> usize {
        let inside = |w: usize| {
            let t = self.along(w, point);
            t.min(1.0 - t)
        };
        std::iter::once(i)
            .chain(self.walls[i].same_line.iter().copied())
            .max_by(|&a, &b| inside(a).total_cmp(&inside(b)))
            .unwrap_or(i)
    }

    /// Straight-ray mode: the horizontal distance σ along a flat ray at which it leaves the
    /// room across the model curve of the curved wall ν — the first root of the curve's
    /// quadratic in σ where it goes from inside to outside.
    fn model_crossing(&self, kappa: f64, nu: DVec3, ray: &Ray) -> Option<f64> {
        let flat = self.space;
        let o = flat.to_model(ray.origin);
        // Flat ambient coordinates are twice the model's: unit speed is half a model unit.
        let e = Complex64::new(ray.direction.x, ray.direction.y) * 0.5;
        let a = -kappa * nu.z * e.norm_sqr();
        let b =
            -2.0 * kappa * nu.z * (o.re * e.re + o.im * e.im) + 2.0 * (nu.x * e.re + nu.y * e.im);
        let c = model_curve(kappa, nu, o);
        let leaving = |sigma: f64| 2.0 * a * sigma + b < 0.0;
        let roots: [Option<f64>; 2] = if a.abs() <= 1e-15 * b.abs() {
            [(b != 0.0).then(|| -c / b), None]
        } else {
            let disc = b * b - 4.0 * a * c;
            if disc < 0.0 {
                return None;
            }
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            [Some(q / a), (q != 0.0).then(|| c / q)]
        };
        roots
            .into_iter()
            .flatten()
            .filter(|&sigma| sigma.is_finite() && sigma > -1e-12 && leaving(sigma))
            .map(|sigma| sigma.max(0.0))
            .min_by(f64::total_cmp)
    }

    /// The linear form of the geodesic that touches wall `wall` at its point `point` (the
    /// wall's own form, except in straight-ray mode, where a wall is a model circle and a
    /// mirror reflects across its tangent line). Positive inside, normalised.
    pub fn wall_form_at(&self, wall: usize, point: DVec3) -> DVec3 {
        let w = &self.walls[wall];
        let Some(curved) = w.drawn_in else {
            return w.form;
        };
        let z = self.space.to_model(point);
        let k = curved.kappa();
        let nu = w.form;
        let gradient = Complex64::new(
            -2.0 * k * nu.z * z.re + 2.0 * nu.x,
            -2.0 * k * nu.z * z.im + 2.0 * nu.y,
        );
        let n = gradient / gradient.norm();
        DVec3::new(n.re, n.im, -(n.re * point.x + n.im * point.y))
    }

    /// The room seen with straight rays (the seed's Fig. 8.1a): the same model picture — floor,
    /// ceiling, and walls drawn as the model curves of the curved walls — in the flat plane,
    /// whose ambient coordinates are (2x, 2y, 1) for the model point x + iy (so lengths agree
    /// with the curved plane's at the model's origin).
    pub fn flattened(&self) -> AnalyticRoom {
        let curved = self
            .walls
            .first()
            .and_then(|w| w.drawn_in)
            .unwrap_or(self.space);
        AnalyticRoom {
            space: Space::new(orbifold::Geometry::Euclidean),
            height: self.height,
            walls: self
                .walls
                .iter()
                .map(|w| RoomWall {
                    drawn_in: Some(curved),
                    // A portal's pairing is an isometry of the curved plane: in the flat
                    // picture it acts by its model map (`AnalyticRoom::drawn_map`).
                    ..w.clone()
                })
                .collect(),
        }
    }

    /// The fraction of wall `wall`'s length at which the wall point `point` lies.
    pub fn along(&self, wall: usize, point: DVec3) -> f64 {
        let w = &self.walls[wall];
        let (space, point) = match w.drawn_in {
            None => (self.space, point),
            Some(curved) => (curved, curved.to_ambient(self.space.to_model(point))),
        };
        let mut s = space.geodesic_parameter(w.start, w.tangent, point);
        if w.closed && s < 0.0 {
            s += std::f64::consts::TAU;
        }
        if w.length > 0.0 { s / w.length } else { 0.0 }
    }

    /// The mirror of wall `wall` at a point on it, if any.
    pub fn mirror_at(
        &self,
        wall: usize,
        point: DVec3,
        height: f64,
    ) -> Option<(usize, &MirrorRect)> {
        // Where along the wall the point is costs inverse hyperbolic or circular functions; a
        // mirror across the whole wall (every wall of a room of mirrors) does not need it.
        let mut along = None;
        self.walls[wall].mirrors.iter().enumerate().find(|(_, m)| {
            if !(m.bottom <= height && height <= m.top) {
                return false;
            }
            if m.from <= 0.0 && m.to >= 1.0 {
                return true;
            }
            let along = *along.get_or_insert_with(|| self.along(wall, point).clamp(0.0, 1.0));
            m.covers(along, height)
        })
    }

    /// Whether a point is inside the room (to `tolerance` in the walls' linear forms).
    pub fn contains(&self, point: DVec3, height: f64, tolerance: f64) -> bool {
        (-tolerance..=self.height + tolerance).contains(&height)
            && self.walls.iter().all(|w| match w.drawn_in {
                None => w.form.dot(point) >= -tolerance,
                Some(curved) => {
                    model_curve(curved.kappa(), w.form, self.space.to_model(point)) >= -tolerance
                }
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use orbifold::Geometry;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn crossing_keys_order_walls_as_their_crossings_do(
            g in 0usize..3,
            (a1, b1, a2, b2) in (-1.0f64..2.0, -2.0f64..2.0, -1.0f64..2.0, -2.0f64..2.0),
        ) {
            // The key exists exactly when the crossing does, and two walls' keys compare as
            // their σ do (`exit` picks the nearest wall by key, then finds only its σ).
            let space = Space::new([Geometry::Spherical, Geometry::Euclidean, Geometry::Hyperbolic][g]);
            let (k1, s1) = (crossing_key(space, a1, b1), line_crossing(space, a1, b1));
            let (k2, s2) = (crossing_key(space, a2, b2), line_crossing(space, a2, b2));
            prop_assert_eq!(k1.is_some(), s1.is_some());
            prop_assert_eq!(k2.is_some(), s2.is_some());
            if let (Some(k1), Some(k2), Some(s1), Some(s2)) = (k1, k2, s1, s2) {
                // Strictly ordered σ (beyond rounding) have strictly ordered keys.
                if s1 < s2 - 1e-12 {
                    prop_assert!(k1 < k2, "σ {s1} < {s2} but keys {k1} ≥ {k2}");
                }
                if s2 < s1 - 1e-12 {
                    prop_assert!(k2 < k1, "σ {s2} < {s1} but keys {k2} ≥ {k1}");
                }
            }
        }
    }

    proptest! {
        #[test]
        fn mirror_at_is_the_first_mirror_that_covers_the_point(
            g in 0usize..3,
            // Ends at, before and just after the wall's own, and points near them.
            rects in proptest::collection::vec((
                prop_oneof![Just(0.0), Just(-0.1), 0.0f64..0.1, 0.1f64..0.7],
                prop_oneof![Just(1.0), Just(1.1), 0.9f64..1.0, 0.3f64..0.9],
                -0.1f64..0.6, 0.4f64..1.1,
            ), 1..4),
            at in prop_oneof![0.0f64..0.1, 0.9f64..1.0, 0.0f64..1.0], height in 0.0f64..1.0,
        ) {
            // The shortcut for mirrors across the whole wall gives what the definition does:
            // the first mirror whose rectangle holds (along, height), along clamped to [0, 1].
            let signature = ["*235", "*2222", "*2223"][g];
            let layout = orbifold::layout::Layout::new(
                &signature.parse().unwrap(),
                &orbifold::layout::LayoutOptions::default(),
            )
            .unwrap();
            let mirrors: Vec<MirrorRect> = rects
                .iter()
                .map(|&(from, to, bottom, top)| MirrorRect {
                    from, to, bottom, top, reflectance: [0.5; 3],
                })
                .collect();
            let walls = vec![mirrors.clone(); layout.edges.len()];
            let room = AnalyticRoom::new(&layout, 1.0, None, &walls).unwrap();
            let mesher = orbifold::room::RoomMesher::new(&layout, &Default::default()).unwrap();
            let point = mesher.wall_point(0, at).unwrap();
            let along = room.along(0, point).clamp(0.0, 1.0);
            prop_assert!((along - at).abs() < 1e-9, "{along} {at}");
            let expected = mirrors.iter().position(|m| m.covers(along, height));
            prop_assert_eq!(room.mirror_at(0, point, height).map(|(i, _)| i), expected);
        }
    }

    proptest! {
        #[test]
        fn a_wall_s_cos_and_sin_are_those_of_its_crossing(
            g in 0usize..3,
            (a, b) in (-1.0f64..2.0, -2.0f64..2.0),
        ) {
            // What `exit` puts the wall's point and tangent together from, without σ.
            let space = Space::new([Geometry::Spherical, Geometry::Euclidean, Geometry::Hyperbolic][g]);
            let (Some(sigma), Some((c, s))) = (line_crossing(space, a, b), crossing_cos_sin(space, a, b)) else {
                return Ok(());
            };
            let (c0, s0) = space.cos_sin(sigma);
            // As close as σ's own rounding lets them be (its derivative grows as the ray
            // nears the line's asymptote in H²).
            let slack = 1e-14 * (1.0 + c0.abs() + s0.abs()).powi(2);
            prop_assert!((c - c0).abs() <= slack && (s - s0).abs() <= slack, "{c} {s} vs {c0} {s0}");
        }
    }

    #[test]
    fn crossing_keys_at_the_edges() {
        let s2 = Space::new(Geometry::Spherical);
        // On the line and moving along it: the sign of b's zero decides σ = π or 0, and the
        // key follows it; moving away: σ = π, the greatest key.
        assert_eq!(line_crossing(s2, 0.0, 0.0), Some(std::f64::consts::PI));
        assert_eq!(crossing_key(s2, 0.0, 0.0), Some(1.0));
        assert_eq!(line_crossing(s2, 0.0, -0.0), Some(0.0));
        assert_eq!(crossing_key(s2, 0.0, -0.0), Some(-1.0));
        assert_eq!(crossing_key(s2, 0.0, 1.0), Some(1.0));
        let h2 = Space::new(Geometry::Hyperbolic);
        // Asymptotic to the line: no crossing, no key.
        assert_eq!(crossing_key(h2, 1.0, -1.0), None);
        assert_eq!(line_crossing(h2, 1.0, -1.0), None);
    }
}
