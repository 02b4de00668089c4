//! Pictures of layouts as SVG (and PNG, rendered from the SVG): the model's boundary, the polygon
//! with each wall in its own colour drawn as a true geodesic arc, the corner orders, the
//! signature and χ, and the placement arrow (the seed's Fig. 5.2 and 6.11).

use std::fmt::Write;

use num_complex::Complex64;
use orbifold::Geometry;
use orbifold::layout::{Layout, Vertex};
use orbifold::space::{ModelGeodesic, Space};

use crate::tiling::{Model, project};

/// Colours for the walls, repeated when there are more walls.
const PALETTE: [&str; 10] = [
    "#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
    "#bcbd22", "#7f7f7f",
];

/// Maps model coordinates to pixels (y up in the model, down on screen).
struct View {
    centre: Complex64,
    scale: f64,
    size: f64,
}

impl View {
    fn fit(layout: &Layout, size: f64) -> View {
        let mut points: Vec<Complex64> = layout.vertices.iter().map(|v| v.position).collect();
        if layout.geometry != Geometry::Euclidean {
            points.extend([1.0, -1.0].map(|x| Complex64::new(x, 0.0)));
            points.extend([1.0, -1.0].map(|y| Complex64::new(0.0, y)));
        }
        let (mut lo, mut hi) = (points[0], points[0]);
        for p in &points {
            lo = Complex64::new(lo.re.min(p.re), lo.im.min(p.im));
            hi = Complex64::new(hi.re.max(p.re), hi.im.max(p.im));
        }
        let extent = (hi.re - lo.re).max(hi.im - lo.im).max(1e-9);
        View {
            centre: (lo + hi) / 2.0,
            scale: 0.84 * size / extent,
            size,
        }
    }

    fn px(&self, z: Complex64) -> (f64, f64) {
        let d = (z - self.centre) * self.scale;
        (self.size / 2.0 + d.re, self.size / 2.0 + 24.0 - d.im)
    }
}

/// A point on wall `i` between its corners, to say which arc of its circle is the side.
fn side_midpoint(layout: &Layout, space: Space, i: usize) -> Option<Complex64> {
    let n = layout.vertices.len();
    let (a, b) = (layout.vertices[i], layout.vertices[(i + 1) % n]);
    if n == 2 || a.ideal || b.ideal {
        // Lunes join antipodes, and ideal ends are infinitely far: use the wall's point nearest
        // the centre, which lies between the corners.
        return Some(match layout.edges[i].geodesic {
            ModelGeodesic::Circle { centre, radius } => {
                let towards = layout.centre - centre;
                centre + towards / towards.norm() * radius
            }
            ModelGeodesic::Line { point, .. } => point,
        });
    }
    // The geodesic midpoint: move a to the origin, halve the distance along the ray, move back.
    let to_origin = |z: Complex64| (z - a.position) / (1.0 + space.kappa() * a.position.conj() * z);
    let from_origin =
        |z: Complex64| (z + a.position) / (1.0 - space.kappa() * a.position.conj() * z);
    let image = to_origin(b.position);
    let d = space.distance(Complex64::new(0.0, 0.0), image);
    let half = image / image.norm() * space.tan(d / 4.0);
    let half = if space.kappa() == 0.0 {
        image / 2.0
    } else {
        half
    };
    Some(from_origin(half))
}

/// The SVG path command that draws wall `i` from its first corner to its second.
fn side_path(layout: &Layout, view: &View, i: usize, start: bool) -> String {
    let space = layout.space();
    let n = layout.vertices.len();
    let (a, b) = (
        layout.vertices[i].position,
        layout.vertices[(i + 1) % n].position,
    );
    let (ax, ay) = view.px(a);
    let (bx, by) = view.px(b);
    let mut path = if start {
        format!("M {ax:.2} {ay:.2} ")
    } else {
        String::new()
    };
    match (layout.edges[i].geodesic, side_midpoint(layout, space, i)) {
        (ModelGeodesic::Circle { centre, radius }, Some(mid)) if radius * view.scale < 1e6 => {
            let cross = (mid - a).re * (b - mid).im - (mid - a).im * (b - mid).re;
            let angle = |p: Complex64, q: Complex64| ((p - centre) / (q - centre)).arg().abs();
            let large = angle(a, mid) + angle(mid, b) > std::f64::consts::PI;
            let r = radius * view.scale;
            let _ = write!(
                path,
                "A {r:.2} {r:.2} 0 {} {} {bx:.2} {by:.2}",
                u8::from(large),
                u8::from(cross < 0.0)
            );
        }
        _ => {
            let _ = write!(path, "L {bx:.2} {by:.2}");
        }
    }
    path
}

fn order_label(v: &Vertex) -> String {
    v.order.to_string()
}

/// The SVG document of a layout, `size` pixels wide.
pub fn layout_svg(layout: &Layout, title: &str, size: u32) -> String {
    let size_f = f64::from(size);
    let view = View::fit(layout, size_f);
    let height = size + 24;
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{height}" viewBox="0 0 {size} {height}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">"#
    );
    let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        svg,
        r#"<text x="12" y="22" font-size="16">{}</text>"#,
        escape(title)
    );
    if layout.geometry != Geometry::Euclidean {
        let (cx, cy) = view.px(Complex64::new(0.0, 0.0));
        let _ = writeln!(
            svg,
            r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="{:.2}" fill="#f4f6fa" stroke="#888" stroke-width="1.5" stroke-dasharray="6 4"/>"##,
            view.scale
        );
    }
    let n = layout.vertices.len();
    if n == 0 {
        // `*`: the whole equator is the mirror.
        let (cx, cy) = view.px(Complex64::new(0.0, 0.0));
        let _ = writeln!(
            svg,
            r#"<circle cx="{cx:.2}" cy="{cy:.2}" r="{:.2}" fill="{}" fill-opacity="0.12" stroke="{}" stroke-width="4"/>"#,
            view.scale, PALETTE[0], PALETTE[0]
        );
    } else {
        let outline: String = (0..n)
            .map(|i| side_path(layout, &view, i, i == 0))
            .collect::<Vec<_>>()
            .join(" ");
        let _ = writeln!(
            svg,
            r##"<path d="{outline} Z" fill="#ffd9b3" fill-opacity="0.6" stroke="none"/>"##
        );
        for i in 0..n {
            let colour = PALETTE[i % PALETTE.len()];
            let _ = writeln!(
                svg,
                r#"<path d="{}" fill="none" stroke="{colour}" stroke-width="3.5" stroke-linecap="round"><title>wall {i}</title></path>"#,
                side_path(layout, &view, i, true)
            );
            if let Some(mid) = side_midpoint(layout, layout.space(), i) {
                let (mx, my) = view.px(mid);
                let (ox, oy) = outward(&view, layout, mid, 14.0);
                let _ = writeln!(
                    svg,
                    r#"<text x="{:.2}" y="{:.2}" font-size="12" fill="{colour}" text-anchor="middle" dominant-baseline="middle">{i}</text>"#,
                    mx + ox,
                    my + oy
                );
            }
        }
        for v in &layout.vertices {
            let (x, y) = view.px(v.position);
            let (ox, oy) = outward(&view, layout, v.position, 16.0);
            let _ = writeln!(
                svg,
                r#"<circle cx="{x:.2}" cy="{y:.2}" r="4" fill="black"/>"#
            );
            let _ = writeln!(
                svg,
                r#"<text x="{:.2}" y="{:.2}" font-size="15" font-weight="bold" text-anchor="middle" dominant-baseline="middle">{}</text>"#,
                x + ox,
                y + oy,
                escape(&order_label(v))
            );
        }
    }
    // The placement arrow: from the centre, in the heading direction.
    let (cx, cy) = view.px(layout.centre);
    let tip = (
        cx + 40.0 * layout.heading.cos(),
        cy - 40.0 * layout.heading.sin(),
    );
    let _ = writeln!(
        svg,
        r#"<g stroke="crimson" fill="crimson"><circle cx="{cx:.2}" cy="{cy:.2}" r="4"/><line x1="{cx:.2}" y1="{cy:.2}" x2="{:.2}" y2="{:.2}" stroke-width="3"/>{}</g>"#,
        tip.0,
        tip.1,
        arrow_head(tip, layout.heading)
    );
    svg.push_str("</svg>\n");
    svg
}

/// A pixel offset pointing away from the layout's centre, for labels.
fn outward(view: &View, layout: &Layout, z: Complex64, length: f64) -> (f64, f64) {
    let (x, y) = view.px(z);
    let (cx, cy) = view.px(layout.centre);
    let (dx, dy) = (x - cx, y - cy);
    let norm = (dx * dx + dy * dy).sqrt().max(1e-9);
    (dx / norm * length, dy / norm * length)
}

fn arrow_head(tip: (f64, f64), heading: f64) -> String {
    let back = |turn: f64| {
        let a = heading + std::f64::consts::PI + turn;
        (tip.0 + 12.0 * a.cos(), tip.1 - 12.0 * a.sin())
    };
    let (l, r) = (back(0.45), back(-0.45));
    format!(
        r#"<polygon points="{:.2},{:.2} {:.2},{:.2} {:.2},{:.2}"/>"#,
        tip.0, tip.1, l.0, l.1, r.0, r.1
    )
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Fonts given with [`add_font`], for SVG text where the system has none (a web page).
static ADDED_FONTS: std::sync::Mutex<Vec<std::sync::Arc<Vec<u8>>>> =
    std::sync::Mutex::new(Vec::new());

/// Adds a font (TrueType or OpenType bytes) for the text of the pictures [`svg_to_png`] renders,
/// after the system's. A page in the browser has no system fonts: the web studio gives egui's
/// own. The first font added becomes the generic `sans-serif` family that every picture's
/// font list ends with, when none of the families it names first is found.
///
/// ```
/// // Bytes that are not a font are ignored when a picture is rendered.
/// orbifold_picture::svg::add_font(vec![0, 1, 2]);
/// let png = orbifold_picture::svg::svg_to_png(
///     r#"<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"/>"#,
/// );
/// assert!(png.is_ok());
/// ```
pub fn add_font(data: Vec<u8>) {
    if let Ok(mut fonts) = ADDED_FONTS.lock() {
        fonts.push(std::sync::Arc::new(data));
    }
}

/// Renders an SVG document to pixels.
fn render(svg: &str) -> Result<resvg::tiny_skia::Pixmap, String> {
    use resvg::{tiny_skia, usvg};
    let mut options = usvg::Options::default();
    let fonts = options.fontdb_mut();
    fonts.load_system_fonts();
    let added = ADDED_FONTS.lock().map(|f| f.clone()).unwrap_or_default();
    for data in added {
        let before = fonts.len();
        fonts.load_font_source(usvg::fontdb::Source::Binary(data));
        let family = (fonts.len() > before)
            .then(|| {
                fonts
                    .faces()
                    .last()
                    .and_then(|f| f.families.first())
                    .map(|f| f.0.clone())
            })
            .flatten();
        let generic = fonts
            .family_name(&usvg::fontdb::Family::SansSerif)
            .to_string();
        let has_generic = fonts
            .faces()
            .any(|f| f.families.iter().any(|(name, _)| *name == generic));
        if let (Some(family), false) = (family, has_generic) {
            fonts.set_sans_serif_family(family);
        }
    }
    let tree = usvg::Tree::from_str(svg, &options)
        .map_err(|e| format!("cannot render the picture: {e}"))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| format!("cannot render a {}×{} picture", size.width(), size.height()))?;
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    Ok(pixmap)
}

/// Renders an SVG document to PNG bytes (text with the system's fonts, where it has any, and
/// those given with [`add_font`]).
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, String> {
    render(svg)?
        .encode_png()
        .map_err(|e| format!("cannot encode the PNG: {e}"))
}

/// An SVG of the tiles of a cover, each outlined by its geodesic arcs and filled by parity, in
/// the model of the layout (Poincaré disk, stereographic plane or Euclidean plane), moved so
/// that `center` is at the middle and magnified by `zoom`.
pub fn tiling_svg(
    layout: &Layout,
    tiles: &[orbifold::cover::Tile],
    title: &str,
    size: u32,
    center: Complex64,
    zoom: f64,
) -> String {
    use glam::{DMat3, DVec3};
    let space = layout.space();
    let size_f = f64::from(size);
    let extent = if layout.geometry == Geometry::Euclidean {
        4.0
    } else {
        1.0
    };
    let view = View {
        centre: Complex64::new(0.0, 0.0),
        scale: 0.46 * size_f * zoom / extent,
        size: size_f,
    };
    let recentre = orbifold::isometry::Isometry::translation(space, center)
        .inverse()
        .matrix();
    let k = space.kappa();
    let inverse_transpose = |m: &DMat3| {
        if k == 0.0 {
            m.inverse().transpose()
        } else {
            let g = DMat3::from_diagonal(DVec3::new(1.0, 1.0, k));
            (g * m.transpose() * g).transpose()
        }
    };
    let mut svg = String::new();
    let height = size + 24;
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{height}" viewBox="0 0 {size} {height}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">"#
    );
    let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        svg,
        r#"<text x="12" y="22" font-size="16">{}</text>"#,
        escape(title)
    );
    if layout.geometry != Geometry::Euclidean {
        let (cx, cy) = view.px(Complex64::new(0.0, 0.0));
        let _ = writeln!(
            svg,
            r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="{:.2}" fill="#eceef2" stroke="#888" stroke-width="1"/>"##,
            view.scale
        );
    }
    for tile in tiles {
        let m = recentre * tile.matrix;
        let walls = inverse_transpose(&m);
        let mut moved = layout.clone();
        for v in &mut moved.vertices {
            v.position = if v.ideal {
                space.ideal_to_model(m * DVec3::new(v.position.re, v.position.im, 1.0))
            } else {
                space.to_model(m * space.to_ambient(v.position))
            };
        }
        for e in &mut moved.edges {
            e.wall = walls * e.wall;
            e.geodesic = space.model_geodesic(e.wall);
        }
        moved.centre = space.to_model(m * space.to_ambient(layout.centre));
        let n = moved.vertices.len();
        if n < 2 {
            continue;
        }
        let outline: String = (0..n)
            .map(|i| side_path(&moved, &view, i, i == 0))
            .collect::<Vec<_>>()
            .join(" ");
        let fill = if tile.reflected { "#264653" } else { "#e9c46a" };
        let _ = writeln!(
            svg,
            r##"<path d="{outline} Z" fill="{fill}" stroke="#222" stroke-width="0.6"/>"##
        );
    }
    svg.push_str("</svg>\n");
    svg
}

/// The layout picture with a floor tessellation drawn over it: every triangle edge as a thin
/// line between its model points (edges are short geodesics, nearly straight at mesh scale).
pub fn mesh_svg(
    layout: &Layout,
    points: &[Complex64],
    triangles: &[[u32; 3]],
    title: &str,
    size: u32,
) -> String {
    let view = View::fit(layout, f64::from(size));
    let mut svg = layout_svg(layout, title, size);
    let end = svg.rfind("</svg>").unwrap_or(svg.len());
    let mut mesh = String::from(
        r##"<g fill="none" stroke="#334" stroke-width="0.5" stroke-opacity="0.75" stroke-linejoin="round">"##,
    );
    for t in triangles {
        let [a, b, c] = t.map(|i| view.px(points[i as usize]));
        let _ = write!(
            mesh,
            r#"<path d="M{:.2} {:.2}L{:.2} {:.2}L{:.2} {:.2}Z"/>"#,
            a.0, a.1, b.0, b.1, c.0, c.1
        );
    }
    mesh.push_str("</g>\n");
    svg.insert_str(end, &mesh);
    svg
}

/// `steps` + 1 points along edge `i` of `polygon`, in ambient coordinates: finite ends by
/// geodesic interpolation; towards an ideal end, along the Poincaré disk's geodesic from the
/// finite end, stopping just short of the circle at infinity; a lune's side (antipodal ends)
/// through its point nearest the centre, which lies between them (the middle point).
///
/// ```
/// use orbifold::pairing::FundamentalPolygon;
/// use orbifold_picture::svg::edge_samples;
/// let lune = FundamentalPolygon::new(&"55".parse().unwrap(), &Default::default()).unwrap();
/// let side = edge_samples(&lune, 0, 16);
/// assert_eq!(side.len(), 17);
/// // Its ends are antipodes, and its middle is a quarter turn from both.
/// assert!((side[0] + side[16]).length() < 1e-12 && side[8].dot(side[0]).abs() < 1e-12);
/// ```
pub fn edge_samples(
    polygon: &orbifold::pairing::FundamentalPolygon,
    i: usize,
    steps: u32,
) -> Vec<glam::DVec3> {
    let space = polygon.space();
    let e = &polygon.edges[i];
    let (Some(a), Some(b)) = (e.from, e.to) else {
        return Vec::new();
    };
    let (a, b) = (polygon.vertices[a], polygon.vertices[b]);
    let along = |p: glam::DVec3, q: glam::DVec3, n: u32| {
        (0..=n)
            .map(move |k| space.interpolate(p, q, f64::from(k) / f64::from(n)))
            .collect::<Vec<_>>()
    };
    let towards_ideal = |z: Complex64, w: Complex64| {
        let d = (w - z) / (1.0 - z.conj() * w);
        (0..=steps)
            .map(|k| {
                let zeta = d * (0.999 * f64::from(k) / f64::from(steps));
                space.to_ambient((zeta + z) / (1.0 + z.conj() * zeta))
            })
            .collect::<Vec<_>>()
    };
    match (a.ideal, b.ideal) {
        (false, false) if space.kappa() > 0.0 && a.ambient.dot(b.ambient) < -1.0 + 1e-9 => {
            let o = polygon.centre_ambient();
            let w = e.wall;
            let mid = (o - w * (w.dot(o) / w.length_squared())).normalize();
            let mut points = along(a.ambient, mid, steps / 2);
            points.extend(along(mid, b.ambient, steps / 2).into_iter().skip(1));
            points
        }
        (false, false) => along(a.ambient, b.ambient, steps),
        (false, true) => towards_ideal(a.position, b.position),
        (true, false) => {
            let mut p = towards_ideal(b.position, a.position);
            p.reverse();
            p
        }
        (true, true) => [a.position, b.position]
            .map(|z| space.to_ambient(z * 0.999))
            .to_vec(),
    }
}

/// Letters for the paired edges: an edge and its partner share one (a, b, c, …); mirrors none.
fn pairing_letters(polygon: &orbifold::pairing::FundamentalPolygon) -> Vec<Option<char>> {
    let partners: Vec<Option<usize>> = polygon
        .edges
        .iter()
        .map(|e| match e.kind {
            orbifold::pairing::EdgeKind::Paired { partner } => Some(partner),
            orbifold::pairing::EdgeKind::Mirror => None,
        })
        .collect();
    orbifold::pairing::pair_letters(&partners)
}

/// An SVG of the tiles of any orbifold group in a `model` of its plane (the Poincaré or Klein
/// disk or the upper half-plane, the stereographic plane or the sphere's front hemisphere, the
/// Euclidean plane), each tile filled by orientation, moved so that
/// `center` is at the middle and magnified by `zoom`, with the letter p in every tile large enough
/// to read (so rotations, reflections and glides show apart); the base tile's edges are drawn as in
/// textbooks: mirrors thick and blue, paired edges red with a shared letter and arrows showing
/// how the pairing glues them (opposite ways for a rotation or translation, the same way for a
/// glide reflection). A tile that holds the point at infinity of the stereographic plane is
/// outlined but not filled.
///
/// ```
/// use orbifold::cover::Bound;
/// use orbifold::pairing::cover::GroupCover;
/// use orbifold_picture::svg::group_tiling_svg;
/// let cover = GroupCover::enumerate(&"22×".parse().unwrap(), Bound::Depth(3), true).unwrap();
/// use orbifold_picture::tiling::Model;
/// let cover = GroupCover::enumerate(&"22×".parse().unwrap(), Bound::Depth(3), true).unwrap();
/// let svg = group_tiling_svg(&cover.polygon, &cover.tiles, Model::Euclidean, "pgg", 400, Default::default(), 1.0);
/// assert!(svg.contains("marker-end"));
/// ```
pub fn group_tiling_svg(
    polygon: &orbifold::pairing::FundamentalPolygon,
    tiles: &[orbifold::pairing::cover::GroupTile],
    model: Model,
    title: &str,
    size: u32,
    center: Complex64,
    zoom: f64,
) -> String {
    let space = polygon.space();
    let size_f = f64::from(size);
    let extent = if polygon.geometry == Geometry::Euclidean {
        4.0
    } else {
        1.0
    };
    let view = View {
        centre: Complex64::new(0.0, 0.0),
        scale: 0.46 * size_f * zoom / extent,
        size: size_f,
    };
    let recentre = orbifold::isometry::Isometry::translation(space, center)
        .inverse()
        .matrix();
    let edges: Vec<Vec<glam::DVec3>> = (0..polygon.edges.len())
        .map(|i| edge_samples(polygon, i, 16))
        .collect();
    let letters = letter_strokes(polygon);
    let mut svg = String::new();
    let height = size + 24;
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{height}" viewBox="0 0 {size} {height}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">"#
    );
    let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        svg,
        r##"<defs><marker id="arrow" viewBox="0 0 10 10" refX="5" refY="5" markerWidth="5" markerHeight="5" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="#c0392b"/></marker></defs>"##
    );
    draw_boundary(&mut svg, model, &view);
    let at = Screen {
        space,
        model,
        view: &view,
    };
    for tile in tiles {
        let m = recentre * tile.matrix;
        let Some((outline, extent)) = tile_outline(&at, &edges, m) else {
            continue;
        };
        let holds_infinity = model == Model::Stereographic
            && polygon.contains_ambient(m.inverse() * glam::DVec3::new(0.0, 0.0, -1.0), 0.0);
        let fill = match (holds_infinity, tile.reflected) {
            (true, _) => "none",
            (false, true) => "#264653",
            (false, false) => "#e9c46a",
        };
        let _ = writeln!(
            svg,
            r##"<path d="{outline} Z" fill="{fill}" stroke="#222" stroke-width="0.6"/>"##
        );
        if extent > 16.0 && !holds_infinity {
            let _ = writeln!(
                svg,
                r##"<path d="{}" fill="none" stroke="#c0392b" stroke-width="{:.1}"/>"##,
                letter_path(&at, &letters, m),
                (extent / 40.0).clamp(0.8, 3.0)
            );
        }
    }
    draw_pairings(&mut svg, polygon, &at, &edges, recentre);
    // The title last, on its own band, so that plane tilings do not cover it.
    let _ = writeln!(
        svg,
        r#"<rect width="100%" height="28" fill="white"/><text x="12" y="22" font-size="16">{}</text>"#,
        escape(title)
    );
    svg.push_str("</svg>\n");
    svg
}

/// Where ambient points land in an SVG picture: the plane, its model and the view's pixels.
struct Screen<'a> {
    space: Space,
    model: Model,
    view: &'a View,
}

impl Screen<'_> {
    /// The pixel of ambient point `p` and whether it is in view: a point behind the sphere is
    /// put on its rim (so an outline across the limb follows it), one off the hyperbolic plane
    /// (rounding at an ideal vertex) is `None`, and one far outside the picture is pulled in
    /// along its direction.
    fn px(&self, p: glam::DVec3) -> Option<((f64, f64), bool)> {
        let (s, front) = match project(self.space, self.model, p) {
            Some(s) => (s, true),
            None if self.model == Model::Sphere => {
                let r = p.x.hypot(p.y);
                (Complex64::new(p.x, p.y) / r.max(1e-300), false)
            }
            None => return None,
        };
        let far = 20.0 * self.view.size / self.view.scale;
        let s = if s.norm() > far || !s.is_finite() {
            s / s.norm() * far
        } else {
            s
        };
        let (x, y) = self.view.px(s);
        (x.is_finite() && y.is_finite()).then_some(((x, y), front))
    }

    /// The pixel of ambient point `p` when it is drawn where it is: in front of the sphere, on
    /// the plane, not pulled in from far outside the picture.
    fn exact(&self, p: glam::DVec3) -> Option<(f64, f64)> {
        let s = project(self.space, self.model, p)?;
        let far = 20.0 * self.view.size / self.view.scale;
        let (x, y) = self.view.px(s);
        (s.norm() <= far && x.is_finite() && y.is_finite()).then_some((x, y))
    }

    /// Continues `path` (whose last point is `last`) along an edge given by its sample points
    /// moved by `m`.
    ///
    /// A geodesic's image is a circle or a line in the conformal models (Poincaré disk,
    /// half-plane, stereographic and Euclidean planes) and a line in the Klein disk, so the
    /// circle through the images of the edge's two ends and its middle sample draws it exactly,
    /// as an SVG arc (a segment when it bows less than `flat` pixels). On the orthographic sphere a
    /// great circle's image is an ellipse: an edge wholly in front is its elliptical arc, and an
    /// edge the rim cuts is cut there ([`Screen::rim_cut`]). Where one of the three points is not
    /// drawn where it is, the samples are joined by straight segments.
    fn trace(
        &self,
        path: &mut String,
        last: &mut Option<(f64, f64)>,
        samples: &[glam::DVec3],
        m: glam::DMat3,
        flat: f64,
    ) {
        let n = samples.len();
        if n >= 3 {
            let three = [samples[0], samples[n / 2], samples[n - 1]].map(|p| m * p);
            let ends = three.map(|p| self.exact(p));
            // On the sphere the whole edge must be in front, or the rim cuts it.
            let front = self.model != Model::Sphere
                || samples
                    .iter()
                    .all(|&p| project(self.space, self.model, m * p).is_some());
            if let ([Some(a), Some(b), Some(c)], true) = (ends, front) {
                line_to(path, last, a);
                let arc = if self.model == Model::Sphere {
                    self.great_circle_arc(three, (a, b, c), flat)
                } else {
                    arc_to(a, b, c, flat)
                };
                path.push_str(&arc);
                *last = Some(c);
                return;
            }
            if self.model == Model::Sphere && self.rim_cut(path, last, three, flat) {
                return;
            }
        }
        for &p in samples {
            if let Some((xy, _)) = self.px(m * p) {
                line_to(path, last, xy);
            }
        }
    }

    /// Continues `path` along a geodesic of the orthographic sphere that the rim cuts, given by
    /// its ends and middle `[p, m, q]`; false (and nothing drawn) when the cut cannot be made
    /// exactly.
    ///
    /// The edge's great circle is p cos θ + w sin θ (w ⊥ p in its plane, towards m), whose
    /// depth z(θ) = p_z cos θ + w_z sin θ vanishes where it crosses the rim: at most twice
    /// along an edge. Between the crossings a piece in front is its elliptical arc
    /// ([`Screen::great_circle_arc`]); a piece behind is drawn where [`Screen::px`] puts its
    /// points, on the rim, radially: an arc of the rim's circle through the rim points of its
    /// ends and middle. Each piece is drawn as two arcs, of its halves.
    fn rim_cut(
        &self,
        path: &mut String,
        last: &mut Option<(f64, f64)>,
        [p, m, q]: [glam::DVec3; 3],
        flat: f64,
    ) -> bool {
        use std::f64::consts::{FRAC_PI_2, PI, TAU};
        let normal = p.cross(m);
        if normal.length() < 1e-9 {
            return false;
        }
        let w = normal.normalize().cross(p);
        let middle = m.dot(w).atan2(m.dot(p));
        // Antipodal ends (a lune's side) are told apart by the middle alone.
        let end = if p.dot(q) < -1.0 + 1e-9 {
            2.0 * middle
        } else {
            q.dot(w).atan2(q.dot(p)).rem_euclid(TAU)
        };
        let depth = glam::DVec2::new(p.z, w.z);
        if !(middle > 0.0 && end > middle && depth.length() > 1e-12) {
            return false;
        }
        let at = |t: f64| p * t.cos() + w * t.sin();
        let phase = w.z.atan2(p.z);
        let mut breaks = vec![0.0];
        for k in -2..=4 {
            let t = phase + FRAC_PI_2 + f64::from(k) * PI;
            if t > 1e-9 && t < end - 1e-9 {
                breaks.push(t);
            }
        }
        breaks.sort_by(f64::total_cmp);
        breaks.push(end);
        // Each piece in two halves: an arc of half its ellipse or circle (a piece between the
        // two crossings is one) has its centre poorly set by its rounded ends in SVG. In front
        // the halves of the parameter are those of the ellipse; behind, the rim's arc is halved
        // by its angle (radially, the points behind do not move evenly along the rim).
        let rim_angle = |v: glam::DVec3| (v.x.hypot(v.y) > 1e-9).then(|| v.y.atan2(v.x));
        let rim_px = |angle: f64| self.view.px(Complex64::from_polar(1.0, angle));
        let ellipse_px = |v: glam::DVec3| self.view.px(Complex64::new(v.x, v.y));
        let mut pieces = Vec::with_capacity(2 * breaks.len());
        for pair in breaks.windows(2) {
            let (t0, t1) = (pair[0], pair[1]);
            let half = (t0 + t1) / 2.0;
            if at(half).z > 0.0 {
                for (u0, u1) in [(t0, half), (half, t1)] {
                    let three = [u0, (u0 + u1) / 2.0, u1].map(at);
                    pieces.push((Some(three), three.map(ellipse_px)));
                }
                continue;
            }
            let [Some(a0), Some(am), Some(a1)] = [t0, half, t1].map(|t| rim_angle(at(t))) else {
                return false;
            };
            // The rim's arc from a0 to a1 that holds am.
            let ccw = (a1 - a0).rem_euclid(TAU);
            let span = if (am - a0).rem_euclid(TAU) <= ccw {
                ccw
            } else {
                ccw - TAU
            };
            for k in 0..2 {
                let start = a0 + span * f64::from(k) / 2.0;
                let three = [0.0, 0.25, 0.5].map(|f| rim_px(start + span * f));
                pieces.push((None, three));
            }
        }
        for (on, [a, b, c]) in pieces {
            line_to(path, last, a);
            let arc = match on {
                Some(three) => self.great_circle_arc(three, (a, b, c), flat),
                None => arc_to(a, b, c, flat),
            };
            path.push_str(&arc);
            *last = Some(c);
        }
        true
    }

    /// The SVG elliptical arc, on the orthographic sphere, from pixel `a` to `c` through `b`:
    /// the images of three points `on` of one great circle.
    ///
    /// The circle's plane has the normal n = p × q. Its image is the ellipse with the major
    /// axis along e₁ = n × ẑ (a diameter in the picture's plane, seen at full length) and the
    /// minor axis |n_z| times as long (the diameter e₂ = n × e₁, foreshortened). Stretching the
    /// picture along the minor axis turns the ellipse into a circle, and the arc's flags are
    /// those of the circle's arc there ([`arc_to`]; the stretch keeps the turning sense).
    fn great_circle_arc(
        &self,
        on: [glam::DVec3; 3],
        (a, b, c): ((f64, f64), (f64, f64), (f64, f64)),
        flat: f64,
    ) -> String {
        let normal = on[0].cross(on[1]).normalize();
        let axis = glam::DVec3::new(normal.y, -normal.x, 0.0);
        let squash = normal.z.abs();
        if !(axis.length() > 1e-9 && squash * self.view.scale > flat) {
            return format!("L{:.2} {:.2} ", c.0, c.1);
        }
        let axis = axis / axis.length();
        // The major axis on screen (y down), and the stretched coordinates of the three pixels.
        let (ux, uy) = (axis.x, -axis.y);
        let stretch = |(x, y): (f64, f64)| {
            let (dx, dy) = (x - a.0, y - a.1);
            (dx * ux + dy * uy, (dy * ux - dx * uy) / squash)
        };
        let Some(arc) = circle_arc(stretch(a), stretch(b), stretch(c), flat) else {
            return format!("L{:.2} {:.2} ", c.0, c.1);
        };
        let (rx, ry) = (self.view.scale, self.view.scale * squash);
        let rotation = uy.atan2(ux).to_degrees();
        format!(
            "A{rx:.2} {ry:.2} {rotation:.2} {} {} {:.2} {:.2} ",
            u8::from(arc.large),
            u8::from(arc.sweep),
            c.0,
            c.1
        )
    }
}

/// How far, in pixels, a tile's edge or a letter may bow before it is drawn as an arc rather than
/// a segment: a quarter pixel, which keeps deep tilings' files small.
const FLAT: f64 = 0.25;

/// Continues `path` to `xy` by a straight segment: a move when the path is empty, nothing when
/// `xy` is within half a pixel of the last point.
fn line_to(path: &mut String, last: &mut Option<(f64, f64)>, (x, y): (f64, f64)) {
    let command = match *last {
        None => "M",
        Some((lx, ly)) if (x - lx).hypot(y - ly) < 0.5 => return,
        Some(_) => "L",
    };
    let _ = write!(path, "{command}{x:.1} {y:.1} ");
    *last = Some((x, y));
}

/// The SVG command from pixel `a` to pixel `c` along the circle through `a`, `b` and `c` (the
/// arc that contains `b`), or a straight segment when `b` lies within `flat` pixels of the chord
/// or the circle is wider than a million pixels. A geodesic's image in a conformal model is such
/// a circle, so three of its points draw it exactly.
///
/// With y down, the arc turns the positive way (SVG's sweep flag 1) when a, b, c turn
/// counter-clockwise in pixel coordinates; it is the larger arc when the angle at b is acute
/// (the inscribed angle at b is half the arc away from b).
///
/// ```
/// use orbifold_picture::svg::arc_to;
/// // A half circle of radius 10 through its lowest point (y down), turning the positive way.
/// assert_eq!(arc_to((0.0, 0.0), (10.0, 10.0), (20.0, 0.0), 0.01), "A10.00 10.00 0 0 0 20.00 0.00 ");
/// assert_eq!(arc_to((0.0, 0.0), (10.0, 0.001), (20.0, 0.0), 0.01), "L20.00 0.00 ");
/// ```
pub fn arc_to(a: (f64, f64), b: (f64, f64), c: (f64, f64), flat: f64) -> String {
    match circle_arc(a, b, c, flat) {
        Some(arc) => format!(
            "A{r:.2} {r:.2} 0 {} {} {:.2} {:.2} ",
            u8::from(arc.large),
            u8::from(arc.sweep),
            c.0,
            c.1,
            r = arc.radius
        ),
        None => format!("L{:.2} {:.2} ", c.0, c.1),
    }
}

/// The circle through three pixels, as an SVG arc from the first to the third sees it.
struct CircleArc {
    radius: f64,
    /// The arc through the middle pixel is the larger one.
    large: bool,
    /// It turns the positive way (y down).
    sweep: bool,
}

/// The arc from `a` to `c` through `b` ([`arc_to`]), or `None` where a segment draws it.
fn circle_arc(a: (f64, f64), b: (f64, f64), c: (f64, f64), flat: f64) -> Option<CircleArc> {
    let (ab, bc, ca) = (
        (b.0 - a.0, b.1 - a.1),
        (c.0 - b.0, c.1 - b.1),
        (a.0 - c.0, a.1 - c.1),
    );
    let cross = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
    let chord = ca.0.hypot(ca.1);
    let radius = ab.0.hypot(ab.1) * bc.0.hypot(bc.1) * chord / (2.0 * cross.abs());
    if cross.abs() <= flat * chord || !radius.is_finite() || radius > 1e6 {
        return None;
    }
    Some(CircleArc {
        radius,
        large: (a.0 - b.0) * (c.0 - b.0) + (a.1 - b.1) * (c.1 - b.1) > 0.0,
        sweep: cross > 0.0,
    })
}

/// The model's boundary: the circle at infinity of the disks, the real axis of the half-plane,
/// the rim of the sphere and the equator of the stereographic plane; the plane itself shaded.
fn draw_boundary(svg: &mut String, model: Model, view: &View) {
    match model {
        Model::Euclidean => {}
        Model::HalfPlane => {
            // The real axis is where the Cayley map's i-shifted picture has height −1.
            let (_, y) = view.px(Complex64::new(0.0, -1.0));
            let _ = writeln!(
                svg,
                r##"<rect x="0" y="0" width="{:.2}" height="{y:.2}" fill="#eceef2"/><line x1="0" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="#888" stroke-width="1"/>"##,
                view.size, view.size
            );
        }
        Model::Poincare | Model::Klein | Model::Stereographic | Model::Sphere => {
            let (cx, cy) = view.px(Complex64::new(0.0, 0.0));
            let _ = writeln!(
                svg,
                r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="{:.2}" fill="#eceef2" stroke="#888" stroke-width="1"/>"##,
                view.scale
            );
        }
    }
}

/// The SVG path of a tile: its edges moved by `m` ([`Screen::trace`]), with points far outside
/// the picture pulled in; `None` for a tile that lies wholly outside the picture, behind the
/// sphere, or is under a pixel and a half across (near the circle at infinity), which keeps deep
/// hyperbolic pictures small. Also the tile's extent in pixels.
fn tile_outline(at: &Screen, edges: &[Vec<glam::DVec3>], m: glam::DMat3) -> Option<(String, f64)> {
    let view = at.view;
    let mut any_front = false;
    let points: Vec<(f64, f64)> = edges
        .iter()
        .flatten()
        .filter_map(|&p| at.px(m * p))
        .map(|(xy, front)| {
            any_front |= front;
            xy
        })
        .collect();
    if !any_front {
        return None;
    }
    let (lo, hi) = points.iter().fold(
        ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN)),
        |(lo, hi), &(x, y)| ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y))),
    );
    let outside = hi.0 < 0.0 || hi.1 < 0.0 || lo.0 > view.size || lo.1 > view.size + 24.0;
    let extent = (hi.0 - lo.0).max(hi.1 - lo.1);
    if points.is_empty() || outside || extent < 1.5 {
        return None;
    }
    let mut path = String::new();
    let mut last = None;
    for edge in edges {
        at.trace(&mut path, &mut last, edge, m, FLAT);
    }
    Some((path, extent))
}

/// The letter p about the polygon's centre, as ambient points of two strokes (a stem, and a
/// bowl at the top right), the same glyph as the raster pictures draw: carried to every tile it
/// shows rotations (p turned) and reflections or glides (p mirrored) apart.
fn letter_strokes(polygon: &orbifold::pairing::FundamentalPolygon) -> Vec<Vec<glam::DVec3>> {
    let space = polygon.space();
    let radius = orbifold::isometry::Isometry::translation_by(
        space,
        polygon.clearance().max(0.0),
        Complex64::new(1.0, 0.0),
    )
    .apply(Complex64::new(0.0, 0.0))
    .norm()
        * 0.85;
    let from_origin = orbifold::isometry::Isometry::translation(space, polygon.centre).matrix();
    let ambient = |z: Complex64| from_origin * space.to_ambient(z * radius);
    let stem = (0..=16)
        .map(|k| ambient(Complex64::new(-0.28, -0.8 + 1.4 * f64::from(k) / 16.0)))
        .collect();
    // 17 points each, the bowl's last the first again: `letter_path` draws them as arcs through
    // three of them where it can.
    let bowl = (0..=16)
        .map(|k| {
            let t = std::f64::consts::TAU * f64::from(k) / 16.0;
            ambient(Complex64::new(0.02, 0.2) + Complex64::from_polar(0.3, t))
        })
        .collect();
    vec![stem, bowl]
}

/// The SVG path of the letter's strokes moved by `m` (the points in view only).
///
/// The stem is a segment and the bowl a circle of the model about the polygon's centre, which
/// the isometries and the conformal models' maps (Möbius maps, similarities) carry to circles
/// or lines: there the stem is one arc through three of its points and the bowl two.
fn letter_path(at: &Screen, strokes: &[Vec<glam::DVec3>], m: glam::DMat3) -> String {
    let mut path = String::new();
    let conformal = !matches!(at.model, Model::Klein | Model::Sphere);
    for stroke in strokes {
        let closed = match (stroke.first(), stroke.last()) {
            (Some(a), Some(b)) => a.distance(*b) < 1e-9,
            _ => false,
        };
        let through: &[usize] = if closed {
            &[0, 4, 8, 12, 16]
        } else {
            &[0, 8, 16]
        };
        if conformal && stroke.len() == 17 {
            let points: Option<Vec<(f64, f64)>> =
                through.iter().map(|&k| at.exact(m * stroke[k])).collect();
            if let Some(p) = points {
                let _ = write!(path, "M{:.1} {:.1} ", p[0].0, p[0].1);
                for arc in p.windows(3).step_by(2) {
                    path.push_str(&arc_to(arc[0], arc[1], arc[2], FLAT));
                }
                continue;
            }
        }
        let mut first = true;
        for &p in stroke {
            let Some(((x, y), true)) = at.px(m * p) else {
                first = true;
                continue;
            };
            let _ = write!(path, "{}{x:.1} {y:.1} ", if first { "M" } else { "L" });
            first = false;
        }
    }
    path
}

/// The base tile's edges: mirrors thick and blue; paired edges red, each with its letter and an
/// arrow (an orientation-preserving pairing takes the partner's start to this edge's end, so the
/// arrows run opposite ways on the two edges; a glide keeps the direction).
fn draw_pairings(
    svg: &mut String,
    polygon: &orbifold::pairing::FundamentalPolygon,
    at: &Screen,
    edges: &[Vec<glam::DVec3>],
    recentre: glam::DMat3,
) {
    use orbifold::pairing::EdgeKind;
    let letters = pairing_letters(polygon);
    for (i, (e, points)) in polygon.edges.iter().zip(edges).enumerate() {
        if points.len() < 2 {
            continue;
        }
        let px: Vec<(f64, f64)> = points
            .iter()
            .filter_map(|&p| at.px(recentre * p))
            .map(|(xy, _)| xy)
            .collect();
        if px.len() < 2 {
            continue;
        }
        let (colour, width) = match e.kind {
            EdgeKind::Mirror => ("#1f6fd1", 3.5),
            EdgeKind::Paired { .. } => ("#c0392b", 2.2),
        };
        let mut line = String::new();
        at.trace(&mut line, &mut None, points, recentre, 0.01);
        let _ = writeln!(
            svg,
            r##"<path d="{}" fill="none" stroke="{colour}" stroke-width="{width}"/>"##,
            line.trim_end()
        );
        if let (EdgeKind::Paired { partner }, Some(letter)) = (e.kind, letters[i]) {
            let forward =
                orbifold::pairing::arrow_runs_forward(i, partner, e.reverses_orientation());
            let mid = px.len() / 2;
            let (a, b) = (px[mid.saturating_sub(1)], px[(mid + 1).min(px.len() - 1)]);
            let ((x0, y0), (x1, y1)) = if forward { (a, b) } else { (b, a) };
            let _ = writeln!(
                svg,
                r##"<line x1="{x0:.2}" y1="{y0:.2}" x2="{x1:.2}" y2="{y1:.2}" stroke="{colour}" stroke-width="2" marker-end="url(#arrow)"/>"##
            );
            // The letter outside the base tile, off the edge's middle away from the polygon's
            // centre, so that it never covers the tile's own motif.
            let (x, y) = px[mid];
            let Some(((cx, cy), _)) = at.px(recentre * polygon.centre_ambient()) else {
                continue;
            };
            let (dx, dy) = (x - cx, y - cy);
            let length = dx.hypot(dy).max(1e-9);
            let _ = writeln!(
                svg,
                r##"<text x="{:.2}" y="{:.2}" font-size="15" fill="{colour}" text-anchor="middle" dominant-baseline="central">{letter}</text>"##,
                x + 12.0 * dx / length,
                y + 12.0 * dy / length
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The centre of an SVG arc of radius r with no rotation, and its start angle and sweep,
    /// by the conversion of the SVG specification (SVG 1.1, appendix F.6.5).
    fn svg_arc_centre(
        a: (f64, f64),
        c: (f64, f64),
        r: f64,
        large: bool,
        sweep: bool,
    ) -> ((f64, f64), f64, f64) {
        let (x1, y1) = ((a.0 - c.0) / 2.0, (a.1 - c.1) / 2.0);
        let d2 = x1 * x1 + y1 * y1;
        let root = ((r * r - d2) / d2).max(0.0).sqrt();
        let sign = if large != sweep { 1.0 } else { -1.0 };
        let (cx1, cy1) = (sign * root * y1, -sign * root * x1);
        let centre = (cx1 + (a.0 + c.0) / 2.0, cy1 + (a.1 + c.1) / 2.0);
        let angle = |x: f64, y: f64| y.atan2(x);
        let theta = angle(x1 - cx1, y1 - cy1);
        let mut delta = angle(-x1 - cx1, -y1 - cy1) - theta;
        let tau = std::f64::consts::TAU;
        delta = delta.rem_euclid(tau);
        if !sweep && delta > 0.0 {
            delta -= tau;
        }
        (centre, theta, delta)
    }

    /// An SVG arc command with its start: (start, rx, ry, rotation in degrees, large, sweep,
    /// end).
    struct SvgArc {
        start: (f64, f64),
        radii: (f64, f64),
        rotation: f64,
        large: bool,
        sweep: bool,
        end: (f64, f64),
    }

    /// A piece of an SVG path: an arc, or a segment from one point to another.
    enum Piece {
        Arc(SvgArc),
        Segment((f64, f64), (f64, f64)),
    }

    impl Piece {
        /// How far a pixel is from the piece.
        fn distance(&self, (px, py): (f64, f64)) -> f64 {
            match self {
                Piece::Arc(arc) => arc.distance((px, py)),
                Piece::Segment(a, b) => {
                    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                    let t = (((px - a.0) * dx + (py - a.1) * dy) / (dx * dx + dy * dy).max(1e-300))
                        .clamp(0.0, 1.0);
                    (px - a.0 - t * dx).hypot(py - a.1 - t * dy)
                }
            }
        }
    }

    impl SvgArc {
        /// How far a pixel is from the arc: from its ellipse, when it lies within the swept
        /// angle (else infinitely far).
        fn distance(&self, (px, py): (f64, f64)) -> f64 {
            let (sin, cos) = self.rotation.to_radians().sin_cos();
            let (rx, ry) = self.radii;
            let unit = |(x, y): (f64, f64)| ((x * cos + y * sin) / rx, (-x * sin + y * cos) / ry);
            let (centre, theta, delta) = svg_arc_centre(
                unit(self.start),
                unit(self.end),
                1.0,
                self.large,
                self.sweep,
            );
            let (ux, uy) = unit((px, py));
            let tau = std::f64::consts::TAU;
            let slack = 0.1 / ry.min(rx);
            let along = ((uy - centre.1).atan2(ux - centre.0) - theta).rem_euclid(tau);
            let along = if delta < 0.0 { tau - along } else { along };
            let along = if along > tau - slack { 0.0 } else { along };
            if along > delta.abs() + slack {
                return f64::INFINITY;
            }
            ((ux - centre.0).hypot(uy - centre.1) - 1.0).abs() * ry.min(rx)
        }
    }

    /// The pieces of an SVG path made of M, L and A commands.
    fn parse_pieces(path: &str) -> Vec<Piece> {
        let mut arcs = Vec::new();
        let mut at = (0.0, 0.0);
        let mut words = path.split_whitespace();
        while let Some(word) = words.next() {
            let (command, first) = word.split_at(1);
            let number = |w: Option<&str>| w.unwrap().parse::<f64>().unwrap();
            match command {
                "M" => at = (number(Some(first)), number(words.next())),
                "L" => {
                    let to = (number(Some(first)), number(words.next()));
                    arcs.push(Piece::Segment(at, to));
                    at = to;
                }
                "A" => {
                    let rx = number(Some(first));
                    let [ry, rotation, large, sweep, x, y] = [(); 6].map(|_| number(words.next()));
                    arcs.push(Piece::Arc(SvgArc {
                        start: at,
                        radii: (rx, ry),
                        rotation,
                        large: large == 1.0,
                        sweep: sweep == 1.0,
                        end: (x, y),
                    }));
                    at = (x, y);
                }
                other => panic!("unexpected command {other} in {path}"),
            }
        }
        arcs
    }

    /// Text in a family only an added font has is drawn with that font (the web studio adds
    /// egui's, as a page has no system fonts).
    #[test]
    fn text_is_drawn_with_an_added_font() {
        let font = epaint_default_fonts::UBUNTU_LIGHT;
        let mut alone = resvg::usvg::fontdb::Database::new();
        alone.load_font_data(font.to_vec());
        let family = alone.faces().next().expect("a face").families[0].0.clone();
        let svg = |family: &str| {
            format!(
                r#"<svg xmlns="http://www.w3.org/2000/svg" width="160" height="40"><text x="4" y="30" font-family="{family}" font-size="28">Echoes</text></svg>"#
            )
        };
        let inked = |pixmap: resvg::tiny_skia::Pixmap| {
            pixmap.pixels().iter().filter(|p| p.alpha() > 128).count()
        };
        let before = inked(render(&svg("No Such Family")).unwrap());
        add_font(font.to_vec());
        let drawn = inked(render(&svg(&family)).unwrap());
        assert!(drawn > 100, "{family}: {drawn} pixels inked");
        // Where the system has no font at all (a page), the added one is the fallback too.
        if before == 0 {
            assert!(inked(render(&svg("No Such Family, sans-serif")).unwrap()) > 100);
        }
    }

    fn model_and_space(which: usize) -> (Model, Space) {
        let (model, geometry) = [
            (Model::Poincare, Geometry::Hyperbolic),
            (Model::Klein, Geometry::Hyperbolic),
            (Model::HalfPlane, Geometry::Hyperbolic),
            (Model::Stereographic, Geometry::Spherical),
            (Model::Euclidean, Geometry::Euclidean),
        ][which];
        (model, Space::new(geometry))
    }

    proptest! {
        /// On the orthographic sphere an edge wholly in front is drawn as its great circle's
        /// elliptical arc: undoing the arc's rotation and radii (as the SVG specification does,
        /// appendix F.6.5) puts 17 points of the geodesic on the unit circle, within the swept
        /// angle, to 0.05 pixel.
        #[test]
        fn front_edges_on_the_sphere_are_elliptical_arcs(
            (x1, y1, x2, y2) in (-0.7f64..0.7, -0.7f64..0.7, -0.7f64..0.7, -0.7f64..0.7),
        ) {
            let space = Space::new(Geometry::Spherical);
            let front = |x: f64, y: f64| glam::DVec3::new(x, y, (1.0 - x * x - y * y).sqrt());
            let (p, q) = (front(x1, y1), front(x2, y2));
            prop_assume!(p.distance(q) > 0.05);
            let samples: Vec<glam::DVec3> =
                (0..=16).map(|k| space.interpolate(p, q, f64::from(k) / 16.0)).collect();
            let view = View { centre: Complex64::new(0.0, 0.0), scale: 150.0, size: 400.0 };
            let at = Screen { space, model: Model::Sphere, view: &view };
            let mut path = String::new();
            at.trace(&mut path, &mut None, &samples, glam::DMat3::IDENTITY, 0.01);
            let pixels: Vec<(f64, f64)> =
                samples.iter().map(|&s| at.exact(s).expect("in front")).collect();
            let Some(arc) = path.find('A') else {
                // Seen edge on: a segment through the centre's image.
                let (a, c) = (pixels[0], pixels[16]);
                let (dx, dy) = (c.0 - a.0, c.1 - a.1);
                for &(px, py) in &pixels {
                    let off = ((px - a.0) * dy - (py - a.1) * dx).abs() / dx.hypot(dy);
                    prop_assert!(off < 0.1, "{}: {} px off", path, off);
                }
                return Ok(());
            };
            let numbers: Vec<f64> =
                path[arc + 1..].split_whitespace().map(|w| w.parse().unwrap()).collect();
            let [rx, ry, rotation, large, sweep, x, y] = numbers[..] else { panic!("{path}") };
            let (sin, cos) = rotation.to_radians().sin_cos();
            let unit = |(px, py): (f64, f64)| {
                ((px * cos + py * sin) / rx, (-px * sin + py * cos) / ry)
            };
            let (centre, theta, delta) =
                svg_arc_centre(unit(pixels[0]), unit((x, y)), 1.0, large == 1.0, sweep == 1.0);
            let slack = 0.05 / ry;
            for &pixel in &pixels {
                let (ux, uy) = unit(pixel);
                let d = (ux - centre.0).hypot(uy - centre.1);
                prop_assert!((d - 1.0).abs() < slack, "{}: {} off the ellipse", path, d - 1.0);
                let along = ((uy - centre.1).atan2(ux - centre.0) - theta)
                    .rem_euclid(std::f64::consts::TAU);
                let along = if delta < 0.0 { std::f64::consts::TAU - along } else { along };
                let along = if along > std::f64::consts::TAU - slack { 0.0 } else { along };
                prop_assert!(along <= delta.abs() + slack, "{}: outside the arc", path);
            }
        }

        /// On the orthographic sphere an edge the rim cuts is drawn in at most three pieces, each
        /// in two halves, not as a polyline: its pieces in front as elliptical arcs, its pieces behind along the
        /// rim where they are drawn (radially). 17 points of the geodesic, each where
        /// `Screen::px` draws it, lie on one of the drawn pieces (an arc placed as the SVG
        /// specification places it, appendix F.6.5, or a segment) within a tenth of a pixel (a
        /// path's first point is written to a tenth of a pixel).
        #[test]
        fn edges_the_rim_cuts_are_arcs_of_the_ellipse_and_the_rim(
            (t1, f1, t2, f2) in (0.0f64..6.3, 0.1f64..3.0, 0.0f64..6.3, 0.1f64..3.0),
        ) {
            let space = Space::new(Geometry::Spherical);
            let point = |t: f64, f: f64| {
                glam::DVec3::new(f.sin() * t.cos(), f.sin() * t.sin(), f.cos())
            };
            let (p, q) = (point(t1, f1), point(t2, f2));
            prop_assume!(p.distance(q) > 0.1 && p.dot(q) > -0.99);
            let samples: Vec<glam::DVec3> =
                (0..=16).map(|k| space.interpolate(p, q, f64::from(k) / 16.0)).collect();
            prop_assume!(samples.iter().any(|v| v.z < -1e-3));
            let view = View { centre: Complex64::new(0.0, 0.0), scale: 150.0, size: 400.0 };
            let at = Screen { space, model: Model::Sphere, view: &view };
            let mut path = String::new();
            at.trace(&mut path, &mut None, &samples, glam::DMat3::IDENTITY, 0.01);
            // At most three pieces of two halves (a segment where a half bows less than `flat`).
            let pieces = parse_pieces(&path);
            prop_assert!(!pieces.is_empty() && pieces.len() <= 6, "{}", path);
            for &v in &samples {
                let ((x, y), _) = at.px(v).expect("drawn");
                let off = pieces
                    .iter()
                    .map(|piece| piece.distance((x, y)))
                    .fold(f64::INFINITY, f64::min);
                prop_assert!(off < 0.1, "{}: ({}, {}) is {} px off", path, x, y, off);
            }
        }

        /// An edge drawn by `Screen::trace` in a conformal model or the Klein disk is the image
        /// of the geodesic: 17 points along it lie on the drawn arc (as SVG itself places the
        /// arc's centre) within 0.05 pixel (the path's numbers have two decimals), or within a
        /// tenth of a pixel of the drawn segment.
        #[test]
        fn edges_are_drawn_as_the_geodesics_images(
            which in 0usize..5,
            (r1, t1, r2, t2) in (0.0f64..0.8, 0.0f64..6.3, 0.0f64..0.8, 0.0f64..6.3),
        ) {
            let (model, space) = model_and_space(which);
            let z1 = Complex64::from_polar(r1, t1);
            let z2 = Complex64::from_polar(r2, t2);
            prop_assume!((z1 - z2).norm() > 0.05);
            let (p, q) = (space.to_ambient(z1), space.to_ambient(z2));
            let samples: Vec<glam::DVec3> =
                (0..=16).map(|k| space.interpolate(p, q, f64::from(k) / 16.0)).collect();
            let view = View { centre: Complex64::new(0.0, 0.0), scale: 150.0, size: 400.0 };
            let at = Screen { space, model, view: &view };
            let mut path = String::new();
            at.trace(&mut path, &mut None, &samples, glam::DMat3::IDENTITY, 0.01);
            let pixels: Vec<(f64, f64)> =
                samples.iter().map(|&s| at.exact(s).expect("in view")).collect();
            let (a, c) = (pixels[0], pixels[16]);
            let words: Vec<&str> = path.split_whitespace().collect();
            if let Some(arc) = path.find('A') {
                let numbers: Vec<f64> = path[arc + 1..]
                    .split_whitespace()
                    .map(|w| w.parse().unwrap())
                    .collect();
                let [r, _, _, large, sweep, x, y] = numbers[..] else {
                    panic!("{path}")
                };
                prop_assert!((x - c.0).abs() < 0.01 && (y - c.1).abs() < 0.01, "{}", path);
                let (centre, theta, delta) =
                    svg_arc_centre(a, (x, y), r, large == 1.0, sweep == 1.0);
                for &(px, py) in &pixels {
                    let d = (px - centre.0).hypot(py - centre.1);
                    prop_assert!((d - r).abs() < 0.05, "{:?} {}: {} off", model, path, d - r);
                    // Within the swept angle, from the start the way the arc turns.
                    let along = ((py - centre.1).atan2(px - centre.0) - theta)
                        .rem_euclid(std::f64::consts::TAU);
                    let along = if delta < 0.0 { std::f64::consts::TAU - along } else { along };
                    // Within 0.05 pixel of the ends, as the path's numbers are rounded.
                    let slack = 0.05 / r;
                    let along = if along > std::f64::consts::TAU - slack { 0.0 } else { along };
                    prop_assert!(along <= delta.abs() + slack, "{:?} {}: outside the arc", model, path);
                }
            } else {
                prop_assert!(words.len() == 4 && words[2].starts_with('L'), "{}", path);
                let (dx, dy) = (c.0 - a.0, c.1 - a.1);
                let length = dx.hypot(dy);
                for &(px, py) in &pixels {
                    let off = ((px - a.0) * dy - (py - a.1) * dx).abs() / length;
                    prop_assert!(off < 0.1, "{:?} {}: {} px off the segment", model, path, off);
                }
            }
        }
    }
}
