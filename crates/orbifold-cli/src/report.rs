//! What `info` and `enumerate` say about one orbifold, as JSON and as text.

use std::io::Write;

use orbifold::{Geometry, Kind, OrbifoldSymbol, Order, Signature};
use serde::Serialize;

/// A corner or cone order in JSON: an integer, the string `"inf"`, or a number for non-integer orders.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum OrderJson {
    Integer(u64),
    Infinite(&'static str),
    Real(f64),
}

impl From<&Order> for OrderJson {
    fn from(order: &Order) -> Self {
        match (order, order.as_integer()) {
            (_, Some(k)) => OrderJson::Integer(k),
            (Order::Infinite, None) => OrderJson::Infinite("inf"),
            (Order::Finite(_), None) => OrderJson::Real(order.to_f64()),
        }
    }
}

fn orders(list: &[Order]) -> Vec<OrderJson> {
    list.iter().map(OrderJson::from).collect()
}

#[derive(Debug, Serialize)]
pub struct GroupJson {
    pub name: String,
    pub conway: String,
    pub family: &'static str,
    pub description: String,
}

/// Everything `info` knows about one orbifold. The keys are a stable interface for scripts.
#[derive(Debug, Serialize)]
pub struct Report {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub input: Option<String>,
    pub canonical: String,
    pub notation: &'static str,
    pub corners: Vec<OrderJson>,
    pub walls: Option<usize>,
    pub euler_characteristic: String,
    pub geometry: &'static str,
    pub kind: &'static str,
    pub reason: Option<String>,
    pub buildable: bool,
    pub area: Option<f64>,
    pub group_order: Option<u128>,
    pub free_parameters: usize,
    pub family: Option<&'static str>,
    pub group: Option<GroupJson>,
    pub cones: Vec<OrderJson>,
    pub boundaries: Vec<Vec<OrderJson>>,
    pub handles: u32,
    pub crosscaps: u32,
    #[serde(skip)]
    symbol: OrbifoldSymbol,
    #[serde(skip)]
    kaleidoscopic: Option<Signature>,
}

impl Report {
    /// The report on a kaleidoscopic signature (as enumerated).
    pub fn of_signature(sig: &Signature) -> Self {
        Report::of_symbol(&OrbifoldSymbol::from(sig.clone()), None)
    }

    /// The report on any symbol; `input` is what the user typed.
    pub fn of_symbol(symbol: &OrbifoldSymbol, input: Option<&str>) -> Self {
        let kaleidoscopic = symbol.as_kaleidoscopic();
        let chi = symbol.euler_characteristic();
        let canonical = symbol.canonical();
        let kind = match &kaleidoscopic {
            Some(sig) => sig.kind(),
            None if symbol.is_bad() => Kind::Bad,
            None => Kind::Orbifold,
        };
        Report {
            input: input.map(str::to_string),
            canonical: canonical.to_string(),
            notation: if kaleidoscopic.is_some() {
                "kaleidoscopic"
            } else {
                "conway"
            },
            corners: orders(&canonical.boundaries().concat()),
            walls: kaleidoscopic.as_ref().map(Signature::wall_count),
            euler_characteristic: chi.to_string(),
            geometry: chi.geometry().name(),
            kind: kind.name(),
            reason: canonical.reason(),
            buildable: kaleidoscopic.as_ref().is_some_and(Signature::is_buildable),
            area: symbol.area(),
            group_order: symbol.group_order(),
            free_parameters: symbol.free_parameters(),
            family: kaleidoscopic
                .as_ref()
                .and_then(Signature::family)
                .map(|f| f.pattern),
            group: symbol.symmetry_group().map(|g| GroupJson {
                name: g.name,
                conway: g.conway,
                family: g.family.name(),
                description: g.description,
            }),
            cones: orders(canonical.cones()),
            boundaries: canonical.boundaries().iter().map(|b| orders(b)).collect(),
            handles: canonical.handles(),
            crosscaps: canonical.crosscaps(),
            symbol: symbol.clone(),
            kaleidoscopic,
        }
    }

    /// The multi-line human-readable report.
    pub fn write_text(&self, out: &mut impl Write) -> std::io::Result<()> {
        let chi = self.symbol.euler_characteristic();
        match &self.input {
            Some(input) if input.trim() != self.canonical => {
                writeln!(out, "{}  (read from {input:?})", self.canonical)?
            }
            _ => writeln!(out, "{}", self.canonical)?,
        }
        let row =
            |out: &mut dyn Write, key: &str, value: &str| writeln!(out, "  {key:<16} {value}");
        match &self.kaleidoscopic {
            Some(sig) => {
                let canon = sig.canonical();
                let walls = sig.wall_count();
                let list: Vec<String> = canon.corners().iter().map(ToString::to_string).collect();
                let corners = if list.is_empty() {
                    "none (one mirror, no corner)".to_string()
                } else {
                    list.join(" ")
                };
                row(
                    out,
                    "notation",
                    &format!(
                        "kaleidoscopic: a polygon of {walls} mirror wall{}",
                        plural(walls)
                    ),
                )?;
                row(out, "corners", &corners)?;
                if !canon.corners().is_empty() {
                    let angles: Vec<String> = canon.corners().iter().map(angle_text).collect();
                    row(out, "angles", &angles.join(" "))?;
                }
            }
            None => {
                row(out, "notation", "Conway (not a polygon of mirrors)")?;
                for (i, feature) in self.symbol.canonical().features().iter().enumerate() {
                    row(out, if i == 0 { "features" } else { "" }, feature)?;
                }
            }
        }
        row(out, "χ", &self.euler_characteristic)?;
        row(out, "geometry", &geometry_text(chi.geometry()))?;
        row(out, "kind", self.kind)?;
        if let Some(reason) = &self.reason {
            row(out, "reason", reason)?;
        }
        if let Some(family) = self.family {
            let walls = self.walls.unwrap_or(0);
            row(
                out,
                "family",
                &format!("{family}  (Table 4.1, {walls} wall{})", plural(walls)),
            )?;
        }
        if let Some(group) = &self.group {
            row(
                out,
                "group",
                &format!(
                    "{} (Conway {}): {}",
                    group.name, group.conway, group.description
                ),
            )?;
        }
        let area = match self.area {
            Some(area) => format!("{} ≈ {area:.6}  (2π|χ|)", chi.area_in_pi()),
            None if chi.geometry() == Geometry::Euclidean => {
                "none: a Euclidean polygon's scale is free".to_string()
            }
            None => "none: it cannot be built".to_string(),
        };
        row(out, "area", &area)?;
        let order = match self.group_order {
            Some(order) => format!("{order}  (2/χ)"),
            None if self.kind == "orbifold" => "infinite".to_string(),
            None => "none".to_string(),
        };
        row(out, "group order", &order)?;
        row(out, "free parameters", &free_parameters_text(self))?;
        if self.kaleidoscopic.is_none() && self.kind == "orbifold" {
            row(
                out,
                "rooms",
                "mirror edges are mirror walls, paired edges portals (`orbifold info` describes the pairings)",
            )?;
        }
        Ok(())
    }

    /// One aligned line for lists: canonical form, χ, geometry.
    pub fn write_line(&self, out: &mut impl Write) -> std::io::Result<()> {
        let order = self
            .group_order
            .map(|o| format!("  group order {o}"))
            .unwrap_or_default();
        let line = format!(
            "{:<20} χ = {:<10} {:<11}{order}",
            self.canonical, self.euler_characteristic, self.geometry
        );
        writeln!(out, "{}", line.trim_end())
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

fn geometry_text(geometry: Geometry) -> String {
    let cover = match geometry {
        Geometry::Spherical => "χ > 0: the mirror images tile the sphere",
        Geometry::Euclidean => "χ = 0: the mirror images tile the Euclidean plane",
        Geometry::Hyperbolic => "χ < 0: the mirror images tile the hyperbolic plane",
    };
    format!("{geometry}  ({cover})")
}

fn angle_text(k: &Order) -> String {
    match (k, k.as_integer()) {
        (Order::Infinite, _) => "0".to_string(),
        (_, Some(k)) => format!("π/{k}"),
        (Order::Finite(r), None) => format!("{}π/{}", r.denom(), r.numer()),
    }
}

fn free_parameters_text(report: &Report) -> String {
    let n = report.free_parameters;
    let why = match (&report.kaleidoscopic, report.geometry) {
        (Some(sig), _) if !sig.is_buildable() => "it cannot be built",
        (Some(sig), "euclidean") if sig.corner_count() == 4 => "the rectangle's aspect ratio",
        (Some(sig), _) if sig.corner_count() >= 4 => "N − 3 cut lengths",
        (Some(_), _) => "the polygon is rigid",
        (None, "hyperbolic") => "Thurston: −3χ(X) + 2·cones + corners",
        (None, "euclidean") => "shape of the lattice up to similarity",
        (None, _) => "rigid",
    };
    format!("{n}  ({why})")
}
