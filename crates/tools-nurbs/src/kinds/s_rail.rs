//! The NUMISHEET'96 S-rail's tools, `kind = "s-rail-punch" | "s-rail-die" |
//! "s-rail-blankholder"`, from the shared S-rail dimensions (mm;
//! docs/tools.md).

use super::{Request, ToolKind};
use crate::builders::Facing;
use crate::builders::s_rail::{self, SRailParams};
use crate::error::NurbsError;
use crate::spec::Tool;

fn punch(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (name, place) = (r.name, r.place);
    let p: SRailParams = r.params()?;
    Ok(Tool::Nurbs(s_rail::punch(name, &p, &place)?))
}

fn die(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (name, place) = (r.name, r.place);
    let p: SRailParams = r.params()?;
    Ok(Tool::Nurbs(s_rail::die(name, &p, &place)?))
}

fn blankholder(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (name, place) = (r.name, r.place);
    let p: SRailParams = r.params()?;
    Ok(Tool::Nurbs(s_rail::blankholder(name, &p, &place)?))
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
