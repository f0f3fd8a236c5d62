//! Drawbeads as equivalent line forces (docs/drawbeads.md).
//!
//! A drawbead is a polyline fixed to a tool (given in the tool's local
//! frame, so it moves with the tool) with a restraining force per unit
//! length `F_t` and a normal (clamping) force per unit length `F_n` (N/mm),
//! given per polyline point and linear in between. Where the bead crosses a
//! quad of the blank that touches the bead's tool, over the crossing length
//! `L`, it pulls the quad against its slip across the bead relative to the
//! tool with up to `∫ F_t ds` and pushes it away from the tool (onto the
//! opposite one) with `∫ F_n ds`; the reaction goes to the bead's tool.
//!
//! The restraint is elastic–plastic, like a friction return: the bead is cut
//! into bins of about [`DrawbeadSpec::spacing`] along its length, fixed to
//! the tool, each with a force per unit length `q` (N/mm) that follows the
//! slip across the bead with the stiffness `k = max F_t / δ` (N/mm²,
//! `δ` = [`DrawbeadSpec::elastic_slip`]) and is capped at the bin's `F_t`.
//! The state belongs to the bead, not to the quads, so the blank flows from
//! one quad to the next without losing the restraint. A bin no quad crosses
//! (the blank has left it, or is not clamped there) holds no force.

mod crossing;
mod set;

pub(crate) use set::{BeadInputs, BeadSet};

use plugins_api::{ToolSurface, Vec3};

use crate::{BlankGeometry, BlankView, ContactError};
use crossing::clip;

/// What a drawbead is built from.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawbeadSpec {
    /// Name (for messages and outputs).
    pub name: String,
    /// Index of the tool the bead is fixed to (as in [`crate::ContactEffect`]).
    pub tool: usize,
    /// The polyline in the tool's local frame (mm), at least two points.
    pub points: Vec<Vec3>,
    /// Restraining force per unit length `F_t` at each point (N/mm, `>= 0`).
    pub restraining: Vec<f64>,
    /// Normal (clamping) force per unit length `F_n` at each point (N/mm, `>= 0`).
    pub normal: Vec<f64>,
    /// Slip across the bead at which the restraint of the strongest point
    /// reaches its cap (mm, `> 0`): sets the stick stiffness.
    pub elastic_slip: f64,
    /// Length of the bins that carry the restraint's state (mm, `> 0`).
    pub spacing: f64,
}

/// Cumulative energies of a drawbead (N·mm = mJ).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct BeadEnergy {
    /// Dissipation of the restraint's slip, `Σ F_t Δu_plastic` (`>= 0`).
    pub dissipation: f64,
    /// Work of the bead's forces on the blank.
    pub blank_work: f64,
    /// Work the bead's tool does on the blank through the bead.
    pub tool_work: f64,
    /// Energy held in the bins' stick springs now, `Σ ½ q² ℓ / k`.
    pub stored: f64,
}

/// One quad a bead crosses in a step.
#[derive(Clone, Copy, Debug)]
struct Crossing {
    quad: u32,
    segment: u32,
    /// Arc length along the segment where the crossing starts and ends (mm).
    s0: f64,
    s1: f64,
    /// Unit in-plane direction across the bead.
    across: Vec3,
    /// Clamping force on the quad (N), away from the bead's tool.
    push: Vec3,
}

/// A drawbead fixed to a tool, with its per-bin state and its last step's forces.
#[derive(Clone, Debug)]
pub struct Drawbead {
    spec: DrawbeadSpec,
    /// Per segment: first bin, length (mm), bin length (mm).
    first_bin: Vec<usize>,
    seg_len: Vec<f64>,
    bin_len: Vec<f64>,
    /// Stick stiffness per unit length (N/mm²).
    k: f64,
    /// Per bin: force per unit length (N/mm), its cap `F_t` (N/mm), and the
    /// step's slip-weighted length and crossed length (mm², mm).
    q: Vec<f64>,
    cap: Vec<f64>,
    slip_len: Vec<f64>,
    crossed: Vec<f64>,
    /// The polyline at the tool's current pose (mm).
    world: Vec<Vec3>,
    crossings: Vec<Crossing>,
    /// Per quad: force on it this step and in the last step (N), and the
    /// step it was last crossed in.
    force: Vec<Vec3>,
    force_last: Vec<Vec3>,
    stamp: Vec<u64>,
    engaged: Vec<u32>,
    engaged_last: Vec<u32>,
    steps: u64,
    /// Restraining force (magnitude of the tangential resultant on the blank, N) of the last step.
    pub restraining_force: f64,
    /// Clamping force (sum of the normal forces on the blank, N) of the last step.
    pub normal_force: f64,
    /// Resultant force of the bead on the blank in the last step (N); the
    /// tool takes its opposite.
    pub resultant: Vec3,
    /// Length of the bead over clamped blank in the last step (mm).
    pub length_engaged: f64,
    /// Largest `restraining_force` of the steps so far (N).
    pub restraining_force_max: f64,
    /// Largest `length_engaged` of the steps so far (mm).
    pub length_engaged_max: f64,
    /// Cumulative energies.
    pub energy: BeadEnergy,
}

impl Drawbead {
    /// A bead over a blank of `quads` quads.
    ///
    /// # Errors
    /// Fewer than two points, a force list of another length, a negative or
    /// non-finite force, a non-positive slip or spacing, a zero-length segment.
    pub fn new(spec: DrawbeadSpec, quads: usize) -> Result<Self, ContactError> {
        check(&spec)?;
        let n_seg = spec.points.len() - 1;
        let (mut first_bin, mut seg_len, mut bin_len) = (Vec::new(), Vec::new(), Vec::new());
        let mut cap = Vec::new();
        for j in 0..n_seg {
            let len = (spec.points[j + 1] - spec.points[j]).norm();
            let n = (len / spec.spacing).ceil().max(1.0) as usize;
            first_bin.push(cap.len());
            seg_len.push(len);
            bin_len.push(len / n as f64);
            for i in 0..n {
                let t = (i as f64 + 0.5) / n as f64;
                cap.push(spec.restraining[j] * (1.0 - t) + spec.restraining[j + 1] * t);
            }
        }
        let f_max = spec.restraining.iter().copied().fold(0.0, f64::max);
        let bins = cap.len();
        Ok(Self {
            k: f_max / spec.elastic_slip,
            world: spec.points.clone(),
            spec,
            first_bin,
            seg_len,
            bin_len,
            q: vec![0.0; bins],
            cap,
            slip_len: vec![0.0; bins],
            crossed: vec![0.0; bins],
            crossings: Vec::with_capacity(quads),
            force: vec![Vec3::zeros(); quads],
            force_last: vec![Vec3::zeros(); quads],
            stamp: vec![u64::MAX; quads],
            engaged: Vec::with_capacity(quads),
            engaged_last: Vec::with_capacity(quads),
            steps: 0,
            restraining_force: 0.0,
            normal_force: 0.0,
            resultant: Vec3::zeros(),
            length_engaged: 0.0,
            restraining_force_max: 0.0,
            length_engaged_max: 0.0,
            energy: BeadEnergy::default(),
        })
    }

    /// The bead's specification.
    pub fn spec(&self) -> &DrawbeadSpec {
        &self.spec
    }

    /// The bead's name.
    pub fn name(&self) -> &str {
        &self.spec.name
    }

    /// The bead's tool.
    pub fn tool(&self) -> usize {
        self.spec.tool
    }

    /// The bead's length (mm).
    pub fn length(&self) -> f64 {
        self.seg_len.iter().sum()
    }

    /// The stick stiffness per unit length `max F_t / elastic_slip` (N/mm²).
    pub fn stiffness(&self) -> f64 {
        self.k
    }

    /// One step: the bead at the tool's pose, the clamped quads it crosses
    /// (`touching[i]`: node `i` touches a tool in this step), the bins'
    /// restraint, the forces on the crossed quads and the energies.
    pub(crate) fn step(
        &mut self,
        tool: &dyn ToolSurface,
        geometry: &BlankGeometry,
        blank: &BlankView<'_>,
        touching: &[bool],
        dt: f64,
    ) {
        self.steps += 1;
        let pose = tool.pose();
        for (w, p) in self.world.iter_mut().zip(&self.spec.points) {
            *w = pose.to_global(p);
        }
        self.find_crossings(geometry, blank, touching, dt, tool);
        self.update_bins();
        self.crossing_forces();
        self.book_work(geometry, blank, tool, dt);
    }

    /// The clamped quads the bead crosses, and each bin's slip across the
    /// bead (slip-weighted and crossed lengths). Clamped: the bead lies
    /// within one thickness of the quad's mid-plane (the tool's face within
    /// half a thickness of the blank's) and a node of the quad touches a tool.
    fn find_crossings(
        &mut self,
        geometry: &BlankGeometry,
        blank: &BlankView<'_>,
        touching: &[bool],
        dt: f64,
        tool: &dyn ToolSurface,
    ) {
        self.crossings.clear();
        self.engaged.clear();
        self.slip_len.iter_mut().for_each(|s| *s = 0.0);
        self.crossed.iter_mut().for_each(|s| *s = 0.0);
        for (e, quad) in geometry.quads().iter().enumerate() {
            if !quad.iter().any(|&i| touching[i as usize]) {
                continue;
            }
            let x = quad.map(|i| blank.x[i as usize]);
            let reach = quad
                .iter()
                .map(|&i| blank.thickness[i as usize])
                .fold(0.0, f64::max);
            let (lo, hi) = bounds(&x);
            for j in 0..self.seg_len.len() {
                let (a, b) = (self.world[j], self.world[j + 1]);
                if (0..3).any(|d| a[d].max(b[d]) < lo[d] - reach || a[d].min(b[d]) > hi[d] + reach)
                {
                    continue;
                }
                let Some(c) = clip(&a, &b, &x, reach) else {
                    continue;
                };
                // Away from the bead's line, which lies on the tool's face.
                let push_dir = if c.offset < 0.0 { -c.normal } else { c.normal };
                let (s0, s1) = (c.t0 * self.seg_len[j], c.t1 * self.seg_len[j]);
                let v: Vec3 = quad.iter().map(|&i| blank.v[i as usize]).sum::<Vec3>() * 0.25;
                let du = (v - tool.velocity_at(&c.centroid)).dot(&c.across) * dt;
                let (first, h) = (self.first_bin[j], self.bin_len[j]);
                for_bins(s0, s1, h, self.bins(j), |i, o| {
                    self.slip_len[first + i] += o * du;
                    self.crossed[first + i] += o;
                });
                let tm = 0.5 * (c.t0 + c.t1);
                let f_n = self.spec.normal[j] * (1.0 - tm) + self.spec.normal[j + 1] * tm;
                self.crossings.push(Crossing {
                    quad: e as u32,
                    segment: j as u32,
                    s0,
                    s1,
                    across: c.across,
                    push: push_dir * (f_n * (s1 - s0)),
                });
                if self.stamp[e] != self.steps {
                    self.stamp[e] = self.steps;
                    self.force[e] = Vec3::zeros();
                    self.engaged.push(e as u32);
                }
            }
        }
    }

    /// Number of bins of segment `j`.
    fn bins(&self, j: usize) -> usize {
        let end = self.first_bin.get(j + 1).copied().unwrap_or(self.q.len());
        end - self.first_bin[j]
    }

    /// The return mapping of every bin: trial `q + k Δu`, capped at `F_t`;
    /// a bin nothing crosses lets go. A bin counts at most its own length
    /// (where two quads both claim a piece of the line, along a shared edge).
    fn update_bins(&mut self) {
        let mut stored = 0.0;
        for j in 0..self.seg_len.len() {
            let (first, h) = (self.first_bin[j], self.bin_len[j]);
            for b in first..first + self.bins(j) {
                let crossed = self.crossed[b];
                if crossed <= 0.0 {
                    self.q[b] = 0.0;
                    continue;
                }
                let len = crossed.min(h);
                let trial = self.q[b] + self.k * self.slip_len[b] / crossed;
                let cap = self.cap[b];
                if trial.abs() > cap {
                    if self.k > 0.0 {
                        self.energy.dissipation += cap * (trial.abs() - cap) / self.k * len;
                    }
                    self.q[b] = cap.copysign(trial);
                } else {
                    self.q[b] = trial;
                }
                if self.k > 0.0 {
                    stored += 0.5 * self.q[b] * self.q[b] * len / self.k;
                }
            }
        }
        self.energy.stored = stored;
    }

    /// Each crossing's force on its quad: `−Σ q ℓ` across the bead plus the
    /// push, each bin's overlap `ℓ` scaled down where the crossings of the
    /// bin add up to more than its length.
    fn crossing_forces(&mut self) {
        let (mut tangential, mut normal, mut length) = (Vec3::zeros(), 0.0, 0.0);
        for c in &self.crossings {
            let j = c.segment as usize;
            let (first, h) = (self.first_bin[j], self.bin_len[j]);
            let (mut restraint, mut share) = (0.0, 0.0);
            for_bins(c.s0, c.s1, h, self.bins(j), |i, o| {
                let b = first + i;
                let o = o * (h / self.crossed[b]).min(1.0);
                restraint += self.q[b] * o;
                share += o;
            });
            let f_t = -c.across * restraint;
            let push = c.push * (share / (c.s1 - c.s0));
            self.force[c.quad as usize] += f_t + push;
            tangential += f_t;
            normal += push.norm();
            length += share;
        }
        self.restraining_force = tangential.norm();
        self.normal_force = normal;
        self.length_engaged = length;
        self.restraining_force_max = self.restraining_force_max.max(self.restraining_force);
        self.length_engaged_max = self.length_engaged_max.max(length);
    }

    /// The work of the quads' forces on the blank and of the tool, with the
    /// mid-step force `½ (F_{n+1} + F_n)` (quads let go complete theirs).
    fn book_work(
        &mut self,
        geometry: &BlankGeometry,
        blank: &BlankView<'_>,
        tool: &dyn ToolSurface,
        dt: f64,
    ) {
        let quads = geometry.quads();
        let work = |e: usize, f_mid: Vec3, energy: &mut BeadEnergy| {
            let x = quads[e].map(|i| blank.x[i as usize]);
            let v: Vec3 = quads[e].iter().map(|&i| blank.v[i as usize]).sum::<Vec3>() * 0.25;
            let c = (x[0] + x[1] + x[2] + x[3]) * 0.25;
            energy.blank_work += f_mid.dot(&v) * dt;
            energy.tool_work += f_mid.dot(&tool.velocity_at(&c)) * dt;
        };
        for &e in &self.engaged_last {
            let e = e as usize;
            if self.stamp[e] != self.steps {
                work(e, 0.5 * self.force_last[e], &mut self.energy);
                self.force_last[e] = Vec3::zeros();
            }
        }
        let mut resultant = Vec3::zeros();
        for &e in &self.engaged {
            let e = e as usize;
            work(
                e,
                0.5 * (self.force[e] + self.force_last[e]),
                &mut self.energy,
            );
            self.force_last[e] = self.force[e];
            resultant += self.force[e];
        }
        self.resultant = resultant;
        std::mem::swap(&mut self.engaged, &mut self.engaged_last);
    }

    /// Add the last step's forces to the nodes (a quarter of each quad's to each of its nodes).
    pub(crate) fn add_forces(&self, quads: &[[u32; 4]], forces: &mut [Vec3]) {
        for &e in &self.engaged_last {
            let f = 0.25 * self.force_last[e as usize];
            for &i in &quads[e as usize] {
                forces[i as usize] += f;
            }
        }
    }

    /// Whether the bead crossed clamped blank in the last step.
    pub fn engaged(&self) -> bool {
        !self.engaged_last.is_empty()
    }

    /// Add the stick springs of the last step's crossings to their nodes: `k L / 4`
    /// per node of a quad crossed over `L` (N/mm), a bound of the highest
    /// frequency of the quarter-shared spring `k L` (Gershgorin).
    pub(crate) fn add_nodal_stiffness(&self, quads: &[[u32; 4]], stiffness: &mut [f64]) {
        for c in &self.crossings {
            let s = 0.25 * self.k * (c.s1 - c.s0);
            for &i in &quads[c.quad as usize] {
                stiffness[i as usize] += s;
            }
        }
    }
}

/// Call `f(bin, overlap)` for every bin of length `h` (of `n` bins) that `[s0, s1]` overlaps.
fn for_bins(s0: f64, s1: f64, h: f64, n: usize, mut f: impl FnMut(usize, f64)) {
    let i0 = ((s0 / h).floor().max(0.0) as usize).min(n - 1);
    let i1 = ((s1 / h).ceil().max(0.0) as usize).min(n);
    for i in i0..i1 {
        let o = s1.min((i + 1) as f64 * h) - s0.max(i as f64 * h);
        if o > 0.0 {
            f(i, o);
        }
    }
}

/// The axis-aligned bounds of four points.
fn bounds(x: &[Vec3; 4]) -> (Vec3, Vec3) {
    let mut lo = x[0];
    let mut hi = x[0];
    for p in &x[1..] {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (lo, hi)
}

/// The checks of [`Drawbead::new`].
fn check(s: &DrawbeadSpec) -> Result<(), ContactError> {
    let bad = |field: &'static str, value: f64, unit: &'static str, range: &'static str| {
        Err(ContactError::OutOfRange {
            pair: format!("drawbead {}", s.name),
            field,
            value,
            unit,
            range,
        })
    };
    let n = s.points.len();
    if n < 2 {
        return bad("points", n as f64, "points", "at least 2");
    }
    if s.restraining.len() != n {
        return bad(
            "restraining_force",
            s.restraining.len() as f64,
            "values",
            "one per point",
        );
    }
    if s.normal.len() != n {
        return bad(
            "normal_force",
            s.normal.len() as f64,
            "values",
            "one per point",
        );
    }
    for &f in &s.restraining {
        if !(f.is_finite() && f >= 0.0) {
            return bad("restraining_force", f, "N/mm", "finite and >= 0");
        }
    }
    for &f in &s.normal {
        if !(f.is_finite() && f >= 0.0) {
            return bad("normal_force", f, "N/mm", "finite and >= 0");
        }
    }
    if !(s.elastic_slip.is_finite() && s.elastic_slip > 0.0) {
        return bad("elastic_slip", s.elastic_slip, "mm", "finite and > 0");
    }
    if !(s.spacing.is_finite() && s.spacing > 0.0) {
        return bad("spacing", s.spacing, "mm", "finite and > 0");
    }
    for w in s.points.windows(2) {
        let len = (w[1] - w[0]).norm();
        if !(len.is_finite() && len > 0.0) {
            return bad("points", len, "mm", "segments of finite, non-zero length");
        }
    }
    Ok(())
}
