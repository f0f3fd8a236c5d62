//! A pair's per-point state saved and restored (forming in stages): the
//! friction history (stored traction, pressure, frictional work density),
//! the last normal and contact force, the outputs of the last step
//! (pressure, traction, `τ_c`, slip, status) and the warm-start seeds of the
//! projection (patch and surface parameters, last distance and local
//! position) with the tool's flat or curved region around the last answer.

use super::{ContactPair, PointStatus};
use fem_core::StateArrays;
use fem_core::resume::{flatten, unflatten};
use plugins_api::{CurvedRegion, CurvedShape, FlatRegion, ProjectionHint, ToolRegion, Vec3};

/// Numbers per point of a saved region: a tag (0 none, 1 flat, 2 cylinder,
/// 3 torus), then its fields, zero-padded.
const REGION_WORDS: usize = 18;

fn v3(w: &[f64]) -> Vec3 {
    Vec3::new(w[0], w[1], w[2])
}

/// `region` as [`REGION_WORDS`] numbers, pushed to `out`.
fn region_words(region: &Option<ToolRegion>, out: &mut Vec<f64>) {
    let start = out.len();
    match region {
        None => out.push(0.0),
        Some(ToolRegion::Flat(f)) => {
            out.push(1.0);
            out.extend(f.normal.iter().chain([&f.offset]).chain(f.centre.iter()));
            out.push(f.radius);
        }
        Some(ToolRegion::Curved(c)) => {
            let (tag, extra) = match c.shape {
                CurvedShape::Cylinder { along } => (2.0, [along[0], along[1], 0.0, 0.0]),
                CurvedShape::Torus {
                    spine,
                    tube_mid,
                    tube_cos,
                } => (3.0, [spine, tube_mid[0], tube_mid[1], tube_cos]),
            };
            out.push(tag);
            out.extend(c.origin.iter().chain(c.axis.iter()));
            out.extend([c.radius, c.side]);
            out.extend(c.mid.iter());
            out.push(c.cos_half);
            out.extend(extra);
        }
    }
    out.resize(start + REGION_WORDS, 0.0);
}

/// The region of [`region_words`].
fn region_of(w: &[f64]) -> Option<ToolRegion> {
    let curved = |shape| {
        ToolRegion::Curved(CurvedRegion {
            origin: v3(&w[1..4]),
            axis: v3(&w[4..7]),
            radius: w[7],
            side: w[8],
            mid: v3(&w[9..12]),
            cos_half: w[12],
            shape,
        })
    };
    match w[0] as u8 {
        1 => Some(ToolRegion::Flat(FlatRegion {
            normal: v3(&w[1..4]),
            offset: w[4],
            centre: v3(&w[5..8]),
            radius: w[8],
        })),
        2 => Some(curved(CurvedShape::Cylinder {
            along: [w[13], w[14]],
        })),
        3 => Some(curved(CurvedShape::Torus {
            spine: w[13],
            tube_mid: [w[14], w[15]],
            tube_cos: w[16],
        })),
        _ => None,
    }
}

/// `PointStatus` as a number and back.
fn status_code(s: PointStatus) -> f64 {
    match s {
        PointStatus::Open => 0.0,
        PointStatus::Stick => 1.0,
        PointStatus::Slip => 2.0,
    }
}

fn status_of(c: f64) -> PointStatus {
    if c == 1.0 {
        PointStatus::Stick
    } else if c == 2.0 {
        PointStatus::Slip
    } else {
        PointStatus::Open
    }
}

impl ContactPair {
    /// Push the per-point state under `prefix` (the pair's name and a dot).
    pub(crate) fn save_arrays(&self, prefix: &str, out: &mut StateArrays) {
        let key = |k: &str| format!("{prefix}{k}");
        out.push(
            &key("nodes"),
            self.nodes.iter().map(|&i| f64::from(i)).collect(),
        );
        let t: Vec<Vec3> = self.friction.iter().map(|p| p.t).collect();
        out.push(&key("t"), flatten(&t));
        out.push(&key("p"), self.friction.iter().map(|p| p.p).collect());
        out.push(
            &key("omega"),
            self.friction.iter().map(|p| p.omega).collect(),
        );
        out.push(&key("n_old"), flatten(&self.n_old));
        out.push(&key("force"), flatten(&self.force));
        out.push(&key("pressure"), self.pressure.clone());
        out.push(&key("traction"), flatten(&self.traction));
        out.push(&key("tau_c"), self.tau_c.clone());
        out.push(&key("slip"), self.slip.clone());
        out.push(
            &key("status"),
            self.status.iter().map(|&s| status_code(s)).collect(),
        );
        // Warm starts: [has, patch, u, v] per point.
        let hints = self
            .last
            .hint
            .iter()
            .flat_map(|h| match h {
                Some(h) => [1.0, f64::from(h.patch), h.u, h.v],
                None => [0.0; 4],
            })
            .collect();
        out.push(&key("hint"), hints);
        let mut regions = Vec::with_capacity(REGION_WORDS * self.last.region.len());
        self.last
            .region
            .iter()
            .for_each(|r| region_words(r, &mut regions));
        out.push(&key("region"), regions);
        out.push(&key("dist"), self.last.dist.clone());
        out.push(&key("local"), flatten(&self.last.local));
    }

    /// Take back what [`ContactPair::save_arrays`] pushed under `prefix`.
    ///
    /// # Errors
    /// Another set of points (nodes) or an array of another length.
    pub(crate) fn restore_arrays(
        &mut self,
        prefix: &str,
        saved: &StateArrays,
    ) -> Result<(), String> {
        let m = self.nodes.len();
        let get = |k: &str, len: usize| saved.get(&format!("{prefix}{k}"), len);
        let nodes = get("nodes", m)?;
        if self
            .nodes
            .iter()
            .zip(nodes)
            .any(|(&a, &b)| f64::from(a) != b)
        {
            return Err(format!("pair `{}`: other blank nodes", self.name));
        }
        let (t, p, omega) = (get("t", 3 * m)?, get("p", m)?, get("omega", m)?);
        for (i, s) in self.friction.iter_mut().enumerate() {
            s.t = Vec3::new(t[3 * i], t[3 * i + 1], t[3 * i + 2]);
            s.p = p[i];
            s.omega = omega[i];
        }
        unflatten(get("n_old", 3 * m)?, &mut self.n_old);
        unflatten(get("force", 3 * m)?, &mut self.force);
        self.pressure.copy_from_slice(get("pressure", m)?);
        unflatten(get("traction", 3 * m)?, &mut self.traction);
        self.tau_c.copy_from_slice(get("tau_c", m)?);
        self.slip.copy_from_slice(get("slip", m)?);
        for (s, &c) in self.status.iter_mut().zip(get("status", m)?) {
            *s = status_of(c);
        }
        for (h, c) in self
            .last
            .hint
            .iter_mut()
            .zip(get("hint", 4 * m)?.chunks_exact(4))
        {
            *h = (c[0] == 1.0).then(|| ProjectionHint {
                patch: c[1] as u32,
                u: c[2],
                v: c[3],
            });
        }
        let regions = get("region", REGION_WORDS * m)?;
        for (r, w) in self
            .last
            .region
            .iter_mut()
            .zip(regions.chunks_exact(REGION_WORDS))
        {
            *r = region_of(w);
        }
        self.last.dist.copy_from_slice(get("dist", m)?);
        unflatten(get("local", 3 * m)?, &mut self.last.local);
        Ok(())
    }
}
