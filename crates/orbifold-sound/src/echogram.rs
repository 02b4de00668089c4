//! The echogram: every echo as a line at its arrival time, as high as its level in decibels
//! relative to the direct sound at one metre, coloured by how many surfaces it reflects off —
//! the room's geometry at a glance (docs/sound.md). Drawn with `plotters` as SVG; PNG through
//! the project's SVG renderer (`orbifold_picture::svg::svg_to_png`).
//!
//! A picture cannot show a million lines apart: echoes are gathered per pixel column and per
//! class of reflection count, and only the loudest of each is drawn (what the eye would see
//! anyway), which keeps the files small.

use plotters::prelude::*;

use crate::arrival::Arrival;
use crate::error::SoundError;

/// The classes of reflection count, each with its colour: none (the direct sound, and echoes
/// through portals alone), 1, 2, 3, 4–7, 8–15, 16–31, 32 and more.
const CLASSES: [(u32, &str, RGBColor); 8] = [
    (0, "direct", RGBColor(0, 0, 0)),
    (1, "1", RGBColor(213, 62, 79)),
    (2, "2", RGBColor(244, 109, 67)),
    (3, "3", RGBColor(253, 174, 97)),
    (4, "4–7", RGBColor(171, 221, 164)),
    (8, "8–15", RGBColor(102, 194, 165)),
    (16, "16–31", RGBColor(50, 136, 189)),
    (32, "32+", RGBColor(94, 79, 162)),
];

/// The font, as the project's other pictures name it (`orbifold-picture`): resvg finds DejaVu
/// where a generic `sans-serif` may name a font that is not installed.
const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";

fn class(reflections: u32) -> usize {
    CLASSES
        .iter()
        .rposition(|(from, _, _)| reflections >= *from)
        .unwrap_or(0)
}

/// The level of an amplitude in decibels relative to the direct sound at one metre (1/(4π)).
///
/// ```
/// use orbifold_sound::echogram::level;
/// assert!(level(1.0 / (4.0 * std::f64::consts::PI * 10.0)).abs() - 20.0 < 1e-9);
/// ```
pub fn level(amplitude: f64) -> f64 {
    20.0 * (4.0 * std::f64::consts::PI * amplitude).max(1e-30).log10()
}

/// The echogram of `arrivals` over `seconds`, down to `floor` dB, as an SVG document of
/// `width` × `height` pixels.
///
/// ```
/// use orbifold_sound::arrival::Arrival;
/// use orbifold_sound::echogram::echogram_svg;
/// let echo = Arrival { time: 0.01, length: 3.43, amplitude: 0.02, bands: [0.02; 7],
///     reflections: 0, path: 0, slab: 0 };
/// let svg = echogram_svg(&[echo], "*2222", 0.1, -60.0, (640, 320)).unwrap();
/// assert!(svg.starts_with("<svg"));
/// ```
pub fn echogram_svg(
    arrivals: &[Arrival],
    title: &str,
    seconds: f64,
    floor: f64,
    (width, height): (u32, u32),
) -> Result<String, SoundError> {
    let mut svg = String::new();
    draw(&mut svg, arrivals, title, seconds, floor, (width, height))
        .map_err(|e| SoundError::Echogram(format!("cannot draw the echogram: {e}")))?;
    Ok(svg)
}

/// The echogram as PNG bytes ([`echogram_svg`] rendered).
pub fn echogram_png(
    arrivals: &[Arrival],
    title: &str,
    seconds: f64,
    floor: f64,
    size: (u32, u32),
) -> Result<Vec<u8>, SoundError> {
    let svg = echogram_svg(arrivals, title, seconds, floor, size)?;
    orbifold_picture::svg::svg_to_png(&svg).map_err(SoundError::Echogram)
}

/// The loudest echo of each reflection class in each of `columns` time columns.
fn loudest(arrivals: &[Arrival], seconds: f64, columns: usize) -> Vec<[Option<&Arrival>; 8]> {
    let mut best: Vec<[Option<&Arrival>; 8]> = vec![[None; 8]; columns];
    for a in arrivals {
        if !(0.0..seconds).contains(&a.time) {
            continue;
        }
        let column = ((a.time / seconds) * columns as f64) as usize;
        let slot = &mut best[column.min(columns - 1)][class(a.reflections)];
        if slot.is_none_or(|b| a.amplitude > b.amplitude) {
            *slot = Some(a);
        }
    }
    best
}

fn draw(
    svg: &mut String,
    arrivals: &[Arrival],
    title: &str,
    seconds: f64,
    floor: f64,
    (width, height): (u32, u32),
) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::with_string(svg, (width, height)).into_drawing_area();
    root.fill(&WHITE)?;
    let top = arrivals
        .iter()
        .map(|a| level(a.amplitude))
        .fold(floor + 10.0, f64::max)
        + 3.0;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 18))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(48)
        .build_cartesian_2d(0.0..seconds, floor..top)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("level (dB re direct sound at 1 m)")
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .light_line_style(WHITE)
        .draw()?;
    let columns = (width as usize).max(1);
    let best = loudest(arrivals, seconds, columns);
    // Many reflections first, so that the early, sparse echoes are drawn on top.
    for c in (0..CLASSES.len()).rev() {
        let color = CLASSES[c].2;
        let lines = best.iter().filter_map(|slots| slots[c]).map(|a| {
            PathElement::new(
                vec![(a.time, floor), (a.time, level(a.amplitude).max(floor))],
                color,
            )
        });
        chart
            .draw_series(lines)?
            .label(match c {
                // Through portals alone an echo reflects off nothing, as the direct sound does.
                0 => "no reflection".to_string(),
                1 => "1 reflection".to_string(),
                _ => format!("{} reflections", CLASSES[c].1),
            })
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 14, y)], color.stroke_width(3))
            });
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 11))
        .draw()?;
    root.present()?;
    Ok(())
}
