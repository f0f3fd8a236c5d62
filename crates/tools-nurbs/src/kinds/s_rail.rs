//! The NUMISHEET'96 S-rail's tools, `kind = "s-rail-punch" | "s-rail-die" |
//! "s-rail-blankholder"`, from the shared S-rail dimensions (mm;
//! docs/tools.md).

use super::{Request, ToolKind};
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
        summary: "S-rail punch: punch_width, draw_depth, arc_radius, arc_angle_deg, straight_lengths, end_extension, punch_shoulder, die_shoulder, thickness, clearance_factor, flange_width, holder_gap, apron (mm, degrees)",
        default_facing: Facing::Up,
        build: punch,
    }
}

inventory::submit! {
    ToolKind {
        name: "s-rail-die",
        summary: "S-rail die: punch_width, draw_depth, arc_radius, arc_angle_deg, straight_lengths, end_extension, punch_shoulder, die_shoulder, thickness, clearance_factor, flange_width, holder_gap, apron (mm, degrees)",
        default_facing: Facing::Up,
        build: die,
    }
}

inventory::submit! {
    ToolKind {
        name: "s-rail-blankholder",
        summary: "S-rail blankholder: punch_width, draw_depth, arc_radius, arc_angle_deg, straight_lengths, end_extension, punch_shoulder, die_shoulder, thickness, clearance_factor, flange_width, holder_gap, apron (mm, degrees)",
        default_facing: Facing::Up,
        build: blankholder,
    }
}
