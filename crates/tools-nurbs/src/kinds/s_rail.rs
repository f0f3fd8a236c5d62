//! The NUMISHEET'96 S-rail's tools, `kind = "s-rail-punch" | "s-rail-die" |
//! "s-rail-blankholder"`, from the shared S-rail dimensions (mm;
//! docs/tools.md).

use super::{Request, ToolKey, ToolKind};
use crate::builders::s_rail::{self, SRailParams};
use crate::builders::{Facing, Placement};
use crate::error::NurbsError;
use crate::nurbs_tool::NurbsTool;
use crate::spec::Tool;

/// An S-rail tool: the table's dimensions, handed to `build`.
fn s_rail_tool(
    r: Request<'_>,
    build: fn(&str, &SRailParams, &Placement) -> Result<NurbsTool, NurbsError>,
) -> Result<Tool, NurbsError> {
    let (name, place) = (r.name, r.place);
    let p: SRailParams = r.params()?;
    Ok(Tool::Nurbs(build(name, &p, &place)?))
}

/// The S-rail's dimensions, shared by its three tools (defaults: the
/// benchmark's, `SRailParams::default`).
const KEYS: &[ToolKey] = &[
    ToolKey::optional(
        "punch_width",
        "mm",
        "30.0",
        "> 2 punch_shoulder",
        "punch width between the walls",
    ),
    ToolKey::optional("draw_depth", "mm", "37.0", "> 0", "draw depth"),
    ToolKey::optional(
        "arc_radius",
        "mm",
        "80.0",
        "> flange_width + 1",
        "centre-line arc radius",
    ),
    ToolKey::optional(
        "arc_angle_deg",
        "degrees",
        "30.0",
        "(0, 90]",
        "turning angle of each arc (a reconstruction)",
    ),
    ToolKey::optional(
        "straight_lengths",
        "mm",
        "[60.0, 50.0, 60.0]",
        "each ≥ 0",
        "straights 1, 2, 3 along the centre line",
    ),
    ToolKey::optional(
        "end_extension",
        "mm",
        "60.0",
        "≥ 0",
        "straights 1 and 3 prolonged beyond the S (a reconstruction)",
    ),
    ToolKey::optional(
        "punch_shoulder",
        "mm",
        "5.0",
        "> 0",
        "punch shoulder radius",
    ),
    ToolKey::optional("die_shoulder", "mm", "5.0", "> 0", "die shoulder radius"),
    ToolKey::optional(
        "thickness",
        "mm",
        "1.0",
        "> 0",
        "blank thickness: sets the clearance and the die roof",
    ),
    ToolKey::optional(
        "clearance_factor",
        "-",
        "1.1",
        "> 0",
        "die–punch clearance as a multiple of the thickness",
    ),
    ToolKey::optional(
        "flange_width",
        "mm",
        "70.0",
        "room for shoulder and holder",
        "half width of die face and holder from the centre line",
    ),
    ToolKey::optional(
        "holder_gap",
        "mm",
        "2.0",
        "> 0",
        "gap between punch wall and holder inner edge",
    ),
    ToolKey::optional(
        "apron",
        "mm",
        "0.0",
        "≥ 0",
        "flat prolongation of die face and holder beyond the flange (0: none)",
    ),
];

fn punch(r: Request<'_>) -> Result<Tool, NurbsError> {
    s_rail_tool(r, s_rail::punch)
}

fn die(r: Request<'_>) -> Result<Tool, NurbsError> {
    s_rail_tool(r, s_rail::die)
}

fn blankholder(r: Request<'_>) -> Result<Tool, NurbsError> {
    s_rail_tool(r, s_rail::blankholder)
}

inventory::submit! {
    ToolKind {
        name: "s-rail-punch",
        summary: "NUMISHEET'96 S-rail punch",
        keys: KEYS,
        default_facing: Facing::Up,
        build: punch,
    }
}

inventory::submit! {
    ToolKind {
        name: "s-rail-die",
        summary: "NUMISHEET'96 S-rail die",
        keys: KEYS,
        default_facing: Facing::Up,
        build: die,
    }
}

inventory::submit! {
    ToolKind {
        name: "s-rail-blankholder",
        summary: "NUMISHEET'96 S-rail blankholder",
        keys: KEYS,
        default_facing: Facing::Up,
        build: blankholder,
    }
}
