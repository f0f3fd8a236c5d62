//! `ShellSet<E, M>`: a set of quads of one formulation and one material, owning their state, as a `fem_core::Effect`.
//!
//! State is laid out for the element loop: per element a thickness, a slice
//! of `IN_PLANE_POINTS × n` stresses and histories (in-plane point major,
//! bottom to top), `IN_PLANE_POINTS` transverse shear stresses and the
//! hourglass forces; every step each element writes its nodal forces and
//! energy increments into its own result slot (in parallel with rayon when
//! the set is large enough), and one serial pass scatters them onto the
//! nodes — so the result does not depend on the thread count.
//!
//! The set shares the blank's nodal thickness and outer-fibre flow stress
//! with the effects that read them (contact), as `fem-core` shared fields
//! ([`NodalField::THICKNESS`], [`NodalField::FLOW_STRESS_TOP`],
//! [`NodalField::FLOW_STRESS_BOTTOM`]), written at the end of its
//! `add_forces`; see [`ShellSet`].

use fem_core::{
    Effect, EnergyTally, FemError, FieldAccess, Forces, Mesh, NodalField, NodalState, StableDt,
    StepContext,
};
use rayon::prelude::*;

mod saved_state;

use crate::block_nodes::BlockNodes;
use crate::error::ShellError;
use crate::formulation::{ElementBlock, ElementResult, ElementState, ShellFormulation};
use crate::geometry::{Frame, V3};
use crate::lanes::F4;
use crate::material::Material;
use crate::outputs::{LogStrain, ShellElementOutput, log_membrane_strain};
use crate::section::Section;

/// Default number of elements from which the element loop runs in parallel.
pub const DEFAULT_PARALLEL_MIN: usize = 512;

/// The shared scalar nodal fields a [`ShellSet`] writes (each only when
/// another effect reads it).
const WRITES_SCALAR: [NodalField; 4] = [
    NodalField::THICKNESS,
    NodalField::FLOW_STRESS_TOP,
    NodalField::FLOW_STRESS_BOTTOM,
    NodalField::AREA,
];

/// Every shared nodal field a [`ShellSet`] writes: the scalars and the normal.
const WRITES: [NodalField; 5] = [
    NodalField::THICKNESS,
    NodalField::FLOW_STRESS_TOP,
    NodalField::FLOW_STRESS_BOTTOM,
    NodalField::AREA,
    NodalField::NORMAL,
];

/// Shells of formulation `E` and material `M` over a set of quads.
///
/// As a [`fem_core::Effect`] it writes the shared nodal fields
/// [`NodalField::THICKNESS`] (mm) and, when an effect reads them,
/// [`NodalField::FLOW_STRESS_TOP`] / [`NodalField::FLOW_STRESS_BOTTOM`]
/// (MPa): at each node, the mean over the elements around it of the element
/// thickness and of [`ShellSet::outer_flow_stress`] (sum over the elements in
/// element order, times the inverse valence). A node of no element gets the
/// section's initial thickness and zero flow stress.
///
/// Time level: they are written at the end of `add_forces`, after the
/// elements have updated their thickness and plastic state for the
/// configuration at `t_{n+1}`; the solver runs the shells before their
/// readers, so contact measures its gaps at `t_{n+1}` with the thickness at
/// `t_{n+1}` computed in the same step (no one-step lag).
#[derive(Debug, Clone)]
pub struct ShellSet<E: ShellFormulation, M: Material> {
    name: String,
    formulation: E,
    material: M,
    section: Section,
    conn: Vec<[u32; 4]>,
    /// Per node (of the node list given to [`ShellSet::new`]): 1 / the number
    /// of elements around it (0 for a node of no element).
    inv_valence: Vec<f64>,
    thickness: Vec<f64>,
    stress: Vec<[f64; 3]>,
    history: Vec<M::History>,
    shear: Vec<[f64; 2]>,
    hourglass: Vec<f64>,
    drilling: Vec<[f64; 4]>,
    drilling_energy: f64,
    density_scale: Vec<f64>,
    /// Per element `1 + β_e`: selective mass scaling's factor on the
    /// inertia of its deformation modes (1 without).
    selective_scale: Vec<f64>,
    /// Results of the elements after the last whole block (`len % 4` of them).
    results: Vec<ElementResult>,
    /// Results of the blocks of four (element `4b + l` in lane `l` of entry `b`).
    results_x4: Vec<ElementResult<F4>>,
    /// Largest node index of the connectivity (checked against the state once per step).
    max_node: usize,
    energy: EnergyTally,
    cached_dt: Option<StableDt>,
    /// Whether `results`/`results_x4` hold the last forces' lengths and areas.
    forces_computed: bool,
    parallel_min: usize,
    wave_speed: f64,
    /// Blocks of four elements store stress, shear, hourglass and drilling
    /// state lane-major (see [`ElementBlock`]), as the formulation asks.
    lane_major: bool,
}

fn v3(p: &fem_core::Vec3) -> V3 {
    [p.x, p.y, p.z]
}

/// The nodal areas and area-weighted normals the shells write when another
/// effect reads them ([`NodalField::AREA`], [`NodalField::NORMAL`]),
/// summed over the elements in the serial scatter.
struct NodalFrames<'a> {
    area: &'a mut [f64],
    normal: &'a mut [fem_core::Vec3],
}

impl<'a> NodalFrames<'a> {
    /// The two fields zeroed, when both are written.
    fn new(area: Option<&'a mut [f64]>, normal: Option<&'a mut [fem_core::Vec3]>) -> Option<Self> {
        let (area, normal) = (area?, normal?);
        area.fill(0.0);
        normal.fill(fem_core::Vec3::zeros());
        Some(Self { area, normal })
    }

    /// Element of nodes `q`, projected area `a` (mm²) and unit normal `n`:
    /// a quarter of `a` to each node's area, `a n` to its normal sum.
    #[inline(always)]
    fn add(&mut self, q: &[u32; 4], a: f64, n: [f64; 3]) {
        let an = fem_core::Vec3::new(n[0] * a, n[1] * a, n[2] * a);
        for &i in q {
            let i = i as usize;
            self.area[i] += 0.25 * a;
            self.normal[i] += an;
        }
    }
}

/// What every element's kernel reads in one step: the formulation,
/// material and section, the nodal state, the step.
struct Kernel<'a, E, M> {
    form: &'a E,
    mat: &'a M,
    sec: &'a Section,
    xs: &'a [fem_core::Vec3],
    vs: &'a [fem_core::Vec3],
    ws: &'a [fem_core::Vec3],
    dt: f64,
}

impl<E: ShellFormulation, M: Material> Kernel<'_, E, M> {
    /// One element (node indices `q`) with its state slices.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn one(
        &self,
        q: &[u32; 4],
        t: &mut f64,
        s: &mut [[f64; 3]],
        h: &mut [M::History],
        sh: &mut [[f64; 2]],
        hg: &mut [f64],
        dr: &mut [f64; 4],
        r: &mut ElementResult,
    ) {
        let x = q.map(|n| v3(&self.xs[n as usize]));
        let v = q.map(|n| v3(&self.vs[n as usize]));
        let w = q.map(|n| v3(&self.ws[n as usize]));
        *r = self.form.compute(
            self.mat,
            self.sec,
            &x,
            &v,
            &w,
            self.dt,
            ElementState {
                thickness: t,
                stress: s,
                history: h,
                shear: sh,
                hourglass: &mut hg[..E::HOURGLASS_VARS],
                drilling: dr,
            },
        );
    }

    /// A block of four consecutive elements through the formulation's
    /// four-element kernel.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn block(
        &self,
        q: &[[u32; 4]; 4],
        t: &mut [f64; 4],
        s: &mut [[f64; 3]],
        h: &mut [M::History],
        sh: &mut [[f64; 2]],
        hg: &mut [f64],
        dr: &mut [[f64; 4]; 4],
        r: &mut ElementResult<F4>,
    ) {
        // SAFETY: every node index is at most `max_node`, which `add_forces`
        // checked against the three arrays' lengths before any kernel runs.
        let nodes = unsafe { BlockNodes::new_unchecked(self.xs, self.vs, self.ws, q) };
        self.form.compute_x4(
            self.mat,
            self.sec,
            &nodes,
            self.dt,
            ElementBlock {
                thickness: t,
                stress: s,
                history: h,
                shear: sh,
                hourglass: hg,
                drilling: dr,
            },
            r,
        );
    }
}

/// The serial part of a step: element results added to the nodal forces,
/// energy increments summed (internal, hourglass, plastic, drilling) and the
/// smallest stable time step kept.
struct Scatter {
    best: StableDt,
    energy: [f64; 4],
}

impl Scatter {
    /// Element `e` with nodes `q`: false (and nothing added) when its
    /// length says it degenerated. `fm(k, i)`: component `i` of node `k`'s
    /// force and moment.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn element(
        &mut self,
        forces: &mut Forces,
        e: usize,
        q: &[u32; 4],
        length: f64,
        density_scale: f64,
        wave_speed: f64,
        energy: [f64; 4],
        fm: impl Fn(usize, usize) -> (f64, f64),
    ) -> bool {
        if length.is_nan() || length <= 0.0 {
            return false;
        }
        for k in 0..4 {
            let n = q[k] as usize;
            let (f, m) = (&mut forces.f[n], &mut forces.m[n]);
            let ((fx, mx), (fy, my), (fz, mz)) = (fm(k, 0), fm(k, 1), fm(k, 2));
            f.x += fx;
            f.y += fy;
            f.z += fz;
            m.x += mx;
            m.y += my;
            m.z += mz;
        }
        for (s, d) in self.energy.iter_mut().zip(energy) {
            *s += d;
        }
        let dte = length * density_scale.sqrt() / wave_speed;
        if dte < self.best.dt {
            self.best.dt = dte;
            self.best.element = e;
        }
        true
    }
}

impl<E: ShellFormulation, M: Material> ShellSet<E, M> {
    /// Shells on `quads` (0-based node indices into `nodes`, counter-clockwise
    /// seen from the shell's top) with one section, formulation and material.
    ///
    /// Errors name the element: node index out of range or repeated, zero
    /// area, inverted or non-convex corner.
    pub fn new(
        name: impl Into<String>,
        nodes: &[fem_core::Vec3],
        quads: &[[u32; 4]],
        section: Section,
        formulation: E,
        material: M,
    ) -> Result<Self, ShellError> {
        crate::error::check(
            "thickness",
            section.thickness,
            "mm",
            "> 0",
            section.thickness > 0.0,
        )?;
        formulation.validate()?;
        for (e, q) in quads.iter().enumerate() {
            for (k, &n) in q.iter().enumerate() {
                if n as usize >= nodes.len() {
                    return Err(ShellError::BadElement {
                        element: e,
                        reason: "node index out of range",
                        measure: "node index",
                        value: n as f64,
                    });
                }
                if q[..k].contains(&n) {
                    return Err(ShellError::BadElement {
                        element: e,
                        reason: "a node appears twice in the connectivity",
                        measure: "node index",
                        value: n as f64,
                    });
                }
            }
            let x = q.map(|n| v3(&nodes[n as usize]));
            let fr = Frame::new(&x);
            if fr.area.is_nan() || fr.area <= 0.0 {
                return Err(ShellError::BadElement {
                    element: e,
                    reason: "zero or undefined area",
                    measure: "area (mm²)",
                    value: fr.area,
                });
            }
            let (corner, q) = fr.corner_quality();
            if q <= 1e-3 {
                return Err(ShellError::BadElement {
                    element: e,
                    reason: match corner {
                        0 => "inverted or non-convex at its 1st corner",
                        1 => "inverted or non-convex at its 2nd corner",
                        2 => "inverted or non-convex at its 3rd corner",
                        _ => "inverted or non-convex at its 4th corner",
                    },
                    measure: "corner cross product / area (-)",
                    value: q,
                });
            }
        }
        let ne = quads.len();
        let ip = E::IN_PLANE_POINTS;
        let np = section.rule.n;
        let nu = material.poisson();
        let wave_speed = (material.young() / (material.density() * (1.0 - nu * nu))).sqrt();
        Ok(Self {
            name: name.into(),
            inv_valence: inverse_valence(nodes.len(), quads),
            thickness: vec![section.thickness; ne],
            stress: vec![[0.0; 3]; ne * ip * np],
            history: vec![material.initial_history(); ne * ip * np],
            shear: vec![[0.0; 2]; ne * ip],
            hourglass: vec![0.0; ne * E::HOURGLASS_VARS.max(1)],
            drilling: vec![[0.0; 4]; ne],
            drilling_energy: 0.0,
            density_scale: vec![1.0; ne],
            selective_scale: vec![1.0; ne],
            results: vec![ElementResult::default(); ne % 4],
            results_x4: vec![ElementResult::default(); ne / 4],
            max_node: quads
                .iter()
                .flatten()
                .map(|&n| n as usize)
                .max()
                .unwrap_or(0),
            energy: EnergyTally::default(),
            cached_dt: None,
            forces_computed: false,
            parallel_min: DEFAULT_PARALLEL_MIN,
            wave_speed,
            lane_major: formulation.lane_major(&section),
            conn: quads.to_vec(),
            formulation,
            material,
            section,
        })
    }

    /// Shells on the quads of element set `set` of `mesh` (`all` for every quad).
    pub fn from_mesh(
        name: impl Into<String>,
        mesh: &Mesh,
        set: &str,
        section: Section,
        formulation: E,
        material: M,
    ) -> Result<Self, FemError> {
        let ids = mesh.element_set(set)?;
        let quads: Vec<[u32; 4]> = ids.iter().map(|&e| mesh.quads[e as usize]).collect();
        Ok(Self::new(
            name,
            &mesh.nodes,
            &quads,
            section,
            formulation,
            material,
        )?)
    }

    /// Run the element loop in parallel from `n` elements on (serial below,
    /// and on one rayon thread); `usize::MAX` keeps it serial.
    pub fn with_parallel_min(mut self, n: usize) -> Self {
        self.parallel_min = n;
        self
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.conn.len()
    }
    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.conn.is_empty()
    }
    /// Connectivity.
    pub fn quads(&self) -> &[[u32; 4]] {
        &self.conn
    }
    /// The section.
    pub fn section(&self) -> &Section {
        &self.section
    }
    /// The material.
    pub fn material(&self) -> &M {
        &self.material
    }
    /// The formulation.
    pub fn formulation(&self) -> &E {
        &self.formulation
    }
    /// Integration points per element (in-plane × through-thickness).
    pub fn points_per_element(&self) -> usize {
        E::IN_PLANE_POINTS * self.section.rule.n
    }

    fn point_index(&self, e: usize, in_plane: usize, k: usize) -> usize {
        (e * E::IN_PLANE_POINTS + in_plane) * self.section.rule.n + k
    }

    /// Current thickness of element `e` (mm).
    pub fn thickness(&self, e: usize) -> f64 {
        self.thickness[e]
    }
    /// Block and lane of element `e` if its state is stored lane-major.
    fn lane_slot(&self, e: usize) -> Option<(usize, usize)> {
        (self.lane_major && e < self.conn.len() / 4 * 4).then_some((e / 4, e % 4))
    }

    /// Stress `[σ_xx, σ_yy, σ_xy]` (MPa, co-rotational frame) at in-plane point
    /// `p` and through-thickness point `k` (bottom = 0) of element `e`.
    pub fn stress(&self, e: usize, p: usize, k: usize) -> [f64; 3] {
        match self.lane_slot(e) {
            Some((b, l)) => {
                let nsp = self.points_per_element();
                let kk = p * self.section.rule.n + k;
                let flat = &self.stress.as_flattened()[b * 12 * nsp..];
                [0, 1, 2].map(|c| flat[(3 * kk + c) * 4 + l])
            }
            None => self.stress[self.point_index(e, p, k)],
        }
    }
    /// Transverse shear stresses `[τ_xz, τ_yz]` (MPa) at in-plane point `p` of element `e`.
    pub fn transverse_shear(&self, e: usize, p: usize) -> [f64; 2] {
        match self.lane_slot(e) {
            Some((b, l)) => {
                let flat = &self.shear.as_flattened()[b * 8 * E::IN_PLANE_POINTS..];
                [0, 1].map(|c| flat[(2 * p + c) * 4 + l])
            }
            None => self.shear[e * E::IN_PLANE_POINTS + p],
        }
    }
    /// Material history at a point (see [`ShellSet::stress`] for the indices).
    pub fn history(&self, e: usize, p: usize, k: usize) -> &M::History {
        &self.history[self.point_index(e, p, k)]
    }
    /// Drilling moments (N·mm) about the normal of element `e` at its four
    /// nodes (the relative drilling penalty's state).
    pub fn drilling_moments(&self, e: usize) -> [f64; 4] {
        match self.lane_slot(e) {
            Some((b, l)) => [0, 1, 2, 3].map(|i| self.drilling[4 * b + i][l]),
            None => self.drilling[e],
        }
    }
    /// Hourglass generalised force `k` (N or N·mm, `k <
    /// HOURGLASS_VARS` of the formulation) of element `e`, in the frame
    /// the formulation keeps it in (Belytschko–Tsay: membrane x, y,
    /// bending x, y, transverse, in the element's co-rotational frame).
    pub fn hourglass_force(&self, e: usize, k: usize) -> f64 {
        let nhg = E::HOURGLASS_VARS.max(1);
        match self.lane_slot(e) {
            Some((b, l)) => self.hourglass[4 * nhg * b + 4 * k + l],
            None => self.hourglass[nhg * e + k],
        }
    }
    /// Overwrite element `e`'s state (the static shells' committed state
    /// after a static solve): its thickness (mm), the stress and history
    /// of each point (`point(p, k)`: in-plane point `p`, through-thickness
    /// point `k`), the transverse shear stresses of each in-plane point
    /// (`shear(p)`), the hourglass generalised forces and the drilling
    /// moments, in the layouts [`ShellSet::stress`] and its siblings read.
    /// The cached stable step is dropped.
    pub(crate) fn restore_element(
        &mut self,
        e: usize,
        thickness: f64,
        point: impl Fn(usize, usize) -> ([f64; 3], M::History),
        shear: impl Fn(usize) -> [f64; 2],
        hourglass: &[f64],
        drilling: [f64; 4],
    ) {
        let (n, ip, nhg) = (
            self.section.rule.n,
            E::IN_PLANE_POINTS,
            E::HOURGLASS_VARS.max(1),
        );
        self.thickness[e] = thickness;
        for p in 0..ip {
            for k in 0..n {
                let (stress, history) = point(p, k);
                let i = self.point_index(e, p, k);
                self.history[i] = history;
                match self.lane_slot(e) {
                    Some((b, l)) => {
                        let kk = p * n + k;
                        let flat = &mut self.stress.as_flattened_mut()[b * 12 * n * ip..];
                        for c in 0..3 {
                            flat[(3 * kk + c) * 4 + l] = stress[c];
                        }
                    }
                    None => self.stress[i] = stress,
                }
            }
        }
        match self.lane_slot(e) {
            Some((b, l)) => {
                let flat = &mut self.shear.as_flattened_mut()[b * 8 * ip..];
                for p in 0..ip {
                    let tau = shear(p);
                    flat[2 * p * 4 + l] = tau[0];
                    flat[(2 * p + 1) * 4 + l] = tau[1];
                }
                for (i, m) in drilling.iter().enumerate() {
                    self.drilling[4 * b + i][l] = *m;
                }
                for (k, q) in hourglass.iter().enumerate().take(nhg) {
                    self.hourglass[4 * nhg * b + 4 * k + l] = *q;
                }
            }
            None => {
                for p in 0..ip {
                    self.shear[e * ip + p] = shear(p);
                }
                self.drilling[e] = drilling;
                for (k, q) in hourglass.iter().enumerate().take(nhg) {
                    self.hourglass[nhg * e + k] = *q;
                }
            }
        }
        self.cached_dt = None;
    }

    /// Add the work of a static solve (its committed increments) to the
    /// set's energies: internal (with its plastic share) and hourglass.
    pub(crate) fn add_static_work(&mut self, w: &EnergyTally) {
        self.energy.internal += w.internal;
        self.energy.hourglass += w.hourglass;
        self.energy.plastic += w.plastic;
    }

    /// Work stored in the drilling penalty since the start (mJ); part of
    /// the internal energy the set reports.
    pub fn drilling_energy(&self) -> f64 {
        self.drilling_energy
    }
    /// Von Mises (equivalent) stress at a point (MPa).
    pub fn von_mises(&self, e: usize, p: usize, k: usize) -> f64 {
        self.material.equivalent_stress(&self.stress(e, p, k))
    }
    /// Equivalent plastic strain at a point (-).
    pub fn plastic_strain(&self, e: usize, p: usize, k: usize) -> f64 {
        self.material.plastic_strain(self.history(e, p, k))
    }
    /// Flow stress at the outer fibres `[bottom, top]` (MPa): the outermost
    /// through-thickness points (on the surfaces for a Lobatto rule),
    /// averaged over the in-plane points. Friction's Levanov law reads it.
    pub fn outer_flow_stress(&self, e: usize) -> [f64; 2] {
        let n = self.section.rule.n;
        let ip = E::IN_PLANE_POINTS;
        let (mut b, mut t) = (0.0, 0.0);
        for p in 0..ip {
            b += self.material.flow_stress(self.history(e, p, 0));
            t += self.material.flow_stress(self.history(e, p, n - 1));
        }
        [b / ip as f64, t / ip as f64]
    }
    /// Membrane (mid-surface) resultants of element `e` from its current
    /// stresses, averaged over in-plane points: `[N_xx, N_yy, N_xy]` (N/mm) and
    /// `[M_xx, M_yy, M_xy]` (N·mm/mm), co-rotational frame.
    pub fn resultants(&self, e: usize) -> ([f64; 3], [f64; 3]) {
        let h = 0.5 * self.thickness[e];
        let (z, w) = self.section.rule.points();
        let ip = E::IN_PLANE_POINTS;
        let mut n = [0.0; 3];
        let mut m = [0.0; 3];
        for p in 0..ip {
            for k in 0..z.len() {
                let s = self.stress(e, p, k);
                for c in 0..3 {
                    n[c] += w[k] * h * s[c] / ip as f64;
                    m[c] += w[k] * h * h * z[k] * s[c] / ip as f64;
                }
            }
        }
        (n, m)
    }

    /// Logarithmic membrane strain of element `e`, from the deformation
    /// gradient of the mid-surface at the element centre between `x0` and `x`.
    pub fn membrane_strain(&self, e: usize, state: &NodalState) -> LogStrain {
        let q = self.conn[e];
        let x0 = q.map(|n| v3(&state.x0[n as usize]));
        let x = q.map(|n| v3(&state.x[n as usize]));
        log_membrane_strain(&x0, &x)
    }

    /// Every output of every element (allocates: for output, not for the step loop).
    pub fn element_outputs(&self, state: &NodalState) -> Vec<ShellElementOutput> {
        let ip = E::IN_PLANE_POINTS;
        let n = self.section.rule.n;
        (0..self.len())
            .map(|e| {
                let mut vm = Vec::with_capacity(ip * n);
                let mut eps_sum = 0.0;
                let mut eps_max: f64 = 0.0;
                for p in 0..ip {
                    for k in 0..n {
                        vm.push(self.von_mises(e, p, k));
                        let ep = self.plastic_strain(e, p, k);
                        eps_sum += ep;
                        eps_max = eps_max.max(ep);
                    }
                }
                ShellElementOutput {
                    strain: self.membrane_strain(e, state),
                    thickness: self.thickness[e],
                    thickness_strain: (self.thickness[e] / self.section.thickness).ln(),
                    plastic_strain_mean: eps_sum / (ip * n) as f64,
                    plastic_strain_max: eps_max,
                    von_mises: vm,
                    outer_flow_stress: self.outer_flow_stress(e),
                }
            })
            .collect()
    }

    /// Every element's forces into `results_x4` / `results` (blocks of four
    /// consecutive elements through the formulation's four-element kernel,
    /// SIMD lanes for BT; the rest one by one), stresses and histories
    /// updated; in parallel from `parallel_min` elements on, with more than
    /// one rayon thread. The nodal state holds every node the shells use
    /// (checked by the caller).
    fn compute_elements(&mut self, dt: f64, state: &NodalState) {
        let ip = E::IN_PLANE_POINTS;
        let nsp = ip * self.section.rule.n;
        let nhg = E::HOURGLASS_VARS.max(1);
        let kernel = Kernel {
            form: &self.formulation,
            mat: &self.material,
            sec: &self.section,
            xs: &state.x,
            vs: &state.v,
            ws: &state.w,
            dt,
        };
        let nb = self.conn.len() / 4;
        let (conn_b, conn_r) = self.conn.as_chunks::<4>();
        let (t_b, t_r) = self.thickness.as_chunks_mut::<4>();
        let (dr_b, dr_r) = self.drilling.as_chunks_mut::<4>();
        let (s_b, s_r) = self.stress.split_at_mut(4 * nb * nsp);
        let (h_b, h_r) = self.history.split_at_mut(4 * nb * nsp);
        let (sh_b, sh_r) = self.shear.split_at_mut(4 * nb * ip);
        let (hg_b, hg_r) = self.hourglass.split_at_mut(4 * nb * nhg);
        let res_b = &mut self.results_x4[..];
        // One thread runs the loop itself: rayon's one worker would take it
        // over and hand it back at every step, two thread switches a step.
        if self.conn.len() >= self.parallel_min && rayon::current_num_threads() > 1 {
            conn_b
                .par_iter()
                .zip(t_b.par_iter_mut())
                .zip(s_b.par_chunks_mut(4 * nsp))
                .zip(h_b.par_chunks_mut(4 * nsp))
                .zip(sh_b.par_chunks_mut(4 * ip))
                .zip(hg_b.par_chunks_mut(4 * nhg))
                .zip(dr_b.par_iter_mut())
                .zip(res_b.par_iter_mut())
                .with_min_len(32)
                .for_each(|(((((((q, t), s), h), sh), hg), dr), r)| {
                    kernel.block(q, t, s, h, sh, hg, dr, r)
                });
        } else {
            conn_b
                .iter()
                .zip(t_b.iter_mut())
                .zip(s_b.chunks_mut(4 * nsp))
                .zip(h_b.chunks_mut(4 * nsp))
                .zip(sh_b.chunks_mut(4 * ip))
                .zip(hg_b.chunks_mut(4 * nhg))
                .zip(dr_b.iter_mut())
                .zip(res_b.iter_mut())
                .for_each(|(((((((q, t), s), h), sh), hg), dr), r)| {
                    kernel.block(q, t, s, h, sh, hg, dr, r)
                });
        }
        conn_r
            .iter()
            .zip(t_r.iter_mut())
            .zip(s_r.chunks_mut(nsp))
            .zip(h_r.chunks_mut(nsp))
            .zip(sh_r.chunks_mut(ip))
            .zip(hg_r.chunks_mut(nhg))
            .zip(dr_r.iter_mut())
            .zip(self.results.iter_mut())
            .for_each(|(((((((q, t), s), h), sh), hg), dr), r)| {
                kernel.one(q, t, s, h, sh, hg, dr, r)
            });
    }

    /// The serial part of a step after the elements: each element's forces
    /// and moments onto its nodes, energies, the stable step, the nodal
    /// fields; the blocks' results read in their lanes. An element that
    /// degenerated stops it with an error naming it.
    fn scatter(
        &mut self,
        ctx: &StepContext,
        forces: &mut Forces,
        fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        let mut acc = Scatter {
            best: StableDt {
                dt: f64::INFINITY,
                element: 0,
                what: "shell area / longest side / plate wave speed",
            },
            energy: [0.0; 4],
        };
        let c = self.wave_speed;
        let (ds, ss) = (&self.density_scale, &self.selective_scale);
        let ([thickness, top, bottom, area], [normal]) =
            fields.write_each(WRITES_SCALAR, [NodalField::NORMAL]);
        let mut frames = NodalFrames::new(area, normal);
        let nb = self.conn.len() / 4;
        let (conn_b, conn_r) = self.conn.as_chunks::<4>();
        let mut bad = None;
        'blocks: for (b, (qs, r)) in conn_b.iter().zip(&self.results_x4).enumerate() {
            for l in 0..4 {
                let e = 4 * b + l;
                let en = [
                    r.d_internal.0[l],
                    r.d_hourglass.0[l],
                    r.d_plastic.0[l],
                    r.d_drilling.0[l],
                ];
                let ok = acc.element(
                    forces,
                    e,
                    &qs[l],
                    r.length.0[l],
                    ds[e] * ss[e],
                    c,
                    en,
                    |k, i| (r.f[k][i].0[l], r.m[k][i].0[l]),
                );
                if !ok {
                    bad = Some((e, r.length.0[l]));
                    break 'blocks;
                }
                if let Some(g) = frames.as_mut() {
                    let n = [r.normal[0].0[l], r.normal[1].0[l], r.normal[2].0[l]];
                    g.add(&qs[l], r.area.0[l], n);
                }
            }
        }
        if bad.is_none() {
            for (j, (q, r)) in conn_r.iter().zip(&self.results).enumerate() {
                let e = 4 * nb + j;
                let en = [r.d_internal, r.d_hourglass, r.d_plastic, r.d_drilling];
                if !acc.element(forces, e, q, r.length, ds[e] * ss[e], c, en, |k, i| {
                    (r.f[k][i], r.m[k][i])
                }) {
                    bad = Some((e, r.length));
                    break;
                }
                if let Some(g) = frames.as_mut() {
                    g.add(q, r.area, r.normal);
                }
            }
        }
        if let Some((e, length)) = bad {
            self.cached_dt = Some(StableDt {
                dt: 0.0,
                element: e,
                what: "shell degenerated (zero or negative area)",
            });
            return Err(FemError::Element {
                effect: self.name.clone(),
                element: e,
                message: format!(
                    "shell inverted or degenerated at t = {} s (projected area or Jacobian {length} mm²)",
                    ctx.time
                ),
            });
        }
        let (best, [di, dh, dp, dd]) = (acc.best, acc.energy);
        self.energy.internal += di;
        self.energy.hourglass += dh;
        self.energy.plastic += dp;
        self.drilling_energy += dd;
        self.forces_computed = true;
        self.cached_dt = if self.conn.is_empty() {
            None
        } else {
            Some(best)
        };
        self.write_fields(thickness, top, bottom);
        Ok(())
    }

    /// Write the shared nodal fields that another effect reads (no allocation).
    fn write_fields(
        &self,
        thickness: Option<&mut [f64]>,
        top: Option<&mut [f64]>,
        bottom: Option<&mut [f64]>,
    ) {
        if let Some(out) = thickness {
            self.nodal_mean(out, self.section.thickness, |e| self.thickness[e]);
        }
        if let (Some(top), Some(bottom)) = (top, bottom) {
            top.fill(0.0);
            bottom.fill(0.0);
            for (e, q) in self.conn.iter().enumerate() {
                let [b, t] = self.outer_flow_stress(e);
                for &n in q {
                    bottom[n as usize] += b;
                    top[n as usize] += t;
                }
            }
            self.scale_by_valence(top, 0.0);
            self.scale_by_valence(bottom, 0.0);
        }
    }

    /// `out[n]` = mean of `value(e)` over the elements `e` around node `n`
    /// (sum in element order, times the inverse valence); `fallback` at a
    /// node of no element.
    fn nodal_mean(&self, out: &mut [f64], fallback: f64, value: impl Fn(usize) -> f64) {
        out.fill(0.0);
        for (e, q) in self.conn.iter().enumerate() {
            let v = value(e);
            for &n in q {
                out[n as usize] += v;
            }
        }
        self.scale_by_valence(out, fallback);
    }

    /// Turn nodal sums over the elements into means; `fallback` at a node of no element.
    fn scale_by_valence(&self, out: &mut [f64], fallback: f64) {
        for (i, o) in out.iter_mut().enumerate() {
            match self.inv_valence.get(i) {
                Some(&w) if w > 0.0 => *o *= w,
                _ => *o = fallback,
            }
        }
    }

    /// The factor that divides element `e`'s squared frequencies: its
    /// conventional density scale times its selective factor `1 + β_e`.
    fn dt_scale(&self, e: usize) -> f64 {
        self.density_scale[e] * self.selective_scale[e]
    }

    fn element_dt(&self, e: usize, length: f64) -> f64 {
        length * self.dt_scale(e).sqrt() / self.wave_speed
    }

    fn dt_from_state(&self, state: &NodalState) -> Option<StableDt> {
        let mut best: Option<StableDt> = None;
        for (e, q) in self.conn.iter().enumerate() {
            let x = q.map(|n| v3(&state.x[n as usize]));
            let fr = Frame::new(&x);
            let (dt, what) = if fr.area > 0.0 {
                (
                    self.element_dt(e, fr.char_length()),
                    "shell area / longest side / plate wave speed",
                )
            } else {
                (0.0, "shell degenerated (zero or negative area)")
            };
            if best.is_none_or(|b| dt < b.dt) {
                best = Some(StableDt {
                    dt,
                    element: e,
                    what,
                });
            }
        }
        best
    }
}

/// Per node: 1 / the number of `quads` around it (0 for a node of none).
fn inverse_valence(nodes: usize, quads: &[[u32; 4]]) -> Vec<f64> {
    let mut valence = vec![0u32; nodes];
    for &n in quads.iter().flatten() {
        valence[n as usize] += 1;
    }
    valence
        .iter()
        .map(|&v| if v > 0 { 1.0 / v as f64 } else { 0.0 })
        .collect()
}

impl<E: ShellFormulation, M: Material> Effect for ShellSet<E, M> {
    fn name(&self) -> &str {
        &self.name
    }

    /// Every point's stress and history, the element state and thickness.
    fn save_state(&self, out: &mut fem_core::StateArrays) {
        self.save_arrays(out);
    }

    /// The saved state, refused for another mesh or point layout.
    fn restore_state(
        &mut self,
        saved: &fem_core::StateArrays,
        _notes: &mut Vec<String>,
    ) -> Result<(), String> {
        self.restore_arrays(saved)
    }

    /// The formulation's static form of the set ([`ShellFormulation::static_form`]).
    fn static_form(&self) -> Result<fem_core::StaticForm, String> {
        E::static_form(self)
    }

    /// The static solve's committed state taken back ([`ShellFormulation::absorb_static`]).
    fn absorb_static(
        &mut self,
        solved: &dyn fem_core::statics::StaticTangent,
        _x: &[fem_core::Vec3],
    ) -> Result<(), String> {
        E::absorb_static(self, solved)
    }

    /// The nodal thickness and the outer-fibre flow stress (see [`ShellSet`]).
    fn writes(&self) -> &[NodalField] {
        &WRITES
    }

    /// Translational mass ρ A t0 / 4 per node; rotational inertia
    /// `(ρ A t0 / 4)(t0²/12 + A/8)` per node: the `A/8` term scales the
    /// rotary inertia so that rotations (bending, transverse shear, and the
    /// drilling penalty: `ω_drill Δt ≲ 2√(γ(1−ν))`, below 0.6 for γ ≤ 0.1)
    /// never control the time step, which stays the membrane one.
    fn add_lumped_mass(&self, state: &NodalState, mass: &mut [f64], inertia: &mut [f64]) {
        let rho = self.material.density();
        let t = self.section.thickness;
        for q in &self.conn {
            let x = q.map(|n| v3(&state.x0[n as usize]));
            let a = Frame::new(&x).area;
            let m = 0.25 * rho * a * t;
            let i = m * (t * t / 12.0 + a / 8.0);
            for &n in q {
                mass[n as usize] += m;
                inertia[n as usize] += i;
            }
        }
    }

    fn stable_dt(&self, state: &NodalState) -> Option<StableDt> {
        self.cached_dt.or_else(|| self.dt_from_state(state))
    }

    fn stiffens_nodes(&self) -> bool {
        !self.conn.is_empty()
    }

    /// Per element `ρ t A c² / L²` (N/mm) on each of its four nodes: the
    /// element's step `L √s / c` is `2 √(m_e / κ_e)` with its nodal mass
    /// share `m_e = s ρ A t / 4` (`s` its density scale), so a node of one
    /// element gets the element's own step back; a node between elements
    /// gets their mass-weighted frequency. Physical stiffness: mass scaling
    /// does not change it. From the last forces' lengths and areas (before
    /// the first forces, from the element frames of `state`).
    fn nodal_stiffness(&self, state: &NodalState, stiffness: &mut [f64]) {
        let rho_c2 = self.material.density() * self.wave_speed * self.wave_speed;
        let mut add = |e: usize, q: &[u32; 4], length: f64, area: f64| {
            if length > 0.0 {
                let k =
                    rho_c2 * area * self.thickness[e] / (length * length * self.selective_scale[e]);
                for &n in q {
                    stiffness[n as usize] += k;
                }
            }
        };
        if !self.forces_computed {
            for (e, q) in self.conn.iter().enumerate() {
                let fr = Frame::new(&q.map(|n| v3(&state.x[n as usize])));
                add(e, q, fr.char_length(), fr.area);
            }
            return;
        }
        let nb = self.conn.len() / 4;
        for (b, r) in self.results_x4.iter().enumerate() {
            for l in 0..4 {
                let e = 4 * b + l;
                add(e, &self.conn[e], r.length.0[l], r.area.0[l]);
            }
        }
        for (j, r) in self.results.iter().enumerate() {
            let e = 4 * nb + j;
            add(e, &self.conn[e], r.length, r.area);
        }
    }

    fn scale_mass(
        &mut self,
        state: &NodalState,
        target_dt: f64,
        mass: &mut [f64],
        inertia: &mut [f64],
    ) -> f64 {
        let rho = self.material.density();
        let mut added = 0.0;
        for (e, q) in self.conn.iter().enumerate() {
            let x = q.map(|n| v3(&state.x[n as usize]));
            let fr = Frame::new(&x);
            if fr.area.is_nan() || fr.area <= 0.0 {
                continue;
            }
            let dt1 = fr.char_length() / self.wave_speed; // at physical density
            let need = (target_dt / dt1).powi(2);
            if need > self.dt_scale(e) {
                let t = self.thickness[e];
                let scale = need / self.selective_scale[e];
                let dm = 0.25 * rho * fr.area * t * (scale - self.density_scale[e]);
                let di = dm * (t * t / 12.0 + fr.area / 8.0);
                for &n in q {
                    mass[n as usize] += dm;
                    inertia[n as usize] += di;
                }
                added += 4.0 * dm;
                self.density_scale[e] = scale;
            }
        }
        self.cached_dt = None;
        added
    }

    /// Selective mass scaling: per element `1 + β_e = (target / Δt_e)²`
    /// wherever that is above its factor so far (`Δt_e` the element's step
    /// at its density), so that its deformation modes carry `1 + β_e` times
    /// its lumped share: `m_e = s ρ A₀ t₀ / 4` per translation and
    /// `m_e (t₀²/12 + A₀/8)` per rotation of each node (`s` the conventional
    /// density scale, 1 unless both ran). Every element with `β_e > 0` goes
    /// to `blocks`.
    fn selective_mass(
        &mut self,
        state: &NodalState,
        target_dt: f64,
        blocks: &mut fem_core::MassBlocks,
    ) -> bool {
        let rho = self.material.density();
        let t0 = self.section.thickness;
        for (e, q) in self.conn.iter().enumerate() {
            let fr = Frame::new(&q.map(|n| v3(&state.x[n as usize])));
            if fr.area > 0.0 {
                let dt1 = fr.char_length() / self.wave_speed; // at physical density
                let need = (target_dt / dt1).powi(2);
                if need > self.dt_scale(e) {
                    self.selective_scale[e] = need / self.density_scale[e];
                }
            }
            if self.selective_scale[e] > 1.0 {
                let a0 = Frame::new(&q.map(|n| v3(&state.x0[n as usize]))).area;
                let m = 0.25 * rho * a0 * t0 * self.density_scale[e];
                let j = m * (t0 * t0 / 12.0 + a0 / 8.0);
                blocks.push(*q, m, j, self.selective_scale[e] - 1.0);
            }
        }
        self.cached_dt = None;
        true
    }

    fn add_forces(
        &mut self,
        ctx: &StepContext,
        state: &NodalState,
        forces: &mut Forces,
        fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        let (xs, vs, ws) = (&state.x, &state.v, &state.w);
        let nodes = xs.len().min(vs.len()).min(ws.len());
        if !self.conn.is_empty() && self.max_node >= nodes {
            return Err(FemError::Element {
                effect: self.name.clone(),
                element: 0,
                message: format!(
                    "the nodal state has {nodes} nodes but the shells use node {}",
                    self.max_node
                ),
            });
        }
        self.compute_elements(ctx.dt, state);
        if let Some(message) = self.material.take_failure() {
            return Err(FemError::Effect {
                effect: self.name.clone(),
                message,
            });
        }
        self.scatter(ctx, forces, fields)
    }

    fn energies(&self) -> EnergyTally {
        self.energy
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BelytschkoTsay, FullyIntegrated, Hardening, J2PlaneStress};
    use fem_core::Vec3;
    use nalgebra::{DMatrix, SymmetricEigen};

    /// Highest natural frequency ω_max (rad/s) of one free element (its
    /// 24×24 stiffness probed column by column with unit velocities over
    /// one step from rest, lumped mass of `add_lumped_mass`) and the
    /// element's stable step (s).
    fn omega_max_and_dt<E: ShellFormulation>(form: E, nodes: &[Vec3], t: f64) -> (f64, f64) {
        let mat = J2PlaneStress::new(
            206_000.0,
            0.3,
            7.85e-9,
            Hardening::swift(1e30, 1.0, 0.0).unwrap(),
        )
        .unwrap();
        let set0 = ShellSet::new(
            "one",
            nodes,
            &[[0, 1, 2, 3]],
            Section::new(t).unwrap(),
            form,
            mat,
        )
        .unwrap();
        let state0 = NodalState::at_rest(nodes);
        let (mut mass, mut inertia) = (vec![0.0; 4], vec![0.0; 4]);
        set0.add_lumped_mass(&state0, &mut mass, &mut inertia);
        let dt = 1e-9;
        let ctx = StepContext {
            time: dt,
            dt,
            step: 1,
            press: None,
        };
        let mut k = DMatrix::<f64>::zeros(24, 24);
        for j in 0..24 {
            let (node, dof) = (j / 6, j % 6);
            let mut st = NodalState::at_rest(nodes);
            if dof < 3 {
                st.v[node][dof] = 1.0;
            } else {
                st.w[node][dof - 3] = 1.0;
            }
            let mut set = set0.clone();
            let mut f = Forces::zeros(4);
            set.add_forces(&ctx, &st, &mut f, &mut fem_core::FieldAccess::none())
                .unwrap();
            for n in 0..4 {
                for c in 0..3 {
                    k[(6 * n + c, j)] = -f.f[n][c] / dt;
                    k[(6 * n + 3 + c, j)] = -f.m[n][c] / dt;
                }
            }
        }
        let scale = k.amax();
        let asym = (&k - k.transpose()).amax() / scale;
        assert!(asym < 1e-6, "{}: stiffness asymmetry {asym:e}", E::NAME);
        let mut a = 0.5 * (&k + k.transpose());
        for i in 0..24 {
            for j in 0..24 {
                let mi = if i % 6 < 3 {
                    mass[i / 6]
                } else {
                    inertia[i / 6]
                };
                let mj = if j % 6 < 3 {
                    mass[j / 6]
                } else {
                    inertia[j / 6]
                };
                a[(i, j)] /= (mi * mj).sqrt();
            }
        }
        let lmax = SymmetricEigen::new(a).eigenvalues.max();
        (lmax.sqrt(), set0.stable_dt(&state0).unwrap().dt)
    }

    fn steel() -> J2PlaneStress {
        J2PlaneStress::new(
            206_000.0,
            0.3,
            7.85e-9,
            Hardening::swift(1e30, 1.0, 0.0).unwrap(),
        )
        .unwrap()
    }

    /// One step of `dt` from rest at `x0` with nodal velocities `v`, `w`:
    /// the forces and the set after it.
    fn one_step<E: ShellFormulation>(
        form: E,
        x0: &[Vec3],
        v: &[Vec3],
        w: &[Vec3],
        dt: f64,
    ) -> (Forces, ShellSet<E, J2PlaneStress>) {
        let mut set = ShellSet::new(
            "one",
            x0,
            &[[0, 1, 2, 3]],
            Section::new(0.8).unwrap(),
            form,
            steel(),
        )
        .unwrap();
        let mut st = NodalState::at_rest(x0);
        st.v = v.to_vec();
        st.w = w.to_vec();
        let mut f = Forces::zeros(x0.len());
        let ctx = StepContext {
            time: dt,
            dt,
            step: 1,
            press: None,
        };
        set.add_forces(&ctx, &st, &mut f, &mut fem_core::FieldAccess::none())
            .unwrap();
        (f, set)
    }

    /// The relative drilling penalty (Hughes & Brezzi 1989) must leave
    /// every rigid motion free: a distorted, tilted element spun rigidly
    /// about its normal, about an in-plane axis and about a skew axis (with
    /// a translation) over one step gets no force, moment or drilling
    /// moment (tolerance 1e-9 of the drilling force of a unit relative
    /// drill). A nodal drill against a still element gives the moment
    /// `k ω Δt`, `k = γ G t A / 4`, at that node (1e-12 relative) and the
    /// in-plane forces that balance it.
    #[test]
    fn drilling_penalty_ignores_rigid_motion_and_resists_relative_drill() {
        // Distorted quad in the plane z = 0.3 x + 0.2 y (tilted).
        let xy = [[0.0, 0.0], [1.2, 0.1], [1.0, 0.9], [0.2, 1.1]];
        let x0: Vec<Vec3> = xy
            .iter()
            .map(|p| Vec3::new(p[0], p[1], 0.3 * p[0] + 0.2 * p[1]))
            .collect();
        let normal = Vec3::new(-0.3, -0.2, 1.0).normalize();
        let (dt, g) = (1e-7, crate::formulation::MAX_DRILLING);
        let form = BelytschkoTsay::default().with_drilling(g).unwrap();
        let fi = FullyIntegrated::default().with_drilling(g).unwrap();
        // Reference: drill node 2 at 1 rad/s about the normal, element still.
        let mut w = vec![Vec3::zeros(); 4];
        w[2] = normal;
        let still = vec![Vec3::zeros(); 4];
        let (f_ref, set) = one_step(form, &x0, &still, &w, dt);
        let fr = Frame::new(&x0.iter().map(v3).collect::<Vec<_>>().try_into().unwrap());
        let k = 0.25 * g * steel().shear_modulus() * 0.8 * fr.area;
        let m = set.drilling_moments(0);
        assert!((m[2] / (k * dt) - 1.0).abs() < 1e-12, "{m:?} vs {}", k * dt);
        assert!(m[0] == 0.0 && m[1] == 0.0 && m[3] == 0.0, "{m:?}");
        assert!((f_ref.m[2].dot(&normal) / (-k * dt) - 1.0).abs() < 1e-12);
        let fsum: Vec3 = f_ref.f.iter().sum();
        let scale = f_ref.f.iter().map(|v| v.norm()).fold(0.0, f64::max);
        assert!(scale > 0.0 && fsum.norm() < 1e-12 * scale);
        // Rigid rotations (rates ω about axes through the node average of the
        // step's midpoint configuration) plus a translation.
        let c: Vec3 = x0.iter().sum::<Vec3>() / 4.0;
        for axis in [
            normal,
            (x0[1] - x0[0]).normalize(),
            Vec3::new(0.3, -0.5, 0.8),
        ] {
            let om = 2.0 * axis;
            let v: Vec<Vec3> = x0
                .iter()
                .map(|p| om.cross(&(p - c)) + Vec3::new(0.1, -0.2, 0.3))
                .collect();
            let w = vec![om; 4];
            // The rates are read in the step's midpoint configuration: the
            // motion is rigid about x0 there, so the step ends at x0 + ½Δt v.
            let x1: Vec<Vec3> = x0.iter().zip(&v).map(|(p, u)| p + 0.5 * dt * u).collect();
            for (name, (f, m)) in [
                ("BT", {
                    let (f, s) = one_step(form, &x1, &v, &w, dt);
                    (f, s.drilling_moments(0))
                }),
                ("FI", {
                    let (f, s) = one_step(fi, &x1, &v, &w, dt);
                    (f, s.drilling_moments(0))
                }),
            ] {
                let worst =
                    f.f.iter()
                        .chain(f.m.iter())
                        .map(|v| v.norm())
                        .fold(0.0, f64::max);
                let md = m.iter().map(|x| x.abs()).fold(0.0, f64::max);
                assert!(
                    worst < 1e-9 * scale && md < 1e-9 * k * dt,
                    "{name}, axis {axis:?}: force/moment {worst:e}, drilling {md:e}"
                );
            }
        }
    }

    /// Free vibration of a free 10 × 10 × 1 mm steel plate of 4 × 4
    /// elements released with nodal drilling rates and in-plane velocities
    /// that do not match (ω_z = 200 sin(x) rad/s, v = 100 (y, 0) mm/s):
    /// the worst energy balance error over the steps and the largest share
    /// of the set's internal energy held by the drilling penalty.
    fn drilling_vibration<E: ShellFormulation>(form: E) -> (f64, f64) {
        use fem_core::{Control, Solver, SolverSettings, rectangle};
        let mesh = rectangle(10.0, 10.0, 4, 4).unwrap();
        let set = ShellSet::from_mesh(
            "plate",
            &mesh,
            "all",
            Section::new(1.0).unwrap(),
            form,
            steel(),
        )
        .unwrap();
        let mut s = Solver::new(&mesh, SolverSettings::default()).unwrap();
        let id = s.add_effect(set);
        for (i, p) in mesh.nodes.iter().enumerate() {
            s.state_mut().w[i].z = 200.0 * p.x.sin();
            s.state_mut().v[i].x = 100.0 * p.y;
        }
        let (mut worst, mut share): (f64, f64) = (0.0, 0.0);
        s.run_until(1e-4, &mut |sv, r| {
            worst = worst.max(r.energy.balance_error);
            let set = sv.effect::<ShellSet<E, J2PlaneStress>>(id).unwrap();
            let internal = set.energies().internal;
            if internal > 0.0 {
                share = share.max(set.drilling_energy() / internal);
            }
            Control::Continue
        })
        .unwrap();
        (worst, share)
    }

    /// Energy balance with the drilling mode excited (requirement
    /// < 0.5 %, here held to 1e-3) at the largest drilling coefficient: the
    /// penalty's work is booked as internal energy, so the ledger must
    /// balance at every step while the penalty holds a large share of the
    /// strain energy (> 5 %, else the test would not test it).
    #[test]
    fn energy_balances_with_drilling_mode_excited() {
        let g = crate::formulation::MAX_DRILLING;
        let bt = drilling_vibration(BelytschkoTsay::default().with_drilling(g).unwrap());
        let fi = drilling_vibration(FullyIntegrated::default().with_drilling(g).unwrap());
        for (name, (worst, share)) in [("BT", bt), ("FI", fi)] {
            println!("{name}: energy balance error {worst:.2e}, drilling share ≤ {share:.3}");
            assert!(worst < 1e-3, "{name}: {worst}");
            assert!(share > 0.05, "{name}: drilling mode not excited ({share})");
        }
    }

    /// A drilling coefficient outside [0, 0.1] (or NaN) is refused with an
    /// error naming the field, both by `with_drilling` and, for a struct
    /// literal, when the set is built.
    #[test]
    fn bad_drilling_coefficient_is_refused_naming_the_field() {
        for g in [-1e-3, 0.2, f64::NAN] {
            let e = BelytschkoTsay::default().with_drilling(g).unwrap_err();
            assert!(e.to_string().contains("`drilling`"), "{e}");
            assert!(FullyIntegrated::default().with_drilling(g).is_err());
            let form = BelytschkoTsay {
                drilling: g,
                ..Default::default()
            };
            let nodes = quad([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
            let r = ShellSet::new(
                "one",
                &nodes,
                &[[0, 1, 2, 3]],
                Section::new(1.0).unwrap(),
                form,
                steel(),
            );
            assert!(r.unwrap_err().to_string().contains("`drilling`"));
        }
    }

    fn quad(p: [[f64; 2]; 4]) -> Vec<Vec3> {
        p.iter().map(|q| Vec3::new(q[0], q[1], 0.0)).collect()
    }

    /// Central-difference stability (ω_max Δt ≤ 2, Belytschko, Liu & Moran,
    /// *Nonlinear Finite Elements*, §6.3; the free element's ω_max bounds the
    /// mesh's): the drilling penalty must not raise one free element's
    /// highest frequency, so the step the set reports stays valid. For each
    /// shape (square, 4:1 rectangle, distorted quad) and thickness (thin and
    /// thick), ω_max Δt at the default and at the largest drilling
    /// coefficient must stay within 1 % of its value without drilling. (The
    /// undrilled value itself, ≈ 2.28 for the square, is the membrane
    /// element's: the solver's safety factor 0.9 and the sharing of nodal
    /// masses in a mesh bring it under 2; not this test's subject.)
    #[test]
    fn drilling_penalty_does_not_limit_the_stable_step() {
        let shapes = [
            quad([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
            quad([[0.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0]]),
            quad([[0.0, 0.0], [1.2, 0.1], [1.0, 0.9], [0.2, 1.1]]),
        ];
        for nodes in &shapes {
            for t in [0.05, 0.5] {
                for g in [
                    crate::formulation::DEFAULT_DRILLING,
                    crate::formulation::MAX_DRILLING,
                ] {
                    let bt = |g| BelytschkoTsay::default().with_drilling(g).unwrap();
                    let fi = |g| FullyIntegrated::default().with_drilling(g).unwrap();
                    let (w0, dt) = omega_max_and_dt(bt(0.0), nodes, t);
                    let (w1, _) = omega_max_and_dt(bt(g), nodes, t);
                    let (v0, dtf) = omega_max_and_dt(fi(0.0), nodes, t);
                    let (v1, _) = omega_max_and_dt(fi(g), nodes, t);
                    println!(
                        "t = {t}, γ = {g}: BT ω_max Δt {:.4} → {:.4}, FI {:.4} → {:.4}",
                        w0 * dt,
                        w1 * dt,
                        v0 * dtf,
                        v1 * dtf
                    );
                    assert!(w1 / w0 < 1.01 && v1 / v0 < 1.01);
                }
            }
        }
    }

    /// A nodal state with fewer nodes than the connectivity uses is refused
    /// with a one-line error (the block gather reads nodes unchecked).
    #[test]
    fn nodal_state_too_small_for_the_connectivity_is_refused() {
        let mesh = fem_core::rectangle(2.0, 2.0, 2, 2).unwrap();
        let mat = J2PlaneStress::new(
            206_000.0,
            0.3,
            7.85e-9,
            Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
        )
        .unwrap();
        let mut set = ShellSet::from_mesh(
            "blank",
            &mesh,
            "all",
            Section::new(0.8).unwrap(),
            BelytschkoTsay::default(),
            mat,
        )
        .unwrap();
        let state = NodalState::at_rest(&mesh.nodes[..5]);
        let mut forces = Forces::zeros(5);
        let ctx = StepContext {
            time: 0.0,
            dt: 1e-6,
            step: 1,
            press: None,
        };
        let e = set
            .add_forces(
                &ctx,
                &state,
                &mut forces,
                &mut fem_core::FieldAccess::none(),
            )
            .unwrap_err();
        assert!(e.to_string().contains("nodal state has 5 nodes"), "{e}");
    }
}
