//! Selective mass scaling: inertia added to the relative motion of each
//! element's nodes only, so that the stable step grows while rigid-body
//! motion keeps its true inertia.
//!
//! # Theory
//!
//! Conventional mass scaling raises the lumped masses `M`; a rigid-body
//! motion then carries the added mass too, and a forming run that adds a
//! lot of it (small elements, nodes that contact springs stiffen) answers
//! with the wrong inertia. Selective mass scaling (Olovsson, Simonsson and
//! Unosson, *Int. J. Numer. Meth. Engng* 63 (2005) 1436–1445; the scheme
//! LS-DYNA calls selective and OpenRadioss advanced mass scaling) adds
//! instead, per element `e`,
//!
//! ```text
//! ΔM_e = β_e M_e P_e,    P_e = I − R_e (R_eᵀ M_e R_e)⁻¹ R_eᵀ M_e
//! ```
//!
//! over the element's 24 DOFs (four nodes, three translations and three
//! rotations each), with `M_e` its lumped share (`m_e` per translation,
//! `j_e` per rotation) and `R_e` its six rigid-body modes in the current
//! configuration: a translation `t` (`u_a = t`, `θ_a = 0`) and a rotation
//! `θ` about the centroid (`u_a = θ × r_a`, `θ_a = θ`, `r_a` the node from
//! the centroid). `P_e` is the `M_e`-orthogonal projection on the element's
//! deformation modes, so that `M_e P_e` is symmetric and
//!
//! ```text
//! (P_e x)_a = (u_a − ū − ω × r_a,  θ_a − ω),
//! ω = (m_e J + 4 j_e I)⁻¹ (m_e Σ r_b × u_b + j_e Σ θ_b),   J = Σ (|r_b|² I − r_b r_bᵀ).
//! ```
//!
//! The rigid modes carry no added inertia; the deformation modes, which
//! hold all of the element's stiffness (its kernel holds the rigid modes),
//! carry `(1 + β_e) M_e`. The element's frequencies therefore all drop by
//! `√(1 + β_e)`, and `β_e = (Δt_target / Δt_e)² − 1` brings its step to the
//! target.
//!
//! # The step
//!
//! Each step solves `(M + ΔM) a = f` for the nodes' linear and angular
//! accelerations by conjugate gradients preconditioned with the diagonal of
//! `M + ΔM`, warm started from the last step's answer; `ΔM` is applied
//! element by element from the current geometry (no matrix is formed).
//! Constrained and massless DOFs take the acceleration zero in the solve
//! (exact for fixed DOFs and constant prescribed velocities; the reaction
//! is still that of the full system). The explicit update then runs
//! unchanged on the lumped masses with the forces `f − ΔM a`. As `ΔM a` is
//! built element by element from `M_e P_e`, its resultant force and its
//! resultant moment about any point (spin moments included) vanish to
//! round-off, whatever the solve's residual: the linear and the angular
//! momentum change exactly as without scaling. The solver books the work
//! of `ΔM a` with the ledger's rule as the energy of the added inertia
//! ([`EnergyLedger::kinetic_added`](crate::EnergyLedger)).

use crate::{Mat3, Vec3};

/// The element blocks of added inertia that effects hand the solver
/// ([`Effect::selective_mass`](crate::Effect::selective_mass)).
#[derive(Debug, Clone, Default)]
pub struct MassBlocks {
    quads: Vec<[u32; 4]>,
    /// `(m_e, j_e, β_e)`.
    shares: Vec<[f64; 3]>,
}

impl MassBlocks {
    /// Add an element of nodes `nodes` with lumped share `mass` (tonne) per
    /// translation and `inertia` (tonne·mm²) per rotation of each node,
    /// whose deformation modes get `beta` times that share on top; ignored
    /// unless `beta` and `mass` are finite and `> 0` and `inertia >= 0`.
    pub fn push(&mut self, nodes: [u32; 4], mass: f64, inertia: f64, beta: f64) {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if ok(beta) && ok(mass) && inertia.is_finite() && inertia >= 0.0 {
            self.quads.push(nodes);
            self.shares.push([mass, inertia, beta]);
        }
    }

    /// Number of blocks.
    pub fn len(&self) -> usize {
        self.quads.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.quads.is_empty()
    }

    /// `Σ_e 4 β_e m_e`: the translational mass the deformation modes carry
    /// on top of the lumped one (tonne).
    pub fn added_mass(&self) -> f64 {
        4.0 * self.shares.iter().map(|s| s[0] * s[2]).sum::<f64>()
    }

    fn clear(&mut self) {
        self.quads.clear();
        self.shares.clear();
    }
}

/// Counts of the mass solves over a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SelectiveStats {
    /// Solves of `(M + ΔM) a = f` (one a step).
    pub solves: u64,
    /// Conjugate-gradient iterations over all solves.
    pub iterations: u64,
    /// The most iterations one solve took.
    pub max_iterations: u32,
    /// Solves that stopped at the iteration cap above the tolerance.
    pub unconverged: u64,
    /// `Σ_e 4 β_e m_e` now (tonne).
    pub added_mass: f64,
    /// Seconds spent in the solves.
    pub seconds: f64,
}

/// A node's six DOFs: translation (mm, N, …) and rotation (rad, N·mm, …).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Six {
    pub(crate) t: Vec3,
    pub(crate) r: Vec3,
}

impl Six {
    const ZERO: Six = Six {
        t: Vec3::new(0.0, 0.0, 0.0),
        r: Vec3::new(0.0, 0.0, 0.0),
    };

    #[inline(always)]
    fn dot(&self, o: &Six) -> f64 {
        self.t.dot(&o.t) + self.r.dot(&o.r)
    }

    #[inline(always)]
    fn axpy(&mut self, alpha: f64, x: &Six) {
        self.t += x.t * alpha;
        self.r += x.r * alpha;
    }

    /// Zero the held components (bit `k`: DOF `k`, translations 0–2).
    #[inline(always)]
    fn mask(&mut self, held: u8) {
        if held != 0 {
            for k in 0..3 {
                if held & (1 << k) != 0 {
                    self.t[k] = 0.0;
                }
                if held & (1 << (k + 3)) != 0 {
                    self.r[k] = 0.0;
                }
            }
        }
    }
}

/// One element's geometry in the current configuration.
#[derive(Debug, Clone, Copy, Default)]
struct Geometry {
    /// Nodes from the centroid (mm).
    r: [Vec3; 4],
    /// `(m_e J + 4 j_e I)⁻¹`; zero for a degenerate element.
    a_inv: Mat3,
}

/// The solver's selective mass: the blocks, their geometry at `t_n` and the
/// conjugate-gradient work vectors (allocated once).
#[derive(Debug, Default)]
pub(crate) struct SelectiveMass {
    blocks: MassBlocks,
    geometry: Vec<Geometry>,
    /// Per node: in some block.
    in_block: Vec<bool>,
    /// Per node, bit `k` set: DOF `k` takes zero acceleration.
    held: Vec<u8>,
    /// The lumped masses as six (translation: `m`, rotation: `j`).
    lumped: Vec<Six>,
    /// `1 / diag(M + ΔM)`, the preconditioner.
    inv_diag: Vec<Six>,
    /// The answer `a` (also the next warm start).
    a: Vec<Six>,
    /// `ΔM a`, subtracted from the forces and moments.
    pub(crate) g: Vec<Six>,
    f: Vec<Six>,
    r: Vec<Six>,
    p: Vec<Six>,
    q: Vec<Six>,
    tolerance: f64,
    max_iterations: u32,
    pub(crate) stats: SelectiveStats,
}

impl SelectiveMass {
    pub(crate) fn new(nodes: usize, tolerance: f64, max_iterations: u32) -> Self {
        let z = vec![Six::ZERO; nodes];
        Self {
            in_block: vec![false; nodes],
            held: vec![0; nodes],
            lumped: z.clone(),
            inv_diag: z.clone(),
            a: z.clone(),
            g: z.clone(),
            f: z.clone(),
            r: z.clone(),
            p: z.clone(),
            q: z,
            tolerance,
            max_iterations,
            ..Default::default()
        }
    }

    /// The blocks, emptied for the effects to refill.
    pub(crate) fn blocks_mut(&mut self) -> &mut MassBlocks {
        self.blocks.clear();
        &mut self.blocks
    }

    /// After the blocks were refilled: which nodes they touch.
    pub(crate) fn blocks_changed(&mut self) {
        self.in_block.iter_mut().for_each(|b| *b = false);
        for q in &self.blocks.quads {
            for &n in q {
                self.in_block[n as usize] = true;
            }
        }
        self.geometry
            .resize(self.blocks.quads.len(), Geometry::default());
        self.stats.added_mass = self.blocks.added_mass();
    }

    /// Hold DOF `dof` (0–2 translations, 3–5 rotations) of `node` at zero
    /// acceleration.
    pub(crate) fn hold(&mut self, node: usize, dof: u8) {
        self.held[node] |= 1 << dof;
    }

    /// Whether any element carries added inertia.
    pub(crate) fn is_active(&self) -> bool {
        !self.blocks.is_empty()
    }

    /// Solve `(M + ΔM) a = f` at the positions `x` (forces `f`, moments
    /// `mt`) and leave `ΔM a` in [`SelectiveMass::g`] (zero outside the
    /// blocks).
    pub(crate) fn solve(
        &mut self,
        x: &[Vec3],
        (mass, inertia): (&[f64], &[f64]),
        (f, mt): (&[Vec3], &[Vec3]),
    ) {
        let started = std::time::Instant::now();
        for i in 0..x.len() {
            self.f[i] = Six { t: f[i], r: mt[i] };
            self.lumped[i] = Six {
                t: Vec3::repeat(mass[i]),
                r: Vec3::repeat(inertia[i]),
            };
        }
        self.update_geometry(x);
        for i in 0..x.len() {
            let mut ai = if self.in_block[i] {
                self.a[i]
            } else {
                mul(&self.f[i], &self.inv_diag[i])
            };
            ai.mask(self.held[i]);
            self.a[i] = ai;
        }
        let its = self.conjugate_gradients();
        self.g.iter_mut().for_each(|g| *g = Six::ZERO);
        add_delta(&self.blocks, &self.geometry, &self.a, &mut self.g);
        let s = &mut self.stats;
        s.solves += 1;
        s.iterations += u64::from(its);
        s.max_iterations = s.max_iterations.max(its);
        s.seconds += started.elapsed().as_secs_f64();
    }

    /// Each block's centroid-relative nodes and `(m J + 4 j I)⁻¹`, and the
    /// inverse diagonal of `M + ΔM` (massless DOFs are held, with a unit
    /// diagonal).
    fn update_geometry(&mut self, x: &[Vec3]) {
        for (i, d) in self.inv_diag.iter_mut().enumerate() {
            let l = self.lumped[i];
            *d = l;
            for k in 0..3 {
                if l.t[k] <= 0.0 {
                    self.held[i] |= 1 << k;
                    d.t[k] = 1.0;
                }
                if l.r[k] <= 0.0 {
                    self.held[i] |= 1 << (k + 3);
                    d.r[k] = 1.0;
                }
            }
        }
        let bl = &self.blocks;
        for ((q, s), geo) in bl.quads.iter().zip(&bl.shares).zip(&mut self.geometry) {
            let [m, j, beta] = *s;
            let xs = q.map(|n| x[n as usize]);
            let centroid = (xs[0] + xs[1] + xs[2] + xs[3]) * 0.25;
            let r = xs.map(|p| p - centroid);
            let mut a = Mat3::identity() * (4.0 * j);
            for ra in &r {
                a += (Mat3::identity() * ra.norm_squared() - ra * ra.transpose()) * m;
            }
            let a_inv = a.try_inverse().unwrap_or_else(Mat3::zeros);
            *geo = Geometry { r, a_inv };
            for (ra, &n) in r.iter().zip(q) {
                // diag(P): 1 − ¼ − m (r × e_k)ᵀ A⁻¹ (r × e_k); 1 − j (A⁻¹)_kk.
                let mut p = Six::ZERO;
                for k in 0..3 {
                    let rk = ra.cross(&Vec3::ith(k, 1.0));
                    p.t[k] = m * (0.75 - m * rk.dot(&(a_inv * rk)));
                    p.r[k] = j * (1.0 - j * a_inv[(k, k)]);
                }
                self.inv_diag[n as usize].axpy(beta, &p);
            }
        }
        for d in &mut self.inv_diag {
            *d = Six {
                t: d.t.map(|v| 1.0 / v),
                r: d.r.map(|v| 1.0 / v),
            };
        }
    }

    /// Jacobi-preconditioned conjugate gradients from the warm start in
    /// `a`, over the DOFs not held; returns the iterations taken. Each
    /// iteration is one pass over the elements (`q = ΔM p` and `pᵀ ΔM p`)
    /// and two over the nodes.
    fn conjugate_gradients(&mut self) -> u32 {
        let Self {
            blocks,
            geometry,
            held,
            lumped,
            inv_diag,
            a,
            f,
            r,
            p,
            q,
            ..
        } = self;
        let n = f.len();
        // r = f − (M + ΔM) a, masked; p = z = r / diag; q = M p.
        r.iter_mut().for_each(|v| *v = Six::ZERO);
        add_delta(blocks, geometry, a, r);
        let (mut f_norm, mut rz, mut rr, mut pmp) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..n {
            let mut fi = f[i];
            fi.mask(held[i]);
            f_norm += fi.dot(&fi);
            let mut ri = fi;
            ri.axpy(-1.0, &mul(&lumped[i], &a[i]));
            ri.axpy(-1.0, &r[i]);
            ri.mask(held[i]);
            r[i] = ri;
            let z = mul(&ri, &inv_diag[i]);
            rz += ri.dot(&z);
            rr += ri.dot(&ri);
            p[i] = z;
            q[i] = mul(&lumped[i], &z);
            pmp += z.dot(&q[i]);
        }
        let goal = self.tolerance * self.tolerance * f_norm;
        let mut its = 0;
        while rr > goal && its < self.max_iterations {
            its += 1;
            let pq = pmp + add_delta(blocks, geometry, p, q);
            // A direction without positive curvature (round-off at the
            // answer, or NaN) ends the solve.
            if pq.is_nan() || pq <= 0.0 {
                break;
            }
            let alpha = rz / pq;
            let (mut rz_new, mut rr_new) = (0.0, 0.0);
            for i in 0..n {
                a[i].axpy(alpha, &p[i]);
                let mut ri = r[i];
                ri.axpy(-alpha, &q[i]);
                // p is zero on the held DOFs, q is not.
                ri.mask(held[i]);
                r[i] = ri;
                rz_new += ri.dot(&mul(&ri, &inv_diag[i]));
                rr_new += ri.dot(&ri);
            }
            rr = rr_new;
            if rr <= goal {
                break;
            }
            let beta = rz_new / rz;
            rz = rz_new;
            pmp = 0.0;
            for i in 0..n {
                let mut pi = mul(&r[i], &inv_diag[i]);
                pi.axpy(beta, &p[i]);
                p[i] = pi;
                q[i] = mul(&lumped[i], &pi);
                pmp += pi.dot(&q[i]);
            }
        }
        if rr > goal {
            self.stats.unconverged += 1;
        }
        its
    }
}

/// Component-wise product.
#[inline(always)]
fn mul(d: &Six, x: &Six) -> Six {
    Six {
        t: d.t.component_mul(&x.t),
        r: d.r.component_mul(&x.r),
    }
}

/// `out += ΔM u`, element by element: `β_e M_e P_e u_e` (module docs);
/// returns `uᵀ ΔM u = Σ_e β_e |P_e u_e|²_{M_e}` (`P_e` is `M_e`-orthogonal).
fn add_delta(blocks: &MassBlocks, geometry: &[Geometry], u: &[Six], out: &mut [Six]) -> f64 {
    let mut energy = 0.0;
    for ((q, s), geo) in blocks.quads.iter().zip(&blocks.shares).zip(geometry) {
        let [m, j, beta] = *s;
        let us = q.map(|n| u[n as usize]);
        let mean = (us[0].t + us[1].t + us[2].t + us[3].t) * 0.25;
        let mut b = (us[0].r + us[1].r + us[2].r + us[3].r) * j;
        for (ra, ua) in geo.r.iter().zip(&us) {
            b += ra.cross(&ua.t) * m;
        }
        let omega = geo.a_inv * b;
        let (bm, bj) = (beta * m, beta * j);
        let mut e = 0.0;
        for ((&n, ra), ua) in q.iter().zip(&geo.r).zip(&us) {
            let dt = ua.t - mean - omega.cross(ra);
            let dr = ua.r - omega;
            let o = &mut out[n as usize];
            o.t += dt * bm;
            o.r += dr * bj;
            e += m * dt.norm_squared() + j * dr.norm_squared();
        }
        energy += beta * e;
    }
    energy
}
