//! Writing a state file (layout: the module docs and docs/stages.md).

use super::{FORMAT_VERSION, FORMSIM_VERSION, MAGIC, StateFile};
use fem_core::resume::flatten;
use fem_core::{StateArrays, ToolResume};
use plugins_api::RigidPose;
use std::path::Path;

/// Little-endian bytes of a state.
#[derive(Default)]
struct Out(Vec<u8>);

impl Out {
    fn u32(&mut self, v: u32) {
        self.0.extend(v.to_le_bytes());
    }
    fn u64(&mut self, v: usize) {
        self.0.extend((v as u64).to_le_bytes());
    }
    fn f64(&mut self, v: f64) {
        self.0.extend(v.to_le_bytes());
    }
    fn str(&mut self, s: &str) {
        self.u64(s.len());
        self.0.extend(s.as_bytes());
    }
    /// A length, then the numbers.
    fn f64s(&mut self, v: &[f64]) {
        self.u64(v.len());
        v.iter().for_each(|&x| self.f64(x));
    }
    fn option(&mut self, v: Option<f64>) {
        self.f64(if v.is_some() { 1.0 } else { 0.0 });
        self.f64(v.unwrap_or(0.0));
    }
    fn pose(&mut self, p: &RigidPose) {
        p.translation.iter().for_each(|&x| self.f64(x));
        p.rotation.iter().for_each(|&x| self.f64(x));
    }
    fn tool(&mut self, t: &ToolResume) {
        self.str(&t.name);
        self.pose(&t.initial);
        self.pose(&t.pose);
        let v = &t.velocity;
        v.linear
            .iter()
            .chain(v.angular.iter())
            .for_each(|&x| self.f64(x));
        self.f64(t.free_speed);
        self.option(t.applied);
        self.option(t.last_reaction);
        t.load.force.iter().for_each(|&x| self.f64(x));
        self.f64(t.load.stiffness);
    }
    fn arrays(&mut self, name: &str, a: &StateArrays) {
        self.str(name);
        self.u64(a.entries().len());
        for (k, v) in a.entries() {
            self.str(k);
            self.f64s(v);
        }
    }
}

/// The bytes of `state`.
pub fn to_bytes(state: &StateFile) -> Vec<u8> {
    let mut o = Out::default();
    o.0.extend(MAGIC);
    o.u32(FORMAT_VERSION);
    o.str(FORMSIM_VERSION);
    o.str(&state.element);
    o.str(&state.material);
    let r = &state.resume;
    o.u64(r.nodes.len());
    o.u64(state.quads.len());
    state.quads.iter().flatten().for_each(|&i| o.u32(i));
    let n = &r.nodes;
    for v in [&n.x0, &n.x, &n.v, &n.w, &r.forces.f, &r.forces.m] {
        o.f64s(&flatten(v));
    }
    o.f64s(&n.mass);
    o.f64s(&n.inertia);
    for x in [
        r.time,
        r.dt_prev,
        r.dt_next,
        r.dt_floor,
        r.physical_mass,
        r.added_mass,
    ] {
        o.f64(x);
    }
    o.u64(r.tools.len());
    r.tools.iter().for_each(|t| o.tool(t));
    o.u64(r.effects.len());
    r.effects.iter().for_each(|(name, a)| o.arrays(name, a));
    r.ledger.to_words().iter().for_each(|&x| o.f64(x));
    o.0
}

/// Write `state` to `path`; returns its checksum.
///
/// # Errors
/// The file cannot be written (one line naming it).
pub fn write(path: &Path, state: &StateFile) -> Result<String, String> {
    let bytes = to_bytes(state);
    std::fs::write(path, &bytes)
        .map_err(|e| format!("{}: cannot write the state: {e}", path.display()))?;
    Ok(super::checksum(&bytes))
}
