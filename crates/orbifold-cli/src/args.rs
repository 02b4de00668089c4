//! The command-line interface: commands, arguments and their help.

use clap::{Args, Parser, Subcommand};
use orbifold::Geometry;

/// Design and explore two-dimensional kaleidoscopic orbifolds: polygons whose walls are mirrors.
///
/// A signature such as `*2333` lists the corners of a polygon; a corner of order k has angle π/k.
/// Its Euler characteristic χ = Σ 1/(2kᵢ) − N/2 + 1 says whether the polygon and its mirror
/// images tile the sphere (χ > 0), the Euclidean plane (χ = 0) or the hyperbolic plane (χ < 0).
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
}

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
