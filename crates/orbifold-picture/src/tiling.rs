//! Pictures of the universal cover of a kaleidoscopic orbifold.
//!
//! The raster renderer folds every pixel back into the base polygon by repeated reflection (the
//! reverse pixel lookup): while the point lies outside some wall, reflect it in that wall. Each
//! reflection crosses exactly one wall separating the point from the base tile, so the number of
//! reflections is the tile's word length (its depth) and its parity is the tile's orientation.
//! Tile edges are drawn where the folded point is within a pixel of a wall, with the pixel's
//! coverage computed from that distance (analytic antialiasing, one sample per pixel). A motif
//! image placed over the base polygon is read at the folded point, so it is carried to every
//! tile and mirrored in the odd ones.

use glam::DVec3;
use num_complex::Complex64;
use orbifold::Geometry;
use orbifold::layout::Layout;
use orbifold::space::Space;
use rayon::prelude::*;

/// The view of the plane the picture shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// The Poincaré disk (hyperbolic; conformal).
    Poincare,
    /// The Klein disk (hyperbolic; geodesics are straight).
    Klein,
    /// The upper half-plane (hyperbolic; conformal).
    HalfPlane,
    /// The stereographic plane (spherical; conformal).
    Stereographic,
    /// An orthographic view of the sphere's front hemisphere.
    Sphere,
    /// The Euclidean plane.
    Euclidean,
}

impl Model {
    /// The models that show a geometry.
    pub fn shows(self, geometry: Geometry) -> bool {
        matches!(
            (self, geometry),
            (
                Model::Poincare | Model::Klein | Model::HalfPlane,
                Geometry::Hyperbolic
            ) | (Model::Stereographic | Model::Sphere, Geometry::Spherical)
                | (Model::Euclidean, Geometry::Euclidean)
        )
    }

    /// The natural model of a geometry.
    pub fn default_for(geometry: Geometry) -> Model {
        match geometry {
            Geometry::Hyperbolic => Model::Poincare,
            Geometry::Spherical => Model::Stereographic,
            Geometry::Euclidean => Model::Euclidean,
        }
    }
}

/// How tiles are coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coloring {
    /// Two colours: orientation-preserving and reversing tiles.
    Parity,
    /// By word length.
    Depth,
    /// By the last wall crossed on the way from the base.
    Wall,
}

/// A picture's framing and style.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// The model.
    pub model: Model,
    /// Width and height in pixels.
    pub size: u32,
    /// The model point (of the standard model of the geometry) shown at the picture's centre;
    /// the view moves by the translation that brings it there.
    pub center: Complex64,
    /// Magnification: 1 shows the whole disk (or, in the plane, a square 2 model units wide).
    pub zoom: f64,
    /// Colouring of the tiles.
    pub coloring: Coloring,
    /// Draw the tiles' edges.
    pub edges: bool,
    /// Reflections after which a pixel is given up (near ideal corners and the boundary).
    pub max_depth: u32,
}

impl View {
    /// Whether this view can show a plane of `geometry`: its model shows that plane, its zoom
    /// is a positive number, and in the Poincaré disk its centre lies inside the disk.
    pub fn check(&self, geometry: orbifold::Geometry) -> Result<(), String> {
        if !self.model.shows(geometry) {
            return Err(format!(
                "the {:?} model does not show the {} plane",
                self.model, geometry
            ));
        }
        if !(self.zoom.is_finite() && self.zoom > 0.0) {
            return Err(format!(
                "the zoom must be a positive number, not {}",
                self.zoom
            ));
        }
        if geometry == orbifold::Geometry::Hyperbolic && self.center.norm() >= 1.0 {
            return Err("the view centre must lie inside the Poincaré disk".into());
        }
        Ok(())
    }

    /// The default view of a geometry at the given size.
    pub fn new(geometry: Geometry, size: u32) -> Self {
        View {
            model: Model::default_for(geometry),
            size,
            center: Complex64::new(0.0, 0.0),
            zoom: 1.0,
            coloring: Coloring::Parity,
            edges: true,
            max_depth: 500,
        }
    }
}

/// An image placed over the base polygon's bounding box (in the standard model).
#[derive(Clone, Debug)]
pub struct Motif {
    /// RGBA pixels, row by row.
    pub rgba: Vec<u8>,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// A rendered picture: RGBA pixels, row by row.
#[derive(Clone, Debug)]
pub struct Picture {
    /// RGBA pixels.
    pub rgba: Vec<u8>,
    /// Width and height.
    pub size: u32,
}

/// What the renderer needs of the polygon, in ambient coordinates.
struct Fold {
    space: Space,
    walls: Vec<DVec3>,
    /// For each wall ν the vector n = (ν₁, ν₂, κν₃) with ν·n = 1: the reflection is p − 2(ν·p)n.
    normals: Vec<DVec3>,
    /// The motif's frame: the base polygon's bounding box in model coordinates.
    frame: (Complex64, Complex64),
    /// The distance from the polygon's centre to its nearest wall: pixels much larger than this
    /// cover many tiles and are shaded as such, without folding.
    inradius: f64,
}

impl Fold {
    fn new(layout: &Layout) -> Self {
        let space = layout.space();
        let walls: Vec<DVec3> = layout.edges.iter().map(|e| e.wall).collect();
        let normals = walls
            .iter()
            .map(|w| DVec3::new(w.x, w.y, space.kappa() * w.z))
            .collect();
        let mut lo = Complex64::new(f64::INFINITY, f64::INFINITY);
        let mut hi = -lo;
        for v in &layout.vertices {
            lo = Complex64::new(lo.re.min(v.position.re), lo.im.min(v.position.im));
            hi = Complex64::new(hi.re.max(v.position.re), hi.im.max(v.position.im));
        }
        if layout.vertices.len() < 3 {
            (lo, hi) = (Complex64::new(-1.0, -1.0), Complex64::new(1.0, 1.0));
        }
        let centre = space.to_ambient(layout.centre);
        let inradius = space.asin(
            walls
                .iter()
                .map(|w| w.dot(centre))
                .fold(f64::INFINITY, f64::min)
                .max(0.0),
        );
        Fold {
            space,
            walls,
            normals,
            frame: (lo, hi),
            inradius,
        }
    }

    /// Folds `p` into the base polygon: (folded point, reflections, last wall), or `None` when
    /// it takes more than `limit` reflections.
    fn fold(&self, mut p: DVec3, limit: u32) -> Option<(DVec3, u32, usize)> {
        let (mut count, mut last) = (0u32, usize::MAX);
        'reflect: loop {
            // Reflect in any wall the point lies outside of: each reflection crosses exactly one
            // wall between the point and the base tile, whichever is chosen. The reflection is
            // p − 2(ν·p) n, reusing the value just computed.
            let tolerance = -1e-12 * p.z.abs().max(1.0);
            for (i, (w, n)) in self.walls.iter().zip(&self.normals).enumerate() {
                let value = w.dot(p);
                if value < tolerance && i != last {
                    if count >= limit {
                        return None;
                    }
                    p -= 2.0 * value * *n;
                    count += 1;
                    last = i;
                    continue 'reflect;
                }
            }
            return Some((p, count, last));
        }
    }

    /// The intrinsic distance from a point of the base polygon to its nearest wall.
    fn wall_distance(&self, p: DVec3) -> f64 {
        let nearest = self
            .walls
            .iter()
            .map(|w| w.dot(p))
            .fold(f64::INFINITY, f64::min);
        self.space.asin(nearest.max(0.0))
    }
}

/// Renders the cover of `layout` as seen in `view`.
///
/// ```
/// use orbifold_picture::tiling::{render, View};
/// use orbifold::layout::{Layout, LayoutOptions};
/// let layout = Layout::new(&"*237".parse().unwrap(), &LayoutOptions::default()).unwrap();
/// let picture = render(&layout, &View::new(layout.geometry, 64), None).unwrap();
/// assert_eq!(picture.rgba.len(), 64 * 64 * 4);
/// ```
pub fn render(layout: &Layout, view: &View, motif: Option<&Motif>) -> Result<Picture, String> {
    if !layout.is_kaleidoscopic() {
        // A room layout with portals: its group's tiling, folded through the pairings.
        let polygon = orbifold::pairing::FundamentalPolygon::from_layout(
            layout.symbol.clone(),
            layout.clone(),
        );
        return crate::group::render_group(&polygon, view, motif);
    }
    view.check(layout.geometry)?;
    let fold = Fold::new(layout);
    let space = fold.space;
    let recentre = orbifold::isometry::Isometry::translation(space, view.center);
    let size = view.size as usize;
    let mut rgba = vec![0u8; size * size * 4];
    rgba.par_chunks_mut(size * 4)
        .enumerate()
        .for_each(|(j, row)| {
            for i in 0..size {
                let colour = pixel(&fold, view, &recentre, motif, i, j);
                row[i * 4..i * 4 + 4].copy_from_slice(&colour);
            }
        });
    Ok(Picture {
        rgba,
        size: view.size,
    })
}

const BACKGROUND: [u8; 4] = [255, 255, 255, 255];
const OUTSIDE: [u8; 4] = [236, 238, 242, 255];
/// Pixels that cover many tiles: mostly edge colour.
const DENSE: [u8; 4] = [70, 70, 80, 255];
const EDGE: [f64; 3] = [40.0, 40.0, 48.0];
pub(crate) const PALETTE: [[f64; 3]; 8] = [
    [231.0, 111.0, 81.0],
    [42.0, 157.0, 143.0],
    [233.0, 196.0, 106.0],
    [38.0, 70.0, 83.0],
    [244.0, 162.0, 97.0],
    [138.0, 177.0, 125.0],
    [131.0, 56.0, 236.0],
    [200.0, 200.0, 200.0],
];

/// The ambient point under screen point `s` (in units of half the picture), or `None` outside
/// the model.
pub(crate) fn unproject(space: Space, model: Model, s: Complex64) -> Option<DVec3> {
    let z = match model {
        Model::Poincare | Model::Stereographic | Model::Euclidean => s,
        Model::Klein => {
            let r2 = s.norm_sqr();
            if r2 >= 1.0 {
                return None;
            }
            s / (1.0 + (1.0 - r2).sqrt())
        }
        Model::HalfPlane => {
            // The picture shows x ∈ [−1, 1], y ∈ [0, 2]; the Cayley map takes i to 0.
            let w = Complex64::new(s.re, s.im + 1.0);
            if w.im <= 0.0 {
                return None;
            }
            (w - Complex64::i()) / (w + Complex64::i())
        }
        Model::Sphere => {
            let r2 = s.norm_sqr();
            if r2 > 1.0 {
                return None;
            }
            return Some(DVec3::new(s.re, s.im, (1.0 - r2).sqrt()));
        }
    };
    if space.kappa() < 0.0 && z.norm_sqr() >= 1.0 {
        return None;
    }
    Some(space.to_ambient(z))
}

/// The screen point (in units of half the picture) of the ambient point `p`: the inverse of
/// the picture's unprojection. `None` off the model: behind the sphere's front hemisphere, or
/// outside the hyperbolic plane.
///
/// ```
/// use glam::DVec3;
/// use num_complex::Complex64;
/// use orbifold::{Geometry, space::Space};
/// use orbifold_picture::tiling::{Model, project};
/// let h2 = Space::new(Geometry::Hyperbolic);
/// // The half-plane picture puts i, the image of the disk's centre, in the middle.
/// let s = project(h2, Model::HalfPlane, DVec3::new(0.0, 0.0, 1.0)).unwrap();
/// assert!(s.norm() < 1e-12);
/// // Straight geodesics in the Klein disk: the model point 0.5 is at 0.8.
/// let p = h2.to_ambient(Complex64::new(0.5, 0.0));
/// assert!((project(h2, Model::Klein, p).unwrap() - Complex64::new(0.8, 0.0)).norm() < 1e-12);
/// ```
pub fn project(space: Space, model: Model, p: DVec3) -> Option<Complex64> {
    if model == Model::Sphere {
        return (p.z >= 0.0).then(|| Complex64::new(p.x, p.y));
    }
    let z = space.to_model(p);
    if space.kappa() < 0.0 && (z.norm_sqr() >= 1.0 || z.is_nan()) {
        return None;
    }
    Some(match model {
        Model::Poincare | Model::Stereographic | Model::Euclidean | Model::Sphere => z,
        Model::Klein => z * (2.0 / (1.0 + z.norm_sqr())),
        // The Cayley map, z ↦ i(1 + z)/(1 − z), moved down by i (as `unproject` moves up).
        Model::HalfPlane => Complex64::i() * (1.0 + z) / (1.0 - z) - Complex64::i(),
    })
}

/// Pixel (i, j)'s point on the plane (ambient) and its intrinsic size: from the conformal
/// factor in the conformal models, numerically (half a pixel to the right) in the others;
/// `None` where the pixel is off the model. Shared by the reflection and the group pictures.
pub(crate) fn pixel_point(space: Space, view: &View, i: usize, j: usize) -> Option<(DVec3, f64)> {
    let half = f64::from(view.size) / 2.0;
    let screen = |x: f64, y: f64| Complex64::new((x - half) / half, (half - y) / half) / view.zoom;
    let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
    let s = screen(x, y);
    let p = unproject(space, view.model, s)?;
    let model_pixel = 1.0 / (half * view.zoom);
    let pixel_size = match view.model {
        Model::Poincare | Model::Stereographic | Model::Euclidean => {
            space.conformal_factor(s) * model_pixel
        }
        _ => unproject(space, view.model, screen(x + 0.5, y))
            .map_or(f64::INFINITY, |q| 2.0 * intrinsic_distance(space, p, q)),
    };
    Some((p, pixel_size))
}

fn pixel(
    fold: &Fold,
    view: &View,
    recentre: &orbifold::isometry::Isometry,
    motif: Option<&Motif>,
    i: usize,
    j: usize,
) -> [u8; 4] {
    let space = fold.space;
    let Some((p, pixel_size)) = pixel_point(space, view, i, j) else {
        return BACKGROUND;
    };
    if pixel_size > 2.0 * fold.inradius {
        // Many tiles under one pixel (near the boundary): their edges dominate.
        return DENSE;
    }
    let p = recentre.apply_ambient(p);
    let Some((folded, depth, last)) = fold.fold(p, view.max_depth) else {
        return OUTSIDE;
    };
    let base = match motif {
        Some(m) => sample(m, fold, space.to_model(folded)),
        None => match view.coloring {
            Coloring::Parity => {
                if depth % 2 == 0 {
                    PALETTE[2]
                } else {
                    PALETTE[3]
                }
            }
            Coloring::Depth => shade(depth),
            Coloring::Wall => PALETTE[if last == usize::MAX { 7 } else { last % 7 }],
        },
    };
    let colour = if view.edges {
        let distance_px = fold.wall_distance(folded) / pixel_size;
        let coverage = (1.3 - distance_px).clamp(0.0, 1.0);
        [0, 1, 2].map(|c| base[c] * (1.0 - coverage) + EDGE[c] * coverage)
    } else {
        base
    };
    [colour[0] as u8, colour[1] as u8, colour[2] as u8, 255]
}

pub(crate) fn intrinsic_distance(space: Space, p: DVec3, q: DVec3) -> f64 {
    let z = space.to_model(p);
    let w = space.to_model(q);
    space.distance(z, w)
}

pub(crate) fn shade(depth: u32) -> [f64; 3] {
    let t = (f64::from(depth) / 12.0).min(1.0);
    let (a, b) = (PALETTE[2], PALETTE[3]);
    [0, 1, 2].map(|c| a[c] * (1.0 - t) + b[c] * t)
}

fn sample(motif: &Motif, fold: &Fold, z: Complex64) -> [f64; 3] {
    sample_frame(motif, fold.frame, z)
}

/// The motif's colour at model point `z`, the motif stretched over the box `frame` (lo, hi).
pub(crate) fn sample_frame(motif: &Motif, frame: (Complex64, Complex64), z: Complex64) -> [f64; 3] {
    let (lo, hi) = frame;
    let u = ((z.re - lo.re) / (hi.re - lo.re)).clamp(0.0, 1.0);
    let v = ((hi.im - z.im) / (hi.im - lo.im)).clamp(0.0, 1.0);
    let x = ((u * f64::from(motif.width)) as u32).min(motif.width - 1);
    let y = ((v * f64::from(motif.height)) as u32).min(motif.height - 1);
    let k = ((y * motif.width + x) * 4) as usize;
    [0, 1, 2].map(|c| f64::from(motif.rgba[k + c]))
}

/// Folds a model point of the plane into the base polygon by reflections in its walls: the
/// folded point, the number of reflections (the depth of the tile containing the point) and the
/// last wall reflected in; `None` after `limit` reflections.
///
/// ```
/// use num_complex::Complex64;
/// use orbifold::layout::{Layout, LayoutOptions};
/// use orbifold_picture::tiling::fold_point;
/// let layout = Layout::new(&"*2222222".parse().unwrap(), &LayoutOptions::default()).unwrap();
/// let (inside, depth, _) = fold_point(&layout, Complex64::new(0.0, 0.0), 100).unwrap();
/// assert_eq!((inside, depth), (Complex64::new(0.0, 0.0), 0));
/// ```
pub fn fold_point(
    layout: &Layout,
    z: Complex64,
    limit: u32,
) -> Option<(Complex64, u32, Option<usize>)> {
    let fold = Fold::new(layout);
    let (p, depth, last) = fold.fold(fold.space.to_ambient(z), limit)?;
    Some((
        fold.space.to_model(p),
        depth,
        (last != usize::MAX).then_some(last),
    ))
}
