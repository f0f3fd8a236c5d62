//! Stage 1a, the broad phase: which of a pair's points may touch its tool
//! in this step. It owns the two cheap tests that keep points away from the
//! projection: the tool's bounding box (widened by half the thickness and the
//! search margin) and the `skip_far` Lipschitz bound on the motion since a
//! point's last projection (docs/contact.md, "Skipping nodes out of reach").

use super::{Candidates, LastProjection, PointsMut, Settings, ToolStep};
use crate::{BlankView, PointStatus};

/// Slack (mm) added to the reach of a skipped node, above the rounding of the
/// local coordinates and of the projection's distance.
const SKIP_TOL: f64 = 1e-9;

/// Fill `cand.points` with the pair points (`nodes[k]` the blank node of
/// point `k`) that must be projected this step, in pair-point order.
///
/// A point farther from the tool's box than half its thickness plus the
/// search margin is opened (`points.open`). With `settings.skip_far`, an open
/// point whose travel in the tool's frame since its last projection (`last`)
/// cannot have brought it within reach stays open and is not a candidate.
/// Returns how many points were skipped that way.
pub(crate) fn broad_phase(
    settings: &Settings,
    tool: &ToolStep,
    blank: &BlankView<'_>,
    nodes: &[u32],
    last: &LastProjection,
    points: &mut PointsMut<'_>,
    cand: &mut Candidates,
) -> u64 {
    let mut skipped = 0;
    cand.points.clear();
    for (k, &node) in nodes.iter().enumerate() {
        let i = node as usize;
        let x = blank.x[i];
        let half = 0.5 * blank.thickness[i];
        if tool.bbox.distance(&x) > half + settings.search_margin {
            points.open(k);
            continue;
        }
        if settings.skip_far && points.status[k] == PointStatus::Open {
            // The distance from a rigidly moving surface is 1-Lipschitz in
            // the point's position in the surface's own frame, so
            // |d_now| ≥ |d_then| − |x_local,now − x_local,then|.
            let moved = (tool.local(&x) - last.local[k]).norm();
            let reach = half.max(settings.max_penetration * blank.thickness[i] - half);
            if last.dist[k] - moved > reach + settings.search_margin + SKIP_TOL {
                skipped += 1;
                continue;
            }
        }
        cand.points.push(k as u32);
    }
    skipped
}
