//! `ShellSet<E, M>`: a set of quads of one formulation and one material, owning their state, as a `fem_core::Effect`.
//!
//! State is laid out for the element loop: per element a thickness, a slice
//! of `IN_PLANE_POINTS × n` stresses and histories (in-plane point major,
//! bottom to top), `IN_PLANE_POINTS` transverse shear stresses and the
//! hourglass forces; every step each element writes its nodal forces and
//! energy increments into its own result slot (in parallel with rayon when
//! the set is large enough), and one serial pass scatters them onto the
//! nodes — so the result does not depend on the thread count.

use fem_core::{Effect, EnergyTally, FemError, Forces, Mesh, NodalState, StableDt, StepContext};
use rayon::prelude::*;

use crate::error::ShellError;
use crate::formulation::{ElementResult, ElementState, ShellFormulation};
use crate::geometry::{Frame, V3};
use crate::material::Material;
use crate::outputs::{LogStrain, ShellElementOutput, log_membrane_strain};
use crate::section::Section;

/// Default number of elements from which the element loop runs in parallel.
pub const DEFAULT_PARALLEL_MIN: usize = 512;

/// Shells of formulation `E` and material `M` over a set of quads.
#[derive(Debug, Clone)]
pub struct ShellSet<E: ShellFormulation, M: Material> {
    name: String,
    formulation: E,
    material: M,
    section: Section,
    conn: Vec<[u32; 4]>,
    thickness: Vec<f64>,
    stress: Vec<[f64; 3]>,
    history: Vec<M::History>,
    shear: Vec<[f64; 2]>,
    hourglass: Vec<f64>,
    density_scale: Vec<f64>,
    results: Vec<ElementResult>,
    energy: EnergyTally,
    cached_dt: Option<StableDt>,
    parallel_min: usize,
    wave_speed: f64,
}

fn v3(p: &fem_core::Vec3) -> V3 {
    [p.x, p.y, p.z]
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
            thickness: vec![section.thickness; ne],
            stress: vec![[0.0; 3]; ne * ip * np],
            history: vec![material.initial_history(); ne * ip * np],
            shear: vec![[0.0; 2]; ne * ip],
            hourglass: vec![0.0; ne * E::HOURGLASS_VARS.max(1)],
            density_scale: vec![1.0; ne],
            results: vec![ElementResult::default(); ne],
            energy: EnergyTally::default(),
            cached_dt: None,
            parallel_min: DEFAULT_PARALLEL_MIN,
            wave_speed,
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

    /// Run the element loop in parallel from `n` elements on (serial below);
    /// `usize::MAX` keeps it serial.
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
    /// Stress `[σ_xx, σ_yy, σ_xy]` (MPa, co-rotational frame) at in-plane point
    /// `p` and through-thickness point `k` (bottom = 0) of element `e`.
    pub fn stress(&self, e: usize, p: usize, k: usize) -> [f64; 3] {
        self.stress[self.point_index(e, p, k)]
    }
    /// Transverse shear stresses `[τ_xz, τ_yz]` (MPa) at in-plane point `p` of element `e`.
    pub fn transverse_shear(&self, e: usize, p: usize) -> [f64; 2] {
        self.shear[e * E::IN_PLANE_POINTS + p]
    }
    /// Material history at a point (see [`ShellSet::stress`] for the indices).
    pub fn history(&self, e: usize, p: usize, k: usize) -> &M::History {
        &self.history[self.point_index(e, p, k)]
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

    fn element_dt(&self, e: usize, length: f64) -> f64 {
        length * self.density_scale[e].sqrt() / self.wave_speed
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

impl<E: ShellFormulation, M: Material> Effect for ShellSet<E, M> {
    fn name(&self) -> &str {
        &self.name
    }

    /// Translational mass ρ A t0 / 4 per node; rotational inertia
    /// `(ρ A t0 / 4)(t0²/12 + A/8)` per node: the `A/8` term scales the
    /// rotary inertia so that rotations (bending, transverse shear) never
    /// control the time step, which stays the membrane one.
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
            if need > self.density_scale[e] {
                let t = self.thickness[e];
                let dm = 0.25 * rho * fr.area * t * (need - self.density_scale[e]);
                let di = dm * (t * t / 12.0 + fr.area / 8.0);
                for &n in q {
                    mass[n as usize] += dm;
                    inertia[n as usize] += di;
                }
                added += 4.0 * dm;
                self.density_scale[e] = need;
            }
        }
        self.cached_dt = None;
        added
    }

    fn add_forces(
        &mut self,
        ctx: &StepContext,
        state: &NodalState,
        forces: &mut Forces,
    ) -> Result<(), FemError> {
        let ip = E::IN_PLANE_POINTS;
        let nsp = ip * self.section.rule.n;
        let nhg = E::HOURGLASS_VARS.max(1);
        let dt = ctx.dt;
        let (xs, vs, ws) = (&state.x, &state.v, &state.w);
        let (form, mat, sec) = (&self.formulation, &self.material, &self.section);
        let kernel = |q: &[u32; 4],
                      t: &mut f64,
                      s: &mut [[f64; 3]],
                      h: &mut [M::History],
                      sh: &mut [[f64; 2]],
                      hg: &mut [f64],
                      r: &mut ElementResult| {
            let x = q.map(|n| v3(&xs[n as usize]));
            let v = q.map(|n| v3(&vs[n as usize]));
            let w = q.map(|n| v3(&ws[n as usize]));
            *r = form.compute(
                mat,
                sec,
                &x,
                &v,
                &w,
                dt,
                ElementState {
                    thickness: t,
                    stress: s,
                    history: h,
                    shear: sh,
                    hourglass: &mut hg[..E::HOURGLASS_VARS],
                },
            );
        };
        if self.conn.len() >= self.parallel_min {
            self.conn
                .par_iter()
                .zip(self.thickness.par_iter_mut())
                .zip(self.stress.par_chunks_mut(nsp))
                .zip(self.history.par_chunks_mut(nsp))
                .zip(self.shear.par_chunks_mut(ip))
                .zip(self.hourglass.par_chunks_mut(nhg))
                .zip(self.results.par_iter_mut())
                .with_min_len(128)
                .for_each(|((((((q, t), s), h), sh), hg), r)| kernel(q, t, s, h, sh, hg, r));
        } else {
            self.conn
                .iter()
                .zip(self.thickness.iter_mut())
                .zip(self.stress.chunks_mut(nsp))
                .zip(self.history.chunks_mut(nsp))
                .zip(self.shear.chunks_mut(ip))
                .zip(self.hourglass.chunks_mut(nhg))
                .zip(self.results.iter_mut())
                .for_each(|((((((q, t), s), h), sh), hg), r)| kernel(q, t, s, h, sh, hg, r));
        }
        // Serial scatter, energies and the stable time step.
        let mut best = StableDt {
            dt: f64::INFINITY,
            element: 0,
            what: "shell area / longest side / plate wave speed",
        };
        let (mut di, mut dh, mut dp) = (0.0, 0.0, 0.0);
        for (e, (q, r)) in self.conn.iter().zip(&self.results).enumerate() {
            if r.length.is_nan() || r.length <= 0.0 {
                self.cached_dt = Some(StableDt {
                    dt: 0.0,
                    element: e,
                    what: "shell degenerated (zero or negative area)",
                });
                return Err(FemError::Element {
                    effect: self.name.clone(),
                    element: e,
                    message: format!(
                        "shell inverted or degenerated at t = {} s (projected area or Jacobian {} mm²)",
                        ctx.time, r.length
                    ),
                });
            }
            for k in 0..4 {
                let n = q[k] as usize;
                forces.f[n].x += r.f[k][0];
                forces.f[n].y += r.f[k][1];
                forces.f[n].z += r.f[k][2];
                forces.m[n].x += r.m[k][0];
                forces.m[n].y += r.m[k][1];
                forces.m[n].z += r.m[k][2];
            }
            di += r.d_internal;
            dh += r.d_hourglass;
            dp += r.d_plastic;
            let dte = r.length * self.density_scale[e].sqrt() / self.wave_speed;
            if dte < best.dt {
                best.dt = dte;
                best.element = e;
            }
        }
        self.energy.internal += di;
        self.energy.hourglass += dh;
        self.energy.plastic += dp;
        self.cached_dt = if self.conn.is_empty() {
            None
        } else {
            Some(best)
        };
        Ok(())
    }

    fn energies(&self) -> EnergyTally {
        self.energy
    }
}
