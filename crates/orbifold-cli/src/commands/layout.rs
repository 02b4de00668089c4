//! `orbifold layout`: the polygon of a signature, as text, JSON, SVG or PNG.

use std::io::Write;
use std::path::Path;

use num_complex::Complex64;
use orbifold::Signature;
use orbifold::layout::{Edge, Layout, LayoutOptions, Shape, Vertex};
use orbifold::space::ModelGeodesic;
use serde::Serialize;

use crate::args::{LayoutArgs, ShapeArg};
use crate::error::CliError;
use crate::output::{self, write_atomic};
use crate::report::OrderJson;
use orbifold_picture::svg as picture;

pub fn run(args: &LayoutArgs) -> Result<(), CliError> {
    let signature: Signature = args
        .signature
        .parse()
        .map_err(|e: orbifold::ParseError| CliError::Input(format!("{e}\n{}", e.snippet())))?;
    let options = options(args)?;
    let layout = Layout::new(&signature, &options).map_err(|e| CliError::Input(e.to_string()))?;
    if let Some(path) = &args.output {
        draw(&layout, path, args.size)?;
    }
    let mut out = output::stdout();
    if args.json {
        serde_json::to_writer_pretty(&mut out, &LayoutJson::new(&layout, &options))?;
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
    let chi = layout.signature.euler_characteristic();
    format!("{}   χ = {}   {}", layout.signature, chi, layout.geometry)
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
}

impl LayoutJson {
    fn new(layout: &Layout, options: &LayoutOptions) -> Self {
        let vertex = |v: &Vertex| VertexJson {
            x: v.position.re,
            y: v.position.im,
            order: OrderJson::from(&v.order),
            angle: v.angle,
            ideal: v.ideal,
        };
        let edge = |e: &Edge| {
            let (circle, line) = match e.geodesic {
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
            };
            EdgeJson {
                from: e.from,
                to: e.to,
                length: number(e.length),
                circle,
                line,
            }
        };
        LayoutJson {
            signature: layout.signature.to_string(),
            canonical: layout.signature.canonical().to_string(),
            euler_characteristic: layout.signature.euler_characteristic().to_string(),
            geometry: layout.geometry.name(),
            model: layout.model_name(),
            shape: match options.shape {
                Shape::Default => "default",
                Shape::Parameters(_) => "parameters",
                Shape::Incircle => "incircle",
            },
            vertices: layout.vertices.iter().map(vertex).collect(),
            edges: layout.edges.iter().map(edge).collect(),
            free_parameters: layout.parameters.clone(),
            parameter_meaning: layout.parameter_meaning.describe(layout.vertices.len()),
            area: layout.area,
            centre: PointJson {
                x: layout.centre.re,
                y: layout.centre.im,
            },
            angle: layout.heading.to_degrees(),
        }
    }
}

fn write_text(out: &mut impl Write, layout: &Layout) -> std::io::Result<()> {
    let model = match layout.model_name() {
        "stereographic" => "stereographic plane",
        "poincare" => "Poincaré disk",
        _ => "Euclidean plane",
    };
    writeln!(out, "{}  {} ({model})", layout.signature, layout.geometry)?;
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
