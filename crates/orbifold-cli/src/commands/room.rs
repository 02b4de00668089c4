//! `orbifold room`: mesh a mirror room and export it.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use orbifold::cover::{Bound, Cover, Tile};
use orbifold::pairing::FundamentalPolygon;
use orbifold::pairing::cover::GroupCover;
use orbifold::room::Quality;
use orbifold_scene::Scene;
use orbifold_scene::document::Tessellation;
use orbifold_scene::export::{ExportFormat, export, smooth_normals};
use orbifold_scene::geometry::{PartKind, RoomGeometry};
use serde::Serialize;

use crate::args::{RoomArgs, TessellationArg};
use crate::error::CliError;
use crate::output;

/// The most triangles one export may hold (about 1.5 GB of OBJ text).
const MAX_EXPORTED_TRIANGLES: usize = 30_000_000;

pub fn run(args: &RoomArgs) -> Result<(), CliError> {
    let picture = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg") || e.eq_ignore_ascii_case("png"));
    let format = ExportFormat::from_path(&args.output);
    if format.is_none() && !picture {
        return Err(CliError::Input(format!(
            "cannot tell the format of {}: the output must end in .obj, .ply or .glb (a mesh), or .svg or .png (a picture of the floor's tessellation)",
            args.output.display()
        )));
    }
    let (mut scene, base) = load(&args.input)?;
    apply_overrides(&mut scene, args);
    // The options may have made the scene invalid (a negative --height, say).
    if let Err(errors) = scene.check(base.as_deref()) {
        let list: Vec<String> = errors.iter().map(ToString::to_string).collect();
        return Err(CliError::Input(list.join("\nerror: ")));
    }
    let start = Instant::now();
    let geometry = scene.geometry(base.as_deref()).map_err(CliError::Input)?;
    let tiles = match args.cover {
        Some(depth) => cover_tiles(&geometry.layout, depth)?,
        None => Vec::new(),
    };
    let room_triangles: usize = geometry
        .parts
        .iter()
        .map(|p| p.surface.triangles.len())
        .sum();
    let total = room_triangles.saturating_mul(tiles.len().max(1));
    if total > MAX_EXPORTED_TRIANGLES {
        return Err(CliError::Input(format!(
            "{} copies of a room of {room_triangles} triangles would be {total} triangles, more than {MAX_EXPORTED_TRIANGLES}; \
             lower --cover or raise --resolution",
            tiles.len()
        )));
    }
    let (groups, omitted) = geometry.groups(&tiles);
    let title = format!(
        "orbifold room {} ({})",
        geometry.layout.symbol,
        geometry.layout.geometry.name()
    );
    let written = match format {
        Some(format) => export(&groups, format, &args.output, &title),
        None => write_picture(&geometry, &args.output),
    }
    .map_err(|e| CliError::Input(format!("cannot write {}: {e}", args.output.display())))?;
    let report = report(&geometry, &groups, &tiles, omitted, &written, start);
    let mut out = output::stdout();
    if args.json {
        serde_json::to_writer_pretty(&mut out, &report)?;
        writeln!(out)?;
    } else {
        write_text(&mut out, &report)?;
    }
    out.flush()?;
    Ok(())
}

/// The floor's tessellation over the layout picture, as SVG or PNG.
fn write_picture(geometry: &RoomGeometry, path: &Path) -> std::io::Result<Vec<std::path::PathBuf>> {
    let space = geometry.layout.space();
    let floor = &geometry.parts[0].surface;
    let points: Vec<_> = floor.points.iter().map(|&p| space.to_model(p)).collect();
    let title = format!(
        "{}: {} floor, {} triangles",
        geometry.layout.symbol,
        match geometry.mesher.options.method {
            orbifold::room::FloorMethod::Contour => "contour",
            orbifold::room::FloorMethod::Geodesic => "geodesic",
        },
        floor.triangles.len()
    );
    let svg =
        orbifold_picture::svg::mesh_svg(&geometry.layout, &points, &floor.triangles, &title, 640);
    let bytes = if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        orbifold_picture::svg::svg_to_png(&svg).map_err(std::io::Error::other)?
    } else {
        svg.into_bytes()
    };
    orbifold_scene::write_atomic(path, &bytes)?;
    Ok(vec![path.to_path_buf()])
}

/// The tiles of the room's group up to word length `depth`: its reflection group's for a
/// polygon of mirrors, the group of its side pairings otherwise.
fn cover_tiles(layout: &orbifold::Layout, depth: usize) -> Result<Vec<Tile>, CliError> {
    let error = |e: orbifold::cover::CoverError| CliError::Input(e.to_string());
    if layout.is_kaleidoscopic() {
        return Ok(
            Cover::enumerate_layout(layout.clone(), Bound::Depth(depth), true)
                .map_err(error)?
                .tiles,
        );
    }
    let polygon = FundamentalPolygon::from_layout(layout.symbol.clone(), layout.clone());
    let cover = GroupCover::enumerate_polygon(polygon, Bound::Depth(depth), true).map_err(error)?;
    Ok(cover
        .tiles
        .iter()
        .map(|t| Tile {
            matrix: t.matrix,
            depth: t.depth,
            reflected: t.reflected,
            wall: t.edge,
        })
        .collect())
}

/// The scene of a `.toml` file (and its directory, for relative paths) or of a bare signature
/// (scene defaults, no objects).
pub(crate) fn load(input: &str) -> Result<(Scene, Option<std::path::PathBuf>), CliError> {
    let path = Path::new(input);
    if input.ends_with(".toml") || path.is_file() {
        let scene = Scene::load(path).map_err(|errors| {
            let list: Vec<String> = errors.iter().map(ToString::to_string).collect();
            CliError::Input(list.join("\nerror: "))
        })?;
        let base = path.parent().map(Path::to_path_buf);
        return Ok((scene, base));
    }
    let signature: orbifold::OrbifoldSymbol = input
        .parse()
        .map_err(|e: orbifold::ParseError| CliError::Input(format!("{e}\n{}", e.snippet())))?;
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.to_string();
    scene.objects.clear();
    scene.lights.clear();
    let layout = scene.layout().map_err(CliError::Input)?;
    scene.camera.at = [layout.centre.re, layout.centre.im];
    Ok((scene, None))
}

fn apply_overrides(scene: &mut Scene, args: &RoomArgs) {
    if let Some(l) = args.resolution {
        scene.room.resolution = l;
    }
    if let Some(h) = args.height {
        scene.room.height = h;
    }
    if let Some(d) = args.cusp {
        scene.room.cusp_distance = Some(d);
    }
    if let Some(t) = args.tessellation {
        scene.room.tessellation = match t {
            TessellationArg::Contour => Tessellation::Contour,
            TessellationArg::Geodesic => Tessellation::Geodesic,
        };
    }
}

#[derive(Serialize)]
struct QualityJson {
    triangles: usize,
    largest_edge: f64,
    smallest_angle_degrees: f64,
}

impl From<Quality> for QualityJson {
    fn from(q: Quality) -> Self {
        QualityJson {
            triangles: q.triangles,
            largest_edge: q.largest_edge,
            smallest_angle_degrees: q.smallest_angle,
        }
    }
}

#[derive(Serialize)]
struct GroupJson {
    name: String,
    vertices: usize,
    triangles: usize,
}

#[derive(Serialize)]
struct RoomReport {
    signature: String,
    geometry: &'static str,
    files: Vec<String>,
    resolution: f64,
    tessellation: &'static str,
    height: f64,
    floor: QualityJson,
    walls: QualityJson,
    objects: usize,
    floor_area: f64,
    polygon_area: f64,
    cusp_distance: Option<f64>,
    cusp_area: f64,
    copies: usize,
    triangles: usize,
    omitted_far_triangles: usize,
    groups: Vec<GroupJson>,
    seconds: f64,
}

fn report(
    geometry: &RoomGeometry,
    groups: &[orbifold_scene::geometry::MeshGroup],
    tiles: &[orbifold::cover::Tile],
    omitted: usize,
    written: &[std::path::PathBuf],
    start: Instant,
) -> RoomReport {
    let space = geometry.layout.space();
    let mesher = &geometry.mesher;
    let floor = &geometry.parts[0].surface;
    let mut walls = orbifold::room::Surface::default();
    for part in &geometry.parts {
        if matches!(part.kind, PartKind::Wall(_) | PartKind::Mirror { .. }) {
            walls.append(&part.surface);
        }
    }
    RoomReport {
        signature: geometry.layout.symbol.to_string(),
        geometry: geometry.layout.geometry.name(),
        files: written.iter().map(|p| p.display().to_string()).collect(),
        resolution: mesher.options.resolution,
        tessellation: match mesher.options.method {
            orbifold::room::FloorMethod::Contour => "contour",
            orbifold::room::FloorMethod::Geodesic => "geodesic",
        },
        height: mesher.options.height,
        floor: floor.quality(space).into(),
        walls: walls.quality(space).into(),
        objects: geometry
            .parts
            .iter()
            .filter(|p| matches!(p.kind, PartKind::Object(_)))
            .count(),
        floor_area: floor.horizontal_area(space),
        polygon_area: mesher.polygon_area,
        cusp_distance: mesher.boundary.cusp_distance,
        cusp_area: mesher.cusp_area(),
        copies: tiles.iter().filter(|t| t.depth > 0).count(),
        triangles: groups.iter().map(|g| g.triangles.len()).sum(),
        omitted_far_triangles: omitted,
        groups: groups
            .iter()
            .map(|g| GroupJson {
                name: g.name.clone(),
                // As written: a vertex on a crease is written once per side.
                vertices: smooth_normals(g).positions.len(),
                triangles: g.triangles.len(),
            })
            .collect(),
        seconds: start.elapsed().as_secs_f64(),
    }
}

fn write_text(out: &mut impl Write, r: &RoomReport) -> std::io::Result<()> {
    writeln!(out, "{}  {}", r.signature, r.geometry)?;
    writeln!(out, "  wrote {}", r.files.join(", "))?;
    writeln!(
        out,
        "  {} triangles in {} groups ({} copies of the room), {:.3} s",
        r.triangles,
        r.groups.len(),
        r.copies,
        r.seconds
    )?;
    writeln!(
        out,
        "  resolution {} ({} floor), height {}",
        r.resolution, r.tessellation, r.height
    )?;
    for (name, q) in [("floor", &r.floor), ("walls", &r.walls)] {
        writeln!(
            out,
            "  {name:<6} {} triangles, longest edge {:.4}, smallest angle {:.2}°",
            q.triangles, q.largest_edge, q.smallest_angle_degrees
        )?;
    }
    writeln!(
        out,
        "  floor area {:.9} of the polygon's {:.9}",
        r.floor_area, r.polygon_area
    )?;
    if let Some(d) = r.cusp_distance {
        writeln!(
            out,
            "  ideal corners cut off at distance {d:.4} from the centre (area {:.3e} left out)",
            r.cusp_area
        )?;
    }
    if r.omitted_far_triangles > 0 {
        writeln!(
            out,
            "  {} triangles near the antipode left out (model coordinates beyond {})",
            r.omitted_far_triangles,
            orbifold_scene::geometry::FARTHEST_EXPORTED
        )?;
    }
    Ok(())
}
