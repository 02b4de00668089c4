//! `orbifold tiling`: pictures of the universal cover.

use std::io::Write;

use num_complex::Complex64;
use orbifold::Signature;
use orbifold::cover::{Bound, Cover};
use orbifold::layout::{Layout, LayoutOptions};
use orbifold_picture::tiling::{Coloring, Model, Motif, View, render};

use crate::args::{ColorArg, ModelArg, TilingArgs};
use crate::commands::layout::numbers;
use crate::error::CliError;
use crate::output::{self, write_atomic};
use orbifold_picture::svg as picture;

pub fn run(args: &TilingArgs) -> Result<(), CliError> {
    let signature: Signature = args
        .signature
        .parse()
        .map_err(|e: orbifold::ParseError| CliError::Input(format!("{e}\n{}", e.snippet())))?;
    let layout = Layout::new(&signature, &LayoutOptions::default())
        .map_err(|e| CliError::Input(e.to_string()))?;
    if signature.kind() != orbifold::Kind::Orbifold {
        return Err(CliError::Input(format!(
            "{signature} is not an orbifold, so its mirror images do not tile the plane: {}",
            signature.reason().unwrap_or_default()
        )));
    }
    let center = match &args.center {
        Some(text) => match numbers(text, "--center")?.as_slice() {
            [x, y] => Complex64::new(*x, *y),
            other => {
                return Err(CliError::Input(format!(
                    "--center takes two numbers x,y, but {} were given",
                    other.len()
                )));
            }
        },
        None => Complex64::new(0.0, 0.0),
    };
    let model = args
        .model
        .map_or(Model::default_for(layout.geometry), model);
    if !model.shows(layout.geometry) {
        return Err(CliError::Input(format!(
            "the {model:?} model does not show the {} plane of {signature}",
            layout.geometry
        )));
    }
    let title = format!(
        "{}   χ = {}   {}",
        signature,
        signature.euler_characteristic(),
        layout.geometry
    );
    let extension = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let bytes = match extension.as_deref() {
        Some("png") => png(args, &layout, model, center)?,
        Some("svg") => {
            if !matches!(
                model,
                Model::Poincare | Model::Stereographic | Model::Euclidean
            ) {
                return Err(CliError::Input(
                    "SVG tilings are drawn in the poincare, stereographic or euclidean model"
                        .into(),
                ));
            }
            let depth = args.depth.unwrap_or(6) as usize;
            let bound = if layout.geometry == orbifold::Geometry::Spherical {
                Bound::All
            } else {
                Bound::Depth(depth)
            };
            let cover = Cover::enumerate(&signature, bound, true)
                .map_err(|e| CliError::Input(e.to_string()))?;
            if cover.tiles.len() > 200_000 {
                return Err(CliError::Input(format!(
                    "{} tiles are too many for an SVG; lower --depth",
                    cover.tiles.len()
                )));
            }
            picture::tiling_svg(&layout, &cover.tiles, &title, args.size, center, args.zoom)
                .into_bytes()
        }
        _ => {
            return Err(CliError::Input(format!(
                "cannot draw to {}: the file name must end in .png or .svg",
                args.output.display()
            )));
        }
    };
    write_atomic(&args.output, &bytes)
        .map_err(|e| CliError::Input(format!("cannot write {}: {e}", args.output.display())))?;
    let mut out = output::stdout();
    writeln!(out, "wrote {}", args.output.display())?;
    Ok(())
}

fn model(arg: ModelArg) -> Model {
    match arg {
        ModelArg::Poincare => Model::Poincare,
        ModelArg::Klein => Model::Klein,
        ModelArg::Halfplane => Model::HalfPlane,
        ModelArg::Stereographic => Model::Stereographic,
        ModelArg::Sphere => Model::Sphere,
        ModelArg::Euclidean => Model::Euclidean,
    }
}

fn png(
    args: &TilingArgs,
    layout: &Layout,
    model: Model,
    center: Complex64,
) -> Result<Vec<u8>, CliError> {
    let motif = match &args.motif {
        Some(path) => {
            let image = image::open(path)
                .map_err(|e| {
                    CliError::Input(format!("cannot read the motif {}: {e}", path.display()))
                })?
                .to_rgba8();
            Some(Motif {
                width: image.width(),
                height: image.height(),
                rgba: image.into_raw(),
            })
        }
        None => None,
    };
    let mut view = View::new(layout.geometry, args.size);
    view.model = model;
    view.center = center;
    view.zoom = args.zoom;
    view.coloring = match args.color {
        ColorArg::Parity => Coloring::Parity,
        ColorArg::Depth => Coloring::Depth,
        ColorArg::Wall => Coloring::Wall,
    };
    if let Some(depth) = args.depth {
        view.max_depth = depth;
    }
    let picture = render(layout, &view, motif.as_ref()).map_err(CliError::Input)?;
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(
            &picture.rgba,
            picture.size,
            picture.size,
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|e| CliError::Input(format!("cannot encode the PNG: {e}")))?;
    Ok(bytes)
}

use image::ImageEncoder;
