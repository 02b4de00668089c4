//! The command-line interface: commands, arguments and their help.

use clap::{Args, Parser, Subcommand};
use orbifold::Geometry;

/// Design and explore two-dimensional orbifolds: polygons whose walls are mirrors or portals.
///
/// A kaleidoscopic signature such as `*2333` lists the corners of a polygon whose walls are all
/// mirrors; a corner of order k has angle π/k. Any other orbifold is written in Conway's notation
/// (`632`, `22×`, `4*3`, `o`): its polygon pairs walls by rotations, glides and translations, and
/// a paired wall is a portal. The Euler characteristic χ says whether the polygon's images tile
/// the sphere (χ > 0), the Euclidean plane (χ = 0) or the hyperbolic plane (χ < 0).
#[derive(Debug, Parser)]
#[command(name = "orbifold", version, arg_required_else_help = true, after_help = EXAMPLES)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

const EXAMPLES: &str = "\
Examples:
  orbifold info '*22222'                 classify the seed's default orbifold
  orbifold info '*632' 4*2 '*∞∞∞' --json  several signatures, as JSON
  orbifold enumerate --corners 3 --max-order 7 --geometry hyperbolic
  orbifold enumerate --table             the seed's Table 4.1

Signatures: `*` then corner orders: digits 2-9, (12) for larger orders, ∞ or inf for ideal
corners, (3/2) or (1.5) for non-orbifold corners. Quote them in the shell: `*` is a glob.";

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Classify signatures: canonical form, χ, geometry, kind, area, group order, free parameters.
    #[command(after_help = INFO_EXAMPLES)]
    Info(InfoArgs),
    /// List every good kaleidoscopic orbifold with N corners and bounded orders, or Table 4.1.
    #[command(after_help = ENUMERATE_EXAMPLES)]
    Enumerate(EnumerateArgs),
    /// Construct the polygon of a signature in its geometry; print it, or draw it as SVG or PNG.
    #[command(after_help = LAYOUT_EXAMPLES)]
    Layout(LayoutArgs),
    /// Enumerate the tiles of the universal cover: counts by word length, optionally the tiles.
    #[command(after_help = COVER_EXAMPLES)]
    Cover(CoverArgs),
    /// Draw the universal cover as a tiling: PNG (every pixel folded into the polygon) or SVG.
    #[command(after_help = TILING_EXAMPLES)]
    Tiling(TilingArgs),
    /// Create, check and show mirror-room scene files (TOML; see docs/scene-format.md).
    #[command(subcommand)]
    Scene(SceneCommand),
    /// Mesh a mirror room (floor, ceiling, walls, mirrors, objects) and export it as OBJ, PLY or
    /// glTF, optionally with every copy under the group up to a depth.
    #[command(after_help = ROOM_EXAMPLES)]
    Room(RoomArgs),
    /// Follow one ray through a mirror room along the true geodesics of S²×R, E²×R or H²×R and
    /// print every hit; or write the per-pixel geometry a camera sees (AOVs) as EXR.
    #[command(after_help = TRACE_EXAMPLES)]
    Trace(TraceArgs),
    /// Render a mirror room photo-realistically, light travelling along the true geodesics:
    /// path tracing with light sampled through mirror images. Writes PNG (tone-mapped) or EXR.
    #[command(after_help = RENDER_EXAMPLES)]
    Render(RenderArgs),
    /// Render the frames of an animation: the camera (or an object) walking along the walls,
    /// orbiting the room's centre, turning on the spot, or following keyframes. Frames can be
    /// rendered in slices on many machines; existing frames are skipped.
    #[command(after_help = ANIMATE_EXAMPLES)]
    Animate(AnimateArgs),
    /// Draw the real-time preview offscreen: the room and its mirror copies rasterised on the
    /// GPU with the non-Euclidean projection (no ray tracing). Works on a software adapter.
    #[command(after_help = PREVIEW_EXAMPLES)]
    Preview(PreviewArgs),
    /// Hear a mirror room: its echoes along the geodesics of S²×R, E²×R or H²×R, found as the
    /// source's images under the reflection group and off the floor and ceiling, as an impulse
    /// response (WAV), optionally played through the room (a dry sound or a built-in clap).
    #[command(after_help = LISTEN_EXAMPLES)]
    Listen(ListenArgs),
}

const LISTEN_EXAMPLES: &str = "\
Examples:
  orbifold listen '*2222' -o shoebox.wav            # the impulse response of a shoebox
  orbifold listen '*444' -o clap.wav --convolve     # a clap in a hyperbolic room
  orbifold listen '*235' -o voice.wav --convolve dry.wav --stereo
  orbifold listen scene.toml -o ir.wav --seconds 1 --echogram echo.png
  orbifold listen '*2333' -o ir.wav --json > arrivals.json

The source is at the scene's first light (a bare signature: the room's centre) and the listener
at the camera, unless the scene's [sound] table says otherwise; it also sets the size of an
intrinsic unit in metres (the curvature radius), the speed of sound, the sample rate, the
absorption of mirrors, walls, floor and ceiling (per octave band if wanted), air absorption and
the level below which echoes are left out (docs/scene-format.md). Stereo puts two ears on the
camera's right axis. The WAV file is 16-bit, scaled so that its peak is 0.9 (the scale is
printed). docs/sound.md explains the acoustics.

--json prints {\"output\", \"sample_rate\", \"seconds\", \"channels\", \"scale\", \"lost\",
\"arrivals\": [{\"time\", \"amplitude\", \"surfaces\", \"length\"}]} (and \"arrivals_right\" in
stereo, \"arrivals\" then being the left ear's), sorted by time: time in seconds, amplitude as
pressure (the direct sound at one metre is 1/(4π)), the surfaces met in order (\"floor\",
\"ceiling\", \"wall I\", \"mirror I\"), length in metres.";

#[derive(Debug, Args)]
pub struct ListenArgs {
    /// A scene file (`.toml`) or an orbifold symbol (its default room: mirrors, and portals that
    /// pass the sound on); the built-in default scene without one.
    #[arg(value_name = "SCENE|SIG")]
    pub input: Option<String>,
    /// The WAV file to write.
    #[arg(short, long, value_name = "FILE.wav", default_value = "listen.wav")]
    pub output: std::path::PathBuf,
    /// The response's length in seconds (default: the scene's [sound] seconds, 2).
    #[arg(long, value_name = "T")]
    pub seconds: Option<f64>,
    /// Two channels: ears on the camera's right axis.
    #[arg(long)]
    pub stereo: bool,
    /// Play a dry sound through the room: this WAV file, or a built-in clap without one.
    #[arg(long, value_name = "DRY.wav", num_args = 0..=1)]
    pub convolve: Option<Option<std::path::PathBuf>>,
    /// Print the echoes as JSON.
    #[arg(long)]
    pub json: bool,
    /// Draw the echogram (PNG or SVG): the echoes over time, coloured by reflections.
    #[arg(long, value_name = "FILE.png|FILE.svg")]
    pub echogram: Option<std::path::PathBuf>,
}

const PREVIEW_EXAMPLES: &str = "\
Examples:
  orbifold preview                                  # the built-in default scene to preview.png
  orbifold preview examples/scenes/fig-1.2-333.toml --depth 12 --size 1280x720
  orbifold preview '*2352' --straight -o flat.png   # as if space were flat, to compare
  orbifold preview '*2223' --attenuation translations -o translations.png
  orbifold preview scene.toml --yaw 30 --pitch -10 --json
  orbifold preview '*2352' --depth 6 --size 1920x1080 --time-frames 60   # frame time on this GPU

Every copy of the room under the reflection group up to --depth reflections (the whole group on
the sphere) is drawn as a GPU instance; each vertex is mapped by the logarithm map of S²×R, E²×R
or H²×R at the eye and then projected like an ordinary pinhole camera, so the picture is what a
person in the mirror room would see, without tracing a ray. Mirrors show as faint glass. On the
sphere both images of each point are drawn: the short and the long way round. Without a GPU the
preview runs on Mesa's software Vulkan driver (Debian: mesa-vulkan-drivers libvulkan1).

--json prints {\"output\", \"width\", \"height\", \"adapter\", \"copies\", \"instances\",
\"triangles_per_copy\", \"triangles\", \"seconds\"}, and with --time-frames also
\"frames_timed\", \"frame_ms\" (the median) and \"frames_per_second\".";

#[derive(Debug, Args)]
pub struct PreviewArgs {
    /// A scene file (`.toml`) or an orbifold symbol (`*632`, `632`, `22×`: a room of mirrors, or
    /// of portals where the group pairs walls); absent: the built-in default scene.
    #[arg(value_name = "SCENE|SIG")]
    pub input: Option<String>,
    /// The picture to write (.png or .jpg).
    #[arg(short, long, value_name = "FILE", default_value = "preview.png")]
    pub output: std::path::PathBuf,
    /// Image size.
    #[arg(long, value_name = "WxH", default_value = "960x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// How many reflections deep the copies go (default: the scene's `[preview] depth`).
    #[arg(long, value_name = "D")]
    pub depth: Option<u32>,
    /// How copies fade: reflectance (as in a real mirror room), orbifold (the room bright),
    /// translations (copies that are not mirror images bright) or universal (all alike).
    #[arg(long, value_name = "MODE", value_parser = parse_attenuation)]
    pub attenuation: Option<orbifold_scene::Attenuation>,
    /// Project as if space were flat (the model picture), to compare with the true geodesics.
    #[arg(long)]
    pub straight: bool,
    /// Draw every copy, also those that cannot be in view.
    #[arg(long)]
    pub no_cull: bool,
    /// Draw every object at full detail, also in far copies (by default far copies draw their
    /// objects simplified to about one triangle per pixel).
    #[arg(long)]
    pub no_lod: bool,
    /// Turn the camera to this bearing (degrees from the model's +x, counter-clockwise).
    #[arg(long, value_name = "DEGREES", allow_hyphen_values = true)]
    pub yaw: Option<f64>,
    /// Tilt the camera to this elevation (degrees).
    #[arg(long, value_name = "DEGREES", allow_hyphen_values = true)]
    pub pitch: Option<f64>,
    /// After the picture, time N more frames with the camera turning a degree a frame (the
    /// copies recomputed every frame, as when walking in the studio) and report the median
    /// time from submitting a frame until the GPU has finished it: a benchmark of this machine.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub time_frames: Option<u32>,
    /// Print a JSON summary instead of text.
    #[arg(long)]
    pub json: bool,
}

fn parse_attenuation(s: &str) -> Result<orbifold_scene::Attenuation, String> {
    use orbifold_scene::Attenuation;
    match s.to_ascii_lowercase().as_str() {
        "reflectance" => Ok(Attenuation::Reflectance),
        "orbifold" => Ok(Attenuation::Orbifold),
        "translations" => Ok(Attenuation::Translations),
        "universal" => Ok(Attenuation::Universal),
        _ => Err(format!(
            "{s:?}: expected reflectance, orbifold, translations or universal"
        )),
    }
}

const RENDER_EXAMPLES: &str = "\
Examples:
  orbifold render                                   # the built-in default scene to render.png
  orbifold render examples/scenes/fig-1.2-333.toml -o room.exr --spp 256
  orbifold render '*2223' --size 320x240 --time-limit 30 -o quick.png
  orbifold render scene.toml --no-nee --spp 4096 -o reference.exr
  orbifold render '*2223' --straight-rays -o flat.png   # as if space were flat, to compare

The image refines in passes of one sample per pixel; a progress bar shows the time left. The
time limit or Ctrl-C stops after the current pass and writes the image so far. The image is the
same for a given --seed whatever the number of threads. A bare signature renders the default
room of that orbifold (every wall a mirror, a figure in the middle, a light, the camera three
quarters of the way to the -x wall). PNG and JPEG images are denoised (guided by what each pixel
saw first); EXR keeps the raw estimate. docs/rendering.md explains the light transport.

--json prints {\"output\", \"width\", \"height\", \"samples\", \"paths\", \"rays\", \"seconds\",
\"stopped_early\", \"relative_noise\", \"dropped_samples\", \"exposure\", \"denoised\"} (paths:
camera paths traced; rays: their geodesic stretches between mirrors, hit searches and shadow
tests alike).";

/// How an image is rendered: what `render` and `animate` share.
#[derive(Debug, Args)]
pub struct ImageArgs {
    /// Image size (default: the scene's `[render]` size).
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Samples per pixel (default: the scene's); on average over the image, since adaptive
    /// sampling gives more to the pixels that are noisiest on screen (for a denoised image,
    /// those the denoiser cannot smooth).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub spp: Option<u32>,
    /// The same number of samples for every pixel (no adaptive sampling).
    #[arg(long)]
    pub no_adaptive: bool,
    /// Stop an image (each frame of an animation) after this many seconds, at the end of the
    /// pass under way, and keep what there is.
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    pub time_limit: Option<f64>,
    /// Stop once the relative noise (the mean over pixels of the standard error of the pixel's
    /// luminance over that luminance + 0.01) is at most this, e.g. 0.02.
    #[arg(long, value_name = "X")]
    pub noise_target: Option<f64>,
    /// Worker threads (default: all cores).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub threads: Option<u32>,
    /// Seed of the random numbers (the same for every frame of an animation: the noise stays
    /// put instead of crawling).
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// The most non-mirror bounces of a path (default: the scene's).
    #[arg(long, value_name = "N")]
    pub max_depth: Option<u32>,
    /// Brute-force path tracing: no light sampling (point and spot lights then give no light).
    #[arg(long)]
    pub no_nee: bool,
    /// Radiance that every surface but mirrors and lights emits, uniformly (default 0): a soft
    /// glow that shows the room's shape even without lights.
    #[arg(long, value_name = "RADIANCE", allow_hyphen_values = true)]
    pub glow: Option<f64>,
    /// Light as if space were flat: the room's model picture with straight rays (the seed's
    /// Fig. 8.1a), to compare with the true geodesics (also `straight_rays = true` in the
    /// scene's `[render]` table).
    #[arg(long)]
    pub straight_rays: bool,
    /// No pixel footprint: count the light's mirror images up to a few pixels wide, and the far
    /// ones that light sampling cannot draw seen after a bounce, by ray hits alone, and
    /// point-sample checkerboards (noisier; for comparing with other renderers).
    #[arg(long)]
    pub no_footprint: bool,
    /// Trace every path in full: no radiance cache for far mirror images and indirect light
    /// (unbiased but noisier; for references and for comparing with other renderers).
    #[arg(long)]
    pub no_radiance_cache: bool,
    /// Candidates drawn for each light sample, of which one is kept (∝ its light if nothing
    /// blocks it) and tested for visibility: 1 is the plain light sample; more lower the noise
    /// of direct light through many mirror images for a little time each (1-16). By default 2
    /// where light sampling has at most 256 choices of light image (the spherical rooms), else 3.
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=i64::from(orbifold_render::integrator::MAX_LIGHT_CANDIDATES)))]
    pub light_candidates: Option<u32>,
    /// Denoise the image (the default for PNG and JPEG): an edge-avoiding filter guided by the
    /// albedo, normal and depth each pixel saw first and by its own noise.
    #[arg(long, conflicts_with = "no_denoise")]
    pub denoise: bool,
    /// Keep the raw path-traced image (the default for EXR).
    #[arg(long)]
    pub no_denoise: bool,
    /// The pixel reconstruction filter (default: the scene's `filter`, which is `gaussian`
    /// unless it says otherwise): `gaussian` (σ = 0.5 pixel, cut off at 1.5, as in pbrt and
    /// Mitsuba; each sample counts for the pixels within 1.5 pixels of it, which averages away
    /// about two thirds of the per-pixel variance and the grain of sub-pixel detail, for a
    /// slightly softer image) or `box` (each sample counts for its own pixel only: sharper,
    /// noisier).
    #[arg(long, value_name = "gaussian|box", value_parser = parse_filter)]
    pub filter: Option<orbifold_render::film::PixelFilter>,
    /// Exposure in stops for PNG and JPEG tone mapping (default: automatic, the log-average
    /// luminance to middle grey 0.18; for an animation, that of a small render of frame 0).
    #[arg(long, value_name = "STOPS", allow_hyphen_values = true)]
    pub exposure: Option<f64>,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// A scene file (`.toml`) or an orbifold symbol (`*632`, `632`, `22×`: a room of mirrors, or
    /// of portals where the group pairs walls); absent: the built-in default scene.
    #[arg(value_name = "SCENE|SIG")]
    pub input: Option<String>,
    /// The image to write: `.png` (tone-mapped, 8-bit sRGB), `.jpg` (the same, smaller) or
    /// `.exr` (linear HDR).
    #[arg(short, long, value_name = "FILE", default_value = "render.png")]
    pub output: std::path::PathBuf,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Print a summary as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

const ANIMATE_EXAMPLES: &str = "\
Examples:
  orbifold animate examples/scenes/fig-8.8-2233.toml --path walls -o frames/
  orbifold animate '*333' --path orbit --count 60 --size 320x240 --spp 32 -o orbit/
  orbifold animate scene.toml --path turn --format jpg -o pano/      # with a panorama camera
  orbifold animate scene.toml --path keys.txt --count 200 -o frames/
  orbifold animate scene.toml --path walls --walker figure -o avatar/
  orbifold animate scene.toml --path walls --frames 40..59 -o frames/  # one slice of a job

Paths: `walls` walks round the room along its walls facing the way it goes (the seed's Fig.
8.7); `orbit` circles the room's centre through the camera, facing the centre; `turn` turns
once on the spot; a FILE holds keyframes, one `x y height yaw [pitch]` per line (model
position, degrees; `#` comments), joined by geodesics. --walker moves an object (by name or
index) instead of the camera.

Frames are FRAME-00000.png ... in the output folder, each written to a temporary file and
renamed, and skipped when already there (unless --force): a stopped job goes on where it
stopped, and slices (--frames A..B, inclusive, counted from 0) can run on many machines at once
(docs/animation.md shows a Slurm array job). The exposure is the same for every frame: --exposure,
or worked out from a small fixed render of frame 0, so every machine agrees. Ctrl-C stops after
the frame under way without writing it.

--json prints one object per line for each frame ({\"frame\", \"output\", \"skipped\",
\"seconds\", \"samples\", \"relative_noise\"}) and a last line {\"frames\", \"rendered\",
\"skipped\", \"seconds\", \"exposure\"}.";

#[derive(Debug, Args)]
pub struct AnimateArgs {
    /// A scene file (`.toml`) or an orbifold symbol (`*632`, `632`, `22×`: a room of mirrors, or
    /// of portals where the group pairs walls); absent: the built-in default scene.
    #[arg(value_name = "SCENE|SIG")]
    pub input: Option<String>,
    /// `walls`, `orbit`, `turn`, or a keyframe file.
    #[arg(long, value_name = "walls|orbit|turn|FILE")]
    pub path: String,
    /// The folder to write the frames to (created if missing).
    #[arg(short, long, value_name = "DIR")]
    pub output: std::path::PathBuf,
    /// Frames in the whole animation (default: 120, or one per keyframe).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub count: Option<u32>,
    /// Render only frames A to B (inclusive, counted from 0), or only frame A.
    #[arg(long, value_name = "A..B", value_parser = parse_frames)]
    pub frames: Option<(u32, u32)>,
    /// What moves: `camera`, or an object's name or index.
    #[arg(long, value_name = "camera|OBJECT", default_value = "camera")]
    pub walker: String,
    /// Image format of the frames.
    #[arg(long, value_name = "png|jpg|exr", default_value = "png")]
    pub format: String,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Render frames that already exist again.
    #[arg(long)]
    pub force: bool,
    /// Print a JSON line per frame and a summary line instead of text.
    #[arg(long)]
    pub json: bool,
}

/// `A..B` or `A` (frame numbers from 0, inclusive).
fn parse_frames(text: &str) -> Result<(u32, u32), String> {
    let number = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("expected A..B or A with frame numbers from 0, found `{text}`"))
    };
    let (a, b) = match text.split_once("..") {
        Some((a, b)) => (number(a)?, number(b.trim_start_matches('='))?),
        None => (number(text)?, number(text)?),
    };
    if a > b {
        return Err(format!("the first frame {a} comes after the last {b}"));
    }
    Ok((a, b))
}

const TRACE_EXAMPLES: &str = "\
Examples:
  orbifold trace '*333' --from 0,0,0.5 --yaw 20 --pitch 10
  orbifold trace '*2223' --from 0.1,0,0.5 --yaw 45 --pitch -5 --bounces 20 --json
  orbifold trace examples/scenes/default.toml --from -0.2,0,0.5 --yaw 0 --pitch 0
  orbifold trace examples/scenes/default.toml --aov aov.exr --size 320x240

Rays are unit-speed geodesics: the height grows linearly with the intrinsic arc length s. Hits
are listed in order: `wall I` (I is the edge index of `orbifold layout`), `floor`, `ceiling` or
`object NAME`, whether it was a mirror, the model point x, y, the height h and the cumulative
arc length s. A mirror reflects the ray (its horizontal direction across the wall; the
elevation is kept); a portal (a wall the orbifold's group pairs with another, as in `632` or
`22×`) carries it on from its partner wall, moved by the pairing. The ray ends at the first
surface that is not a mirror or a portal, after --bounces of them, or when it runs out through
an ideal corner. With a bare symbol the room is the default layout of `orbifold layout SIG`,
every mirror wall a full mirror and every paired wall a portal.

JSON: {\"hits\": [{\"surface\", \"mirror\", \"kind\" (mirror, portal or surface), \"to\" (a
portal's partner wall), \"x\", \"y\", \"h\", \"s\", \"throughput\"}], \"end\"}.
AOV channels: Z (geodesic depth), P.X P.Y P.Z (model x, y, height), N.X N.Y N.Z (normal in the
local frame), id (0 floor, 1 ceiling, 2+i wall i, 1000+j object j, -1 none), bounces.";

#[derive(Debug, Args)]
pub struct TraceArgs {
    /// An orbifold symbol (`*2333`, `632`: every mirror wall a full mirror, every paired wall a
    /// portal), or a scene file (`.toml`).
    #[arg(value_name = "SIG|SCENE")]
    pub input: String,
    /// Where the ray starts: model x, model y and height (default: the scene's camera).
    #[arg(long, value_name = "X,Y,H", value_parser = parse_triple, allow_hyphen_values = true)]
    pub from: Option<[f64; 3]>,
    /// Bearing in degrees, counter-clockwise from the model's +x direction (default: the camera's).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub yaw: Option<f64>,
    /// Elevation in degrees, positive upwards (default: the camera's).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub pitch: Option<f64>,
    /// The most mirror reflections and portal crossings to follow.
    #[arg(long, value_name = "N", default_value_t = 100)]
    pub bounces: usize,
    /// The room's height (default: the scene's, 1).
    #[arg(long, value_name = "H")]
    pub height: Option<f64>,
    /// Print the hits as JSON.
    #[arg(long)]
    pub json: bool,
    /// Instead of one ray, write the AOVs of the scene's camera (moved by --from, --yaw, --pitch)
    /// to this EXR file.
    #[arg(long, value_name = "FILE.exr")]
    pub aov: Option<std::path::PathBuf>,
    /// The AOV image size.
    #[arg(long, value_name = "WxH", default_value = "640x480", value_parser = parse_size)]
    pub size: (u32, u32),
}

/// `x,y,h` as three finite numbers.
fn parse_triple(text: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected three numbers x,y,h, not {text:?}"));
    }
    let mut out = [0.0; 3];
    for (k, part) in parts.iter().enumerate() {
        let v: f64 = part
            .parse()
            .map_err(|_| format!("{part:?} (number {} of {text:?}) is not a number", k + 1))?;
        if !v.is_finite() {
            return Err(format!("{part:?} is not a finite number"));
        }
        out[k] = v;
    }
    Ok(out)
}

/// `WxH` with both between 1 and 16384.
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT such as 640x480, not {text:?}"))?;
    let parse = |v: &str| -> Result<u32, String> {
        match v.trim().parse::<u32>() {
            Ok(n) if (1..=16384).contains(&n) => Ok(n),
            _ => Err(format!(
                "{v:?} in {text:?} is not a size between 1 and 16384"
            )),
        }
    };
    Ok((parse(w)?, parse(h)?))
}

/// A pixel filter by name (`box` or `gaussian`).
fn parse_filter(text: &str) -> Result<orbifold_render::film::PixelFilter, String> {
    orbifold_render::film::PixelFilter::from_name(text)
}

const ROOM_EXAMPLES: &str = "\
Examples:
  orbifold room '*2223' -o room.obj                 the room of a signature, all walls mirrors
  orbifold room examples/scenes/default.toml -o room.glb --json
  orbifold room '*333' -o kaleidoscope.ply --cover 4  the room and its copies to depth 4

Groups are named floor, ceiling, wall I (wall parts without a mirror), mirror I.J (mirror J of
wall I) and the objects' names; with --cover, the copies of each are in `<name> copies`.
Coordinates are 2 × model x, 2 × model y and height (glTF: x, height, -y, as glTF is Y up): the
model scaled by its metric at the centre, so a Euclidean room has its true size and shape. Ideal
corners are cut off at the distance reported. A bare signature gets the scene defaults and no
objects.";

/// The floor and ceiling tessellation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TessellationArg {
    /// The seed's contour-based method: rungs across the polygon between boundary samples.
    Contour,
    /// A fan from the centre refined by geodesic midpoint subdivision.
    Geodesic,
}

#[derive(Debug, Args)]
pub struct RoomArgs {
    /// An orbifold symbol (`*2333`, `632`), or a scene file (`.toml`).
    #[arg(value_name = "SIG|SCENE")]
    pub input: String,
    /// The mesh file to write: `.obj` (with a `.mtl` and the textures' images beside it), `.ply`
    /// (vertex colours, and texture coordinates with the images beside it) or `.glb` (images
    /// embedded); or `.svg` or `.png`, a picture of the floor's tessellation.
    #[arg(long, short = 'o', value_name = "FILE")]
    pub output: std::path::PathBuf,
    /// The longest edge wanted, in intrinsic units (default: the scene's, 0.1).
    #[arg(long, value_name = "L")]
    pub resolution: Option<f64>,
    /// Also write every copy of the room and its objects under the group up to this many
    /// reflections.
    #[arg(long, value_name = "DEPTH")]
    pub cover: Option<usize>,
    /// The floor and ceiling tessellation (default: the scene's, contour).
    #[arg(long, value_enum)]
    pub tessellation: Option<TessellationArg>,
    /// Cut ideal corners off at this intrinsic distance from the polygon's centre.
    #[arg(long, value_name = "D")]
    pub cusp: Option<f64>,
    /// The wall height (default: the scene's, 1).
    #[arg(long, value_name = "H")]
    pub height: Option<f64>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Scene-file commands.
#[derive(Debug, Subcommand)]
pub enum SceneCommand {
    /// Write a new scene: the built-in default room, or one on the given signature.
    #[command(
        after_help = "Examples:\n  orbifold scene new -o room.toml\n  orbifold scene new '*2333' -o room.toml"
    )]
    New {
        /// The room's signature (default: the seed's *22222).
        #[arg(value_name = "SIG")]
        signature: Option<String>,
        /// The file to write (written whole or not at all).
        #[arg(long, short = 'o', value_name = "FILE")]
        output: std::path::PathBuf,
    },
    /// Check scene files: every problem with its file, line, column and key; exit status 2 if any.
    #[command(after_help = "Example:\n  orbifold scene check examples/scenes/*.toml")]
    Check {
        /// The scene files.
        #[arg(value_name = "FILE", required = true)]
        files: Vec<std::path::PathBuf>,
    },
    /// Print a scene with every field, the defaults filled in: what the renderer, the preview
    /// and the exports will use (for scripts, `--json`).
    #[command(
        after_help = "Examples:\n  orbifold scene show examples/scenes/fig-1.2-333.toml\n  orbifold scene show room.toml --json | jq .lights"
    )]
    Show {
        /// The scene file.
        #[arg(value_name = "FILE")]
        file: std::path::PathBuf,
        /// Print JSON instead of TOML.
        #[arg(long)]
        json: bool,
    },
}

const TILING_EXAMPLES: &str = "\
PNG pictures fold every pixel back into the polygon by reflections: the number of reflections is
the tile's depth, its parity the tile's orientation; edges are antialiased from the distance to
the nearest wall. A motif image, stretched over the polygon's bounding box, is carried to every
tile and mirrored in the odd ones. SVG pictures draw the tiles up to --depth as geodesic arcs.

Any other orbifold (cones, handles, cross-caps, several boundaries) is folded through the side
pairings of its fundamental polygon (see `orbifold layout SYMBOL`): a letter p in every tile shows
rotations (p turned), reflections and glides (p mirrored into q) apart; --color depth counts the
pairings applied, --color wall colours by the pair of edges crossed last; a pixel that does not
arrive within --depth moves (default 500) is left grey. SVGs draw the group's tiles (without
--depth: whole depths up to 20 000 tiles), each with its p, and the pairings as arrows and
letters, mirrors blue.

Models: poincare, klein, halfplane (hyperbolic); stereographic, sphere (spherical); euclidean.

Examples:
  orbifold tiling '*237' -o 237.png
  orbifold tiling '*2222222' -o 74.svg --depth 4
  orbifold tiling '*∞∞∞' -o farey.png --model halfplane --color depth
  orbifold tiling '*235' -o sphere.png --model sphere --motif photo.jpg
  orbifold tiling '*333' -o p3m1.png --zoom 0.3 --center 0.1,0
  orbifold tiling 632 -o p6.png                   rotations only: every p turned
  orbifold tiling '22×' -o pgg.svg                 glides: arrows the same way round
  orbifold tiling '4*3' -o 4star3.png --color wall";

const COVER_EXAMPLES: &str = "\
Every tile is the image of the polygon under one element of the reflection group, produced
exactly once, with its word length (depth: its distance from the base tile across walls). The
counts per depth are checked against the group's growth series (Steinberg's formula).

Examples:
  orbifold cover '*235'                       the 120 tiles of the icosahedral group
  orbifold cover '*2222222' --depth 9 --json  the {7,4} tiling to depth 9
  orbifold cover '*∞∞∞' --max-tiles 1000 --tiles --json

Euclidean and hyperbolic covers are infinite: give --depth, --radius or --max-tiles. Requests
that would exceed the memory budget are refused before they start.";

const LAYOUT_EXAMPLES: &str = "\
The polygon is drawn in model coordinates: the stereographic plane (spherical), the Euclidean
plane, or the Poincaré disk (hyperbolic). Vertex i has the i-th order of the signature as typed;
wall i joins vertex i to vertex i+1. Ideal corners (∞) lie exactly on the unit circle.

Free parameters: *2222 has one, the ratio of wall 0's length to wall 1's. A hyperbolic N-gon has
N−3: parameter j (j = 1…N−3) sets the distance between wall N−1 and wall j to its value in the
balanced polygon (the one with an inscribed circle) times the 8th root of the parameter. Every
positive value gives a valid polygon; all 1 is the balanced polygon; the default is 1.4 each.
Any other symbol's polygon lists what each of its parameters means, with its range.

Examples:
  orbifold layout '*2333'
  orbifold layout '*22222' --params 1,3 --json
  orbifold layout '2*2222' --params 2,0.5,1   a cone and a mirror: *222222 with a side folded
  orbifold layout '*∞∞∞∞∞' --shape incircle -o ideal.svg
  orbifold layout '*235' --at 0.3,-0.1 --angle 30 -o tile.png --size 600";

const INFO_EXAMPLES: &str = "\
Accepted notation:
  kaleidoscopic   *  *22  *2333  *23456789(10)(11)  *∞∞∞  *222infinf  *(inf)(inf)(inf)
  non-orbifold    *(3/2)33  *(1.5)33      (corner angle π/k with k not an integer)
  Conway          632  4*2  2*22  22×  **  *×  ××  o  22222   (any 2D orbifold; x for ×)

Examples:
  orbifold info '*22222'
  orbifold info '*632' '*362' '*236'     three readings of one orbifold (p6m)
  orbifold info '*23' --json             a bad orbifold, explained
  orbifold info 632 2*22 '22×'           wallpaper groups p6, cmm, pgg

Exit status: 0 on success, 2 when a signature cannot be read (nothing is printed on stdout).";

const ENUMERATE_EXAMPLES: &str = "\
Each orbifold is listed once, in canonical form (the smallest reading under rotation and
reversal), in lexicographic order. Bad orbifolds (*k, *k₁k₂ with k₁ ≠ k₂) are never listed.

Examples:
  orbifold enumerate --corners 3 --max-order 6
  orbifold enumerate --corners 4 --max-order 4 --ideal --json
  orbifold enumerate --corners 5 --max-order 9 --count
  orbifold enumerate --table";

#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Signatures to classify, kaleidoscopic (`*2333`) or in Conway's notation (`4*2`).
    #[arg(value_name = "SIG", required = true)]
    pub signatures: Vec<String>,
    /// Print a JSON array, one object per signature, instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct EnumerateArgs {
    /// The number of corners N (0 lists `*`; with 1 corner every orbifold is bad).
    #[arg(long, short = 'n', value_name = "N", required_unless_present = "table")]
    pub corners: Option<usize>,
    /// The largest finite corner order K: orders 2, 3, …, K.
    #[arg(long, short = 'k', value_name = "K", required_unless_present = "table")]
    pub max_order: Option<u64>,
    /// Keep only this geometry: spherical, euclidean or hyperbolic.
    #[arg(long, short = 'g', value_name = "G")]
    pub geometry: Option<Geometry>,
    /// Also use ideal corners of order ∞.
    #[arg(long)]
    pub ideal: bool,
    /// Print only how many there are (per geometry).
    #[arg(long, conflicts_with = "table")]
    pub count: bool,
    /// Print the seed's Table 4.1: the families of orbifolds by number of walls and geometry.
    #[arg(long, conflicts_with_all = ["corners", "max_order", "geometry", "ideal"])]
    pub table: bool,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Which polygon to build when no parameters are given.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ShapeArg {
    /// Every free parameter at its default, 1.4.
    Default,
    /// The unique polygon with an inscribed circle: the most balanced shape.
    Incircle,
}

#[derive(Debug, Args)]
pub struct LayoutArgs {
    /// The signature, such as `*2333`, `*∞∞∞` or `*(3/2)33`, or any orbifold symbol (`632`,
    /// `22×`, `4*2`, `oo`): a polygon with side pairings (docs/orbifolds.md).
    #[arg(value_name = "SIG")]
    pub signature: String,
    /// The free shape parameters, comma-separated: positive numbers, each in its documented
    /// range (`orbifold layout SIG` lists them).
    #[arg(
        long,
        value_name = "A,B,…",
        allow_hyphen_values = true,
        conflicts_with = "shape"
    )]
    pub params: Option<String>,
    /// The shape when no parameters are given.
    #[arg(long, value_enum, default_value = "default")]
    pub shape: ShapeArg,
    /// Where to put the polygon's centre, in model coordinates.
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub at: Option<String>,
    /// Turn the polygon about its centre by this many degrees (counter-clockwise).
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_hyphen_values = true
    )]
    pub angle: f64,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Draw the layout to this file: `.svg` or `.png`.
    #[arg(long, short = 'o', value_name = "FILE")]
    pub output: Option<std::path::PathBuf>,
    /// The picture's width in pixels.
    #[arg(long, value_name = "PX", default_value_t = 800, value_parser = clap::value_parser!(u32).range(64..=8192))]
    pub size: u32,
}

#[derive(Debug, Args)]
pub struct CoverArgs {
    /// The kaleidoscopic signature, or any orbifold symbol (its group from the side pairings).
    #[arg(value_name = "SIG")]
    pub signature: String,
    /// Every tile of word length at most D.
    #[arg(long, value_name = "D", conflicts_with_all = ["radius", "max_tiles"])]
    pub depth: Option<usize>,
    /// Every tile whose centre lies within intrinsic distance R of the base tile's centre.
    #[arg(long, value_name = "R", conflicts_with = "max_tiles")]
    pub radius: Option<f64>,
    /// At most M tiles, whole depths at a time.
    #[arg(long, value_name = "M")]
    pub max_tiles: Option<usize>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Also list the tiles (isometry, depth, parity, wall).
    #[arg(long)]
    pub tiles: bool,
}

/// The view of the plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ModelArg {
    /// The Poincaré disk (hyperbolic).
    Poincare,
    /// The Klein disk (hyperbolic).
    Klein,
    /// The upper half-plane (hyperbolic).
    Halfplane,
    /// The stereographic plane (spherical).
    Stereographic,
    /// An orthographic view of the sphere (spherical).
    Sphere,
    /// The Euclidean plane.
    Euclidean,
}

/// How tiles are coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ColorArg {
    /// By orientation: even and odd tiles.
    Parity,
    /// By word length.
    Depth,
    /// By the last wall crossed.
    Wall,
}

#[derive(Debug, Args)]
pub struct TilingArgs {
    /// The orbifold: a kaleidoscopic signature (`*237`), any Conway symbol (`632`, `22×`) or a
    /// wallpaper group's short name (`p6`, `pgg`).
    #[arg(value_name = "SIG")]
    pub signature: String,
    /// The picture to write: `.png` or `.svg`.
    #[arg(long, short = 'o', value_name = "FILE")]
    pub output: std::path::PathBuf,
    /// Width and height in pixels.
    #[arg(long, value_name = "PX", default_value_t = 1024, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub size: u32,
    /// The model (default: the natural one of the geometry).
    #[arg(long, value_enum)]
    pub model: Option<ModelArg>,
    /// Tile colours.
    #[arg(long = "color", value_enum, default_value = "parity")]
    pub color: ColorArg,
    /// A PNG or JPEG image placed over the polygon and carried to every tile.
    #[arg(long, value_name = "IMG")]
    pub motif: Option<std::path::PathBuf>,
    /// The model point shown at the centre of the picture.
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub center: Option<String>,
    /// Magnification.
    #[arg(long, value_name = "Z", default_value_t = 1.0)]
    pub zoom: f64,
    /// For SVG: draw tiles up to this word length. For PNG: give up on a pixel after this many
    /// reflections or pairings (near ideal corners and the boundary).
    #[arg(long, value_name = "D")]
    pub depth: Option<u32>,
}
