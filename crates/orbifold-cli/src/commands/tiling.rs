//! `orbifold tiling`: pictures of the universal cover, for kaleidoscopic symbols by reflections
//! (`orbifold_picture::tiling`), for every other orbifold through the side pairings of its
//! fundamental polygon (`orbifold_picture::group`).

use std::io::Write;

use num_complex::Complex64;
use orbifold::cover::{Bound, Cover};
use orbifold::layout::{Layout, LayoutOptions};
use orbifold::pairing::FundamentalPolygon;
use orbifold::pairing::cover::GroupCover;
use orbifold::{Geometry, OrbifoldSymbol, Signature};
use orbifold_picture::group::render_group;
use orbifold_picture::tiling::{Coloring, Model, Motif, Picture, View, render};

use crate::args::{ColorArg, ModelArg, TilingArgs};
use crate::commands::layout::numbers;
use crate::error::CliError;
use crate::output::{self, write_atomic};
use orbifold_picture::svg as picture;

pub fn run(args: &TilingArgs) -> Result<(), CliError> {
    let signature: Signature = match args.signature.parse::<Signature>() {
        Ok(signature) => signature,
        // Not kaleidoscopic: any other orbifold, folded through its side pairings.
        Err(e) => match args.signature.parse::<OrbifoldSymbol>() {
            Ok(symbol) if symbol.as_kaleidoscopic().is_none() => return run_group(args, &symbol),
            _ => return Err(CliError::Input(format!("{e}\n{}", e.snippet()))),
        },
    };
    let layout = Layout::new(&signature, &LayoutOptions::default())
        .map_err(|e| CliError::Input(e.to_string()))?;
    if signature.kind() != orbifold::Kind::Orbifold {
        return Err(CliError::Input(format!(
            "{signature} is not an orbifold, so its mirror images do not tile the plane: {}",
            signature.reason().unwrap_or_default()
        )));
    }
    let center = center(args)?;
    let model = pick_model(args, layout.geometry, &signature.to_string())?;
    let title = format!(
        "{}   χ = {}   {}",
        signature,
        signature.euler_characteristic(),
        layout.geometry
    );
    let bytes = match extension(args).as_deref() {
        Some("png") => png(args, &layout, model, center)?,
        // The reflection group's own SVG draws exact arcs in the models whose geodesics are
        // circles through the model's formulas; the others go through the group's picture.
        Some("svg") if !arcs_drawn_in(model) => {
            let symbol: OrbifoldSymbol = signature
                .to_string()
                .parse()
                .map_err(|e| CliError::Input(format!("{signature} as an orbifold symbol: {e}")))?;
            return run_group(args, &symbol);
        }
        Some("svg") => {
            let depth = args.depth.unwrap_or(6) as usize;
            let bound = if layout.geometry == orbifold::Geometry::Spherical {
                Bound::All
            } else {
                Bound::Depth(depth)
            };
            let cover = Cover::enumerate(&signature, bound, true)
                .map_err(|e| CliError::Input(e.to_string()))?;
            too_many(cover.tiles.len())?;
            picture::tiling_svg(&layout, &cover.tiles, &title, args.size, center, args.zoom)
                .into_bytes()
        }
        _ => return Err(bad_extension(args)),
    };
    write(args, &bytes)
}

/// Any orbifold that is not kaleidoscopic: its polygon with side pairings, every pixel folded
/// through the pairings (PNG) or the group's tiles with the pairings drawn (SVG).
fn run_group(args: &TilingArgs, symbol: &OrbifoldSymbol) -> Result<(), CliError> {
    if let Some(reason) = symbol.is_bad().then(|| symbol.reason()).flatten() {
        return Err(CliError::Input(format!(
            "{symbol} is not a good orbifold, so its group does not tile the plane: {reason}"
        )));
    }
    let polygon = FundamentalPolygon::new(symbol, &LayoutOptions::default())
        .map_err(|e| CliError::Input(format!("cannot build {symbol}: {e}")))?;
    let center = center(args)?;
    let model = pick_model(args, polygon.geometry, &symbol.to_string())?;
    let title = format!(
        "{}   χ = {}   {}",
        symbol,
        symbol.euler_characteristic(),
        polygon.geometry
    );
    let bytes = match extension(args).as_deref() {
        Some("png") => {
            let view = view(args, polygon.geometry, model, center);
            let motif = motif(args)?;
            let picture = render_group(&polygon, &view, motif.as_ref()).map_err(CliError::Input)?;
            encode(&picture)?
        }
        Some("svg") => {
            let bound = if polygon.geometry == orbifold::Geometry::Spherical {
                Bound::All
            } else {
                // Without --depth, whole depths up to 20 000 tiles: groups with many
                // generators grow fast, and tiles too small to see are left out anyway.
                args.depth
                    .map_or(Bound::Tiles(20_000), |d| Bound::Depth(d as usize))
            };
            let cover = GroupCover::enumerate(symbol, bound, true)
                .map_err(|e| CliError::Input(e.to_string()))?;
            too_many(cover.tiles.len())?;
            picture::group_tiling_svg(
                &cover.polygon,
                &cover.tiles,
                model,
                &title,
                args.size,
                center,
                args.zoom,
            )
            .into_bytes()
        }
        _ => return Err(bad_extension(args)),
    };
    write(args, &bytes)
}

fn center(args: &TilingArgs) -> Result<Complex64, CliError> {
    Ok(match &args.center {
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
    })
}

/// The requested model, or the geometry's natural one; an error if it does not show it.
fn pick_model(args: &TilingArgs, geometry: Geometry, name: &str) -> Result<Model, CliError> {
    let model = args.model.map_or(Model::default_for(geometry), model);
    if !model.shows(geometry) {
        return Err(CliError::Input(format!(
            "the {model:?} model does not show the {geometry} plane of {name}"
        )));
    }
    Ok(model)
}

fn extension(args: &TilingArgs) -> Option<String> {
    args.output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// Whether the reflection group's SVG (exact arcs from the model's geodesic formulas) draws in
/// `model`; the Klein disk, the half-plane and the sphere are drawn by the group's picture.
fn arcs_drawn_in(model: Model) -> bool {
    matches!(
        model,
        Model::Poincare | Model::Stereographic | Model::Euclidean
    )
}

fn too_many(tiles: usize) -> Result<(), CliError> {
    if tiles > 200_000 {
        return Err(CliError::Input(format!(
            "{tiles} tiles are too many for an SVG; lower --depth"
        )));
    }
    Ok(())
}

fn bad_extension(args: &TilingArgs) -> CliError {
    CliError::Input(format!(
        "cannot draw to {}: the file name must end in .png or .svg",
        args.output.display()
    ))
}

fn write(args: &TilingArgs, bytes: &[u8]) -> Result<(), CliError> {
    write_atomic(&args.output, bytes)
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
    let motif = motif(args)?;
    let view = view(args, layout.geometry, model, center);
    let picture = render(layout, &view, motif.as_ref()).map_err(CliError::Input)?;
    encode(&picture)
}

fn motif(args: &TilingArgs) -> Result<Option<Motif>, CliError> {
    let Some(path) = &args.motif else {
        return Ok(None);
    };
    let image = image::open(path)
        .map_err(|e| CliError::Input(format!("cannot read the motif {}: {e}", path.display())))?
        .to_rgba8();
    Ok(Some(Motif {
        width: image.width(),
        height: image.height(),
        rgba: image.into_raw(),
    }))
}

fn view(args: &TilingArgs, geometry: Geometry, model: Model, center: Complex64) -> View {
    let mut view = View::new(geometry, args.size);
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
    view
}

fn encode(picture: &Picture) -> Result<Vec<u8>, CliError> {
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
