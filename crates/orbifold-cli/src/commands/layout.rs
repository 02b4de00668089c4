//! `orbifold layout`: the polygon of a signature, as text, JSON, SVG or PNG. Kaleidoscopic
//! signatures are laid out as mirror polygons; every other good orbifold symbol gets a
//! fundamental polygon with side pairings (`orbifold::pairing`, docs/orbifolds.md).

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use glam::DMat3;
use num_complex::Complex64;
use orbifold::layout::{Edge, Layout, LayoutOptions, Shape, Vertex};
use orbifold::pairing::{self, Cycle, EdgeKind, FundamentalPolygon};
use orbifold::space::ModelGeodesic;
use orbifold::{OrbifoldSymbol, Signature};
use serde::Serialize;

use crate::args::{LayoutArgs, ShapeArg};
use crate::error::CliError;
use crate::output::{self, write_atomic};
use crate::report::OrderJson;
use orbifold_picture::svg as picture;

pub fn run(args: &LayoutArgs) -> Result<(), CliError> {
    let signature = match args.signature.parse::<Signature>() {
        Ok(signature) => signature,
        Err(e) => match args.signature.parse::<OrbifoldSymbol>() {
            Ok(symbol) if symbol.as_kaleidoscopic().is_none() => {
                return run_paired(args, &symbol);
            }
            _ => return Err(CliError::Input(format!("{e}\n{}", e.snippet()))),
        },
    };
    let options = options(args)?;
    let layout = Layout::new(&signature, &options).map_err(|e| CliError::Input(e.to_string()))?;
    if let Some(path) = &args.output {
        draw(&layout, path, args.size)?;
    }
    let mut out = output::stdout();
    if args.json {
        let polygon = FundamentalPolygon::from_layout(signature.clone().into(), layout.clone());
        serde_json::to_writer_pretty(&mut out, &LayoutJson::new(&layout, &options, &polygon))?;
        writeln!(out)?;
    } else {
        write_text(&mut out, &layout)?;
        if let Some(path) = &args.output {
            writeln!(out, "wrote {}", path.display())?;
        }
    }
    out.flush()?;
    Ok(())
}

/// A symbol with cones, handles, cross-caps or several boundaries: its polygon with pairings.
fn run_paired(args: &LayoutArgs, symbol: &OrbifoldSymbol) -> Result<(), CliError> {
    let options = options(args)?;
    let polygon =
        FundamentalPolygon::new(symbol, &options).map_err(|e| CliError::Input(e.to_string()))?;
    if let Some(path) = &args.output {
        draw_paired(&polygon, path, args.size)?;
    }
    let mut out = output::stdout();
    if args.json {
        serde_json::to_writer_pretty(&mut out, &PolygonJson::new(&polygon, &options))?;
        writeln!(out)?;
    } else {
        write_paired_text(&mut out, &polygon)?;
        if let Some(path) = &args.output {
            writeln!(out, "wrote {}", path.display())?;
        }
    }
    out.flush()?;
    Ok(())
}

fn options(args: &LayoutArgs) -> Result<LayoutOptions, CliError> {
    let shape = match (&args.params, args.shape) {
        (Some(text), _) => Shape::Parameters(numbers(text, "--params")?),
        (None, ShapeArg::Incircle) => Shape::Incircle,
        (None, ShapeArg::Default) => Shape::Default,
    };
    let at = match &args.at {
        Some(text) => match numbers(text, "--at")?.as_slice() {
            [x, y] => Complex64::new(*x, *y),
            other => {
                return Err(CliError::Input(format!(
                    "--at takes two numbers x,y, but {} were given",
                    other.len()
                )));
            }
        },
        None => Complex64::new(0.0, 0.0),
    };
    Ok(LayoutOptions {
        shape,
        at,
        angle: args.angle.to_radians(),
    })
}

/// Comma-separated finite numbers; the message names the option and the bad item.
pub fn numbers(text: &str, option: &str) -> Result<Vec<f64>, CliError> {
    if text.trim().is_empty() {
        return Ok(Vec::new());
    }
    text.split(',')
        .enumerate()
        .map(|(i, item)| match item.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(CliError::Input(format!(
                "{option}: item {} ({:?}) is not a finite number",
                i + 1,
                item.trim()
            ))),
        })
        .collect()
}

fn draw(layout: &Layout, path: &Path, size: u32) -> Result<(), CliError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let svg = picture::layout_svg(layout, &title(layout), size);
    let bytes = match extension.as_deref() {
        Some("svg") => svg.into_bytes(),
        Some("png") => picture::svg_to_png(&svg).map_err(CliError::Input)?,
        _ => {
            return Err(CliError::Input(format!(
                "cannot draw to {}: the file name must end in .svg or .png",
                path.display()
            )));
        }
    };
    write_atomic(path, &bytes)
        .map_err(|e| CliError::Input(format!("cannot write {}: {e}", path.display())))
}

fn title(layout: &Layout) -> String {
    let chi = layout.symbol.euler_characteristic();
    format!("{}   χ = {}   {}", layout.symbol, chi, layout.geometry)
}

fn number(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

#[derive(Serialize)]
struct VertexJson {
    x: f64,
    y: f64,
    order: OrderJson,
    angle: f64,
    ideal: bool,
}

#[derive(Serialize)]
struct CircleJson {
    cx: f64,
    cy: f64,
    r: f64,
}

#[derive(Serialize)]
struct LineJson {
    px: f64,
    py: f64,
    dx: f64,
    dy: f64,
}

#[derive(Serialize)]
struct EdgeJson {
    from: Option<usize>,
    to: Option<usize>,
    /// null when an end is ideal (the length is infinite).
    length: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    circle: Option<CircleJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    line: Option<LineJson>,
    /// `mirror` or `paired`.
    kind: &'static str,
    /// The partner edge of a paired edge; null for a mirror.
    partner: Option<usize>,
    /// The group element g with g(P) the tile across this edge, as rows of its ambient matrix:
    /// the reflection for a mirror; for an edge paired with j, the map of edge j onto this one.
    neighbour: [[f64; 3]; 3],
}

/// A vertex cycle: the corners glued into one point of the orbifold.
#[derive(Serialize)]
pub(crate) struct CycleJson {
    vertices: Vec<usize>,
    /// `cone`, `corner`, `regular` or `ideal`.
    kind: &'static str,
    order: OrderJson,
    angle_sum: f64,
}

impl From<&Cycle> for CycleJson {
    fn from(c: &Cycle) -> Self {
        CycleJson {
            vertices: c.vertices.clone(),
            kind: c.kind.name(),
            order: OrderJson::from(&c.order),
            angle_sum: c.angle_sum,
        }
    }
}

pub(crate) fn rows(m: DMat3) -> [[f64; 3]; 3] {
    [
        m.row(0).to_array(),
        m.row(1).to_array(),
        m.row(2).to_array(),
    ]
}

fn kind_name(kind: EdgeKind) -> (&'static str, Option<usize>) {
    match kind {
        EdgeKind::Mirror => ("mirror", None),
        EdgeKind::Paired { partner } => ("paired", Some(partner)),
    }
}

fn geodesic_json(g: ModelGeodesic) -> (Option<CircleJson>, Option<LineJson>) {
    match g {
        ModelGeodesic::Circle { centre, radius } => (
            Some(CircleJson {
                cx: centre.re,
                cy: centre.im,
                r: radius,
            }),
            None,
        ),
        ModelGeodesic::Line { point, direction } => (
            None,
            Some(LineJson {
                px: point.re,
                py: point.im,
                dx: direction.re,
                dy: direction.im,
            }),
        ),
    }
}

#[derive(Serialize)]
struct PointJson {
    x: f64,
    y: f64,
}

#[derive(Serialize)]
struct LayoutJson {
    signature: String,
    canonical: String,
    euler_characteristic: String,
    geometry: &'static str,
    model: &'static str,
    shape: &'static str,
    vertices: Vec<VertexJson>,
    edges: Vec<EdgeJson>,
    free_parameters: Vec<f64>,
    parameter_meaning: String,
    area: f64,
    centre: PointJson,
    angle: f64,
    cycles: Vec<CycleJson>,
}

impl LayoutJson {
    fn new(layout: &Layout, options: &LayoutOptions, polygon: &FundamentalPolygon) -> Self {
        let vertex = |v: &Vertex| VertexJson {
            x: v.position.re,
            y: v.position.im,
            order: OrderJson::from(&v.order),
            angle: v.angle,
            ideal: v.ideal,
        };
        let edge = |(e, p): (&Edge, &pairing::Edge)| {
            let (circle, line) = geodesic_json(e.geodesic);
            let (kind, partner) = kind_name(p.kind);
            EdgeJson {
                from: e.from,
                to: e.to,
                length: number(e.length),
                circle,
                line,
                kind,
                partner,
                neighbour: rows(p.neighbour),
            }
        };
        LayoutJson {
            signature: layout.symbol.to_string(),
            canonical: layout.symbol.canonical().to_string(),
            euler_characteristic: layout.symbol.euler_characteristic().to_string(),
            geometry: layout.geometry.name(),
            model: layout.model_name(),
            shape: match options.shape {
                Shape::Default => "default",
                Shape::Parameters(_) => "parameters",
                Shape::Incircle => "incircle",
            },
            vertices: layout.vertices.iter().map(vertex).collect(),
            edges: layout.edges.iter().zip(&polygon.edges).map(edge).collect(),
            free_parameters: layout.parameters.clone(),
            parameter_meaning: layout.parameter_meaning.describe(layout.vertices.len()),
            area: layout.area,
            centre: PointJson {
                x: layout.centre.re,
                y: layout.centre.im,
            },
            angle: layout.heading.to_degrees(),
            cycles: polygon.cycles.iter().map(CycleJson::from).collect(),
        }
    }
}

fn write_text(out: &mut impl Write, layout: &Layout) -> std::io::Result<()> {
    let model = match layout.model_name() {
        "stereographic" => "stereographic plane",
        "poincare" => "Poincaré disk",
        _ => "Euclidean plane",
    };
    writeln!(out, "{}  {} ({model})", layout.symbol, layout.geometry)?;
    let params: Vec<String> = layout.parameters.iter().map(|p| format!("{p}")).collect();
    let params = if params.is_empty() {
        "none".to_string()
    } else {
        params.join(", ")
    };
    writeln!(out, "  free parameters  {params}")?;
    writeln!(
        out,
        "                   {}",
        layout.parameter_meaning.describe(layout.vertices.len())
    )?;
    writeln!(out, "  area             {:.9}", layout.area)?;
    writeln!(
        out,
        "  centre           ({:.6}, {:.6}), arrow at {:.1}°",
        layout.centre.re,
        layout.centre.im,
        layout.heading.to_degrees()
    )?;
    writeln!(
        out,
        "  vertex  order  angle        ideal  x                  y"
    )?;
    for (i, v) in layout.vertices.iter().enumerate() {
        writeln!(
            out,
            "  {i:<6}  {:<5}  {:<11.9}  {:<5}  {:<+18.15}  {:<+18.15}",
            v.order.to_string(),
            v.angle,
            if v.ideal { "yes" } else { "no" },
            v.position.re,
            v.position.im
        )?;
    }
    writeln!(out, "  wall  from→to  length        geodesic")?;
    for (i, e) in layout.edges.iter().enumerate() {
        let ends = match (e.from, e.to) {
            (Some(a), Some(b)) => format!("{a}→{b}"),
            _ => "-".to_string(),
        };
        let length = if e.length.is_finite() {
            format!("{:.9}", e.length)
        } else {
            "∞".to_string()
        };
        let geodesic = match e.geodesic {
            ModelGeodesic::Circle { centre, radius } => {
                format!(
                    "circle centre ({:.6}, {:.6}) radius {:.6}",
                    centre.re, centre.im, radius
                )
            }
            ModelGeodesic::Line { point, direction } => format!(
                "line through ({:.6}, {:.6}) direction ({:.6}, {:.6})",
                point.re, point.im, direction.re, direction.im
            ),
        };
        writeln!(out, "  {i:<4}  {ends:<7}  {length:<12}  {geodesic}")?;
    }
    Ok(())
}

/// The JSON of a polygon with side pairings: the keys of a kaleidoscopic layout, and the
/// construction, the parameters' meanings and how many of the symbol's parameters are missing.
#[derive(Serialize)]
pub(crate) struct PolygonJson {
    signature: String,
    canonical: String,
    euler_characteristic: String,
    geometry: &'static str,
    model: &'static str,
    shape: &'static str,
    construction: &'static str,
    vertices: Vec<VertexJson>,
    edges: Vec<EdgeJson>,
    cycles: Vec<CycleJson>,
    free_parameters: Vec<f64>,
    parameter_meaning: String,
    parameter_meanings: Vec<String>,
    /// Each parameter's open range [low, high]; null for an unbounded end.
    parameter_ranges: Vec<[Option<f64>; 2]>,
    missing_parameters: usize,
    area: f64,
    centre: PointJson,
    angle: f64,
}

fn model_name(polygon: &FundamentalPolygon) -> &'static str {
    match polygon.geometry {
        orbifold::Geometry::Spherical => "stereographic",
        orbifold::Geometry::Euclidean => "euclidean",
        orbifold::Geometry::Hyperbolic => "poincare",
    }
}

/// The order of each vertex's cycle.
fn vertex_orders(polygon: &FundamentalPolygon) -> Vec<orbifold::Order> {
    let mut orders = vec![orbifold::Order::integer(1); polygon.vertices.len()];
    for c in &polygon.cycles {
        for &v in &c.vertices {
            orders[v] = c.order;
        }
    }
    orders
}

fn edge_length(polygon: &FundamentalPolygon, e: &pairing::Edge) -> f64 {
    match (e.from, e.to) {
        (Some(a), Some(b)) => {
            let (a, b) = (polygon.vertices[a], polygon.vertices[b]);
            if a.ideal || b.ideal {
                f64::INFINITY
            } else {
                polygon.space().ambient_distance(a.ambient, b.ambient)
            }
        }
        _ => f64::INFINITY,
    }
}

impl PolygonJson {
    pub(crate) fn new(polygon: &FundamentalPolygon, options: &LayoutOptions) -> Self {
        let space = polygon.space();
        let orders = vertex_orders(polygon);
        let chi = polygon.symbol.euler_characteristic();
        PolygonJson {
            signature: polygon.symbol.to_string(),
            canonical: polygon.symbol.canonical().to_string(),
            euler_characteristic: chi.to_string(),
            geometry: polygon.geometry.name(),
            model: model_name(polygon),
            shape: match options.shape {
                Shape::Default => "default",
                Shape::Parameters(_) => "parameters",
                Shape::Incircle => "incircle",
            },
            construction: polygon.construction.name(),
            vertices: polygon
                .vertices
                .iter()
                .zip(&orders)
                .map(|(v, order)| VertexJson {
                    x: v.position.re,
                    y: v.position.im,
                    order: OrderJson::from(order),
                    angle: v.angle,
                    ideal: v.ideal,
                })
                .collect(),
            edges: polygon
                .edges
                .iter()
                .map(|e| {
                    let (circle, line) = geodesic_json(space.model_geodesic(e.wall));
                    let (kind, partner) = kind_name(e.kind);
                    EdgeJson {
                        from: e.from,
                        to: e.to,
                        length: number(edge_length(polygon, e)),
                        circle,
                        line,
                        kind,
                        partner,
                        neighbour: rows(e.neighbour),
                    }
                })
                .collect(),
            cycles: polygon.cycles.iter().map(CycleJson::from).collect(),
            free_parameters: polygon.parameters.clone(),
            parameter_meaning: parameter_summary(polygon),
            parameter_meanings: polygon.parameter_meanings.clone(),
            parameter_ranges: polygon
                .parameter_ranges
                .iter()
                .map(|&(low, high)| [low, high].map(|v| v.is_finite().then_some(v)))
                .collect(),
            missing_parameters: polygon.missing_parameters,
            area: polygon.area,
            centre: PointJson {
                x: polygon.centre.re,
                y: polygon.centre.im,
            },
            angle: options.angle.to_degrees(),
        }
    }
}

/// One sentence on the parameters, with the ones this construction does not offer.
pub(crate) fn parameter_summary(polygon: &FundamentalPolygon) -> String {
    let mut text = if polygon.parameter_meanings.is_empty() {
        "none: the polygon is rigid".to_string()
    } else {
        polygon
            .parameter_meanings
            .iter()
            .enumerate()
            .map(|(i, m)| format!("{}: {m}", i + 1))
            .collect::<Vec<_>>()
            .join("; ")
    };
    if polygon.missing_parameters > 0 {
        let _ = write!(
            text,
            " ({} more of the orbifold's {} shape parameters are not offered by the {} construction; see docs/orbifolds.md)",
            polygon.missing_parameters,
            polygon.symbol.free_parameters(),
            polygon.construction.name()
        );
    }
    text
}

/// How each edge is glued, in words: `mirror`, or `paired with 3 (rotation)`.
pub(crate) fn pairing_text(polygon: &FundamentalPolygon, i: usize) -> String {
    let e = &polygon.edges[i];
    match e.kind {
        EdgeKind::Mirror => "mirror".to_string(),
        EdgeKind::Paired { partner } if e.reverses_orientation() => {
            format!("paired with {partner} by a glide reflection")
        }
        EdgeKind::Paired { partner } => {
            let what = isometry_kind(polygon, e.neighbour);
            format!("paired with {partner} by {what}")
        }
    }
}

/// Elliptic, parabolic or hyperbolic (a rotation, a limit rotation, a translation), from the
/// trace of the orientation-preserving ambient matrix: 1 + 2 cos θ for a rotation by θ.
fn isometry_kind(polygon: &FundamentalPolygon, m: DMat3) -> String {
    let trace = m.x_axis.x + m.y_axis.y + m.z_axis.z;
    let euclidean = polygon.geometry == orbifold::Geometry::Euclidean;
    if euclidean && (m.x_axis.x - 1.0).abs() < 1e-9 && (m.y_axis.y - 1.0).abs() < 1e-9 {
        return "a translation".into();
    }
    if trace < 3.0 - 1e-9 {
        let angle = ((trace - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
        format!("a rotation by {:.1}°", angle.to_degrees())
    } else if trace < 3.0 + 1e-9 {
        "a parabolic rotation about an ideal point".into()
    } else {
        "a hyperbolic translation".into()
    }
}

fn write_paired_text(out: &mut impl Write, polygon: &FundamentalPolygon) -> std::io::Result<()> {
    let model = match model_name(polygon) {
        "stereographic" => "stereographic plane",
        "poincare" => "Poincaré disk",
        _ => "Euclidean plane",
    };
    writeln!(
        out,
        "{}  {} ({model}), {} construction",
        polygon.symbol,
        polygon.geometry,
        polygon.construction.name()
    )?;
    let params: Vec<String> = polygon.parameters.iter().map(|p| format!("{p}")).collect();
    let params = if params.is_empty() {
        "none".to_string()
    } else {
        params.join(", ")
    };
    writeln!(out, "  free parameters  {params}")?;
    writeln!(out, "                   {}", parameter_summary(polygon))?;
    writeln!(out, "  area             {:.9}", polygon.area)?;
    writeln!(
        out,
        "  centre           ({:.6}, {:.6})",
        polygon.centre.re, polygon.centre.im
    )?;
    let orders = vertex_orders(polygon);
    writeln!(
        out,
        "  vertex  order  angle        ideal  x                  y"
    )?;
    for (i, v) in polygon.vertices.iter().enumerate() {
        writeln!(
            out,
            "  {i:<6}  {:<5}  {:<11.9}  {:<5}  {:<+18.15}  {:<+18.15}",
            orders[i].to_string(),
            v.angle,
            if v.ideal { "yes" } else { "no" },
            v.position.re,
            v.position.im
        )?;
    }
    writeln!(out, "  edge  from→to  length        glued")?;
    for (i, e) in polygon.edges.iter().enumerate() {
        let ends = match (e.from, e.to) {
            (Some(a), Some(b)) => format!("{a}→{b}"),
            _ => "-".to_string(),
        };
        let length = edge_length(polygon, e);
        let length = if length.is_finite() {
            format!("{length:.9}")
        } else {
            "∞".to_string()
        };
        writeln!(
            out,
            "  {i:<4}  {ends:<7}  {length:<12}  {}",
            pairing_text(polygon, i)
        )?;
    }
    writeln!(out, "  cycle  kind     order  angle sum     vertices")?;
    for (i, c) in polygon.cycles.iter().enumerate() {
        let vertices: Vec<String> = c.vertices.iter().map(ToString::to_string).collect();
        writeln!(
            out,
            "  {i:<5}  {:<7}  {:<5}  {:<12.9}  {}",
            c.kind.name(),
            c.order.to_string(),
            c.angle_sum,
            vertices.join(" ")
        )?;
    }
    Ok(())
}

fn draw_paired(polygon: &FundamentalPolygon, path: &Path, size: u32) -> Result<(), CliError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let chi = polygon.symbol.euler_characteristic();
    let title = format!("{}   χ = {}   {}", polygon.symbol, chi, polygon.geometry);
    let svg = paired_svg(polygon, &title, size);
    let bytes = match extension.as_deref() {
        Some("svg") => svg.into_bytes(),
        Some("png") => picture::svg_to_png(&svg).map_err(CliError::Input)?,
        _ => {
            return Err(CliError::Input(format!(
                "cannot draw to {}: the file name must end in .svg or .png",
                path.display()
            )));
        }
    };
    write_atomic(path, &bytes)
        .map_err(|e| CliError::Input(format!("cannot write {}: {e}", path.display())))
}

/// The polygon in its model: mirrors in blue, paired edges in red with matching letters and
/// arrows (an edge and its partner carry the same letter; the arrows show which way the pairing
/// glues them, as in textbooks), vertices coloured by their cycle's kind.
fn paired_svg(polygon: &FundamentalPolygon, title: &str, size: u32) -> String {
    let space = polygon.space();
    let edges: Vec<Vec<Complex64>> = (0..polygon.edges.len())
        .map(|i| {
            let points = picture::edge_samples(polygon, i, 48);
            points.iter().map(|&p| space.to_model(p)).collect()
        })
        .collect();
    let all: Vec<Complex64> = edges.iter().flatten().copied().collect();
    let hyperbolic = polygon.geometry == orbifold::Geometry::Hyperbolic;
    let (centre, half) = if hyperbolic {
        (Complex64::new(0.0, 0.0), 1.05)
    } else {
        let (lo, hi) = all.iter().fold(
            (
                Complex64::new(f64::MAX, f64::MAX),
                Complex64::new(f64::MIN, f64::MIN),
            ),
            |(lo, hi), z| {
                (
                    Complex64::new(lo.re.min(z.re), lo.im.min(z.im)),
                    Complex64::new(hi.re.max(z.re), hi.im.max(z.im)),
                )
            },
        );
        (
            (lo + hi) / 2.0,
            0.55 * (hi.re - lo.re).max(hi.im - lo.im).max(1e-9),
        )
    };
    let s = f64::from(size);
    let scale = s / (2.0 * half);
    let px = |z: Complex64| {
        (
            (z.re - centre.re) * scale + s / 2.0,
            s / 2.0 - (z.im - centre.im) * scale + 24.0,
        )
    };
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{}" viewBox="0 0 {size} {}">"#,
        size + 24,
        size + 24
    );
    let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        svg,
        r#"<text x="8" y="18" font-family="sans-serif" font-size="14">{}</text>"#,
        escape(title)
    );
    if hyperbolic {
        let (cx, cy) = px(Complex64::new(0.0, 0.0));
        let _ = writeln!(
            svg,
            r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="{:.2}" fill="none" stroke="#999" stroke-width="1"/>"##,
            scale
        );
    }
    let _ = writeln!(
        svg,
        r##"<defs><marker id="arrow" viewBox="0 0 10 10" refX="5" refY="5" markerWidth="7" markerHeight="7" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="#c0392b"/></marker></defs>"##
    );
    let partners: Vec<Option<usize>> = polygon
        .edges
        .iter()
        .map(|e| match e.kind {
            EdgeKind::Paired { partner } => Some(partner),
            EdgeKind::Mirror => None,
        })
        .collect();
    let letters = orbifold::pairing::pair_letters(&partners);
    for (i, (e, points)) in polygon.edges.iter().zip(&edges).enumerate() {
        // Each edge is a geodesic, a circle or a line in these conformal models: the arc
        // through its ends and its middle point draws it exactly.
        let d = match points.as_slice() {
            [] => String::new(),
            [first, .., last] if points.len() >= 3 => {
                let (x, y) = px(*first);
                let middle = px(points[points.len() / 2]);
                let arc = picture::arc_to(px(*first), middle, px(*last), 0.01);
                format!("M{x:.2} {y:.2} {}", arc.trim_end())
            }
            _ => {
                let line: Vec<String> = points
                    .iter()
                    .map(|&z| {
                        let (x, y) = px(z);
                        format!("{x:.2} {y:.2}")
                    })
                    .collect();
                format!("M{}", line.join(" L"))
            }
        };
        let (colour, width) = match e.kind {
            EdgeKind::Mirror => ("#1f6fd1", 3.5),
            EdgeKind::Paired { .. } => ("#c0392b", 2.0),
        };
        let _ = writeln!(
            svg,
            r##"<path d="{d}" fill="none" stroke="{colour}" stroke-width="{width}"/>"##
        );
        if let (EdgeKind::Paired { partner }, Some(letter)) = (e.kind, letters[i]) {
            let forward =
                orbifold::pairing::arrow_runs_forward(i, partner, e.reverses_orientation());
            let mid = points.len() / 2;
            let (a, b) = (
                points[mid.saturating_sub(1)],
                points[(mid + 1).min(points.len() - 1)],
            );
            let (a, b) = if forward { (a, b) } else { (b, a) };
            let ((x0, y0), (x1, y1)) = (px(a), px(b));
            let _ = writeln!(
                svg,
                r##"<line x1="{x0:.2}" y1="{y0:.2}" x2="{x1:.2}" y2="{y1:.2}" stroke="{colour}" stroke-width="2" marker-end="url(#arrow)"/>"##
            );
            let (x, y) = px(points[mid]);
            let _ = writeln!(
                svg,
                r##"<text x="{:.2}" y="{:.2}" font-family="sans-serif" font-size="15" fill="{colour}">{letter}</text>"##,
                x + 6.0,
                y - 6.0
            );
        }
    }
    let orders = vertex_orders(polygon);
    let mut kinds = vec!["regular"; polygon.vertices.len()];
    for c in &polygon.cycles {
        for &v in &c.vertices {
            kinds[v] = c.kind.name();
        }
    }
    for (i, v) in polygon.vertices.iter().enumerate() {
        let (x, y) = px(v.position);
        let fill = match kinds[i] {
            "cone" => "#e67e22",
            "corner" => "#1f6fd1",
            "ideal" => "#7f8c8d",
            _ => "#222",
        };
        let _ = writeln!(
            svg,
            r##"<circle cx="{x:.2}" cy="{y:.2}" r="4" fill="{fill}"/>"##
        );
        if !orders[i].is_one() {
            let _ = writeln!(
                svg,
                r##"<text x="{:.2}" y="{:.2}" font-family="sans-serif" font-size="12" fill="{fill}">{}</text>"##,
                x + 5.0,
                y + 14.0,
                escape(&orders[i].to_string())
            );
        }
    }
    svg.push_str("</svg>\n");
    svg
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
