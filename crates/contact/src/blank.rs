//! The blank as contact sees it: quad connectivity, nodal areas, normals, and the
//! nodal velocity and deformation gradients that some formulations read.
//!
//! Only what the active friction components declare ([`plugins_api::PointNeeds`],
//! friction-math §6) is computed: [`BlankGeometry::update`] takes the union of
//! the needs and skips the gradients nobody reads.

use plugins_api::{Mat3, PointNeeds, Vec3};
use rayon::prelude::*;

use crate::ContactError;

/// The blank's nodal data for one contact step (global frame).
#[derive(Clone, Copy, Debug)]
pub struct BlankView<'a> {
    /// Initial nodal positions (mm).
    pub x0: &'a [Vec3],
    /// Nodal positions at `t_{n+1}` (mm).
    pub x: &'a [Vec3],
    /// Nodal velocities at `t_{n+1/2}` (mm/s).
    pub v: &'a [Vec3],
    /// Lumped nodal masses (tonne), for normal damping.
    pub mass: &'a [f64],
    /// Current nodal shell thickness (mm).
    pub thickness: &'a [f64],
    /// Flow stress at the top fibre (side of `+n_blank`) and the bottom fibre, per
    /// node (MPa); needed only by laws that declare [`PointNeeds::FLOW_STRESS`].
    pub flow_stress: Option<(&'a [f64], &'a [f64])>,
}

/// Quad connectivity with node → quad adjacency, and per-step nodal geometry.
#[derive(Clone, Debug)]
pub struct BlankGeometry {
    quads: Vec<[u32; 4]>,
    /// CSR offsets of the quads around each node.
    offsets: Vec<u32>,
    /// Quads around each node.
    around: Vec<u32>,
    /// Current nodal (tributary) area, mm².
    pub area: Vec<f64>,
    /// Current nodal unit normal (area-weighted mean of the quads' normals).
    pub normal: Vec<Vec3>,
    /// Nodal velocity gradient at mid-step (1/s), when needed.
    pub vel_grad: Vec<Mat3>,
    /// Nodal deformation gradient at `t_n`, when needed.
    pub f_old: Vec<Mat3>,
    /// Nodal deformation gradient at `t_{n+1}`, when needed.
    pub f_new: Vec<Mat3>,
    /// How many times the velocity gradients were evaluated (for tests and reports).
    pub vel_grad_evaluations: u64,
    /// How many times the deformation gradients were evaluated.
    pub def_grad_evaluations: u64,
    /// How many times [`BlankGeometry::update`] computed the nodal areas and
    /// normals itself (rather than taking them from [`BlankGeometry::set_nodal`]).
    pub nodal_evaluations: u64,
    /// Whether the nodal areas and normals of the coming [`BlankGeometry::update`]
    /// were given ([`BlankGeometry::set_nodal`]) rather than to be computed.
    nodal_given: bool,
    // Per-quad scratch.
    quad_area: Vec<f64>,
    quad_normal: Vec<Vec3>,
    quad_l: Vec<Mat3>,
    /// Per quad: the deformation gradients at `n` and `n+1`.
    quad_f: Vec<[Mat3; 2]>,
    /// Per quad: the frame of the initial configuration.
    quad_f0: Vec<Option<CentreFrame>>,
}

/// Shape-function derivatives of the bilinear quad at its centre: `∂N/∂ξ`, `∂N/∂η`.
const DN_DXI: [f64; 4] = [-0.25, 0.25, 0.25, -0.25];
const DN_DETA: [f64; 4] = [-0.25, -0.25, 0.25, 0.25];

/// Surface-gradient basis at the quad centre: covariant tangents and the
/// contravariant (dual) vectors, the unit normal and the area (mm²).
#[derive(Clone, Copy, Debug)]
struct CentreFrame {
    dual1: Vec3,
    dual2: Vec3,
    normal: Vec3,
    area: f64,
}

fn centre_frame(x: [Vec3; 4]) -> Option<CentreFrame> {
    let mut g1 = Vec3::zeros();
    let mut g2 = Vec3::zeros();
    for a in 0..4 {
        g1 += x[a] * DN_DXI[a];
        g2 += x[a] * DN_DETA[a];
    }
    let c = g1.cross(&g2);
    let j = c.norm();
    if j <= 0.0 || !j.is_finite() {
        return None;
    }
    let normal = c / j;
    // Dual basis: g^1 = g2 × n / j, g^2 = n × g1 / j.
    let dual1 = g2.cross(&normal) / j;
    let dual2 = normal.cross(&g1) / j;
    // The quad's area: exact for a planar parallelogram, the centre-point rule otherwise.
    Some(CentreFrame {
        dual1,
        dual2,
        normal,
        area: 4.0 * j,
    })
}

/// `Σ_a w_a ⊗ ∇_s N_a` at the quad centre.
fn surface_gradient(w: [Vec3; 4], f: &CentreFrame) -> Mat3 {
    let mut g = Mat3::zeros();
    for a in 0..4 {
        let grad_n = f.dual1 * DN_DXI[a] + f.dual2 * DN_DETA[a];
        g += w[a] * grad_n.transpose();
    }
    g
}

/// Quads or nodes per parallel task in [`BlankGeometry::update_areas`].
const PARALLEL_CHUNK: usize = 512;

/// Blanks with more quads than this compute the velocity and deformation
/// gradients in parallel (each quad costs about ten times its area and
/// normal, so the loops pay for the hand-over sooner).
const PARALLEL_MIN_GRADIENT_QUADS: usize = 256;

/// Quads or nodes per parallel task of the gradients.
const GRADIENT_CHUNK: usize = 64;

/// `value(e, quad, &mut out[e])` for every quad `e`, in parallel chunks for
/// more than [`PARALLEL_MIN_GRADIENT_QUADS`] quads when rayon's pool has more
/// than one thread (each slot written alone: the same bits on any number of
/// threads).
fn per_quad<T: Send>(
    quads: &[[u32; 4]],
    out: &mut [T],
    value: impl Fn(usize, &[u32; 4], &mut T) + Sync,
) {
    if quads.len() > PARALLEL_MIN_GRADIENT_QUADS && rayon::current_num_threads() > 1 {
        quads
            .par_iter()
            .zip(out.par_iter_mut())
            .enumerate()
            .with_min_len(GRADIENT_CHUNK)
            .for_each(|(e, (q, o))| value(e, q, o));
    } else {
        quads
            .iter()
            .zip(out.iter_mut())
            .enumerate()
            .for_each(|(e, (q, o))| value(e, q, o));
    }
}

impl BlankGeometry {
    /// Blanks with more quads than this update their nodal areas and normals
    /// in parallel (when rayon's current pool has more than one thread).
    pub const PARALLEL_MIN_QUADS: usize = 2048;

    /// Build the adjacency of `quads` over `n_nodes` nodes.
    ///
    /// # Errors
    /// A quad referring to a node index `≥ n_nodes`.
    pub fn new(n_nodes: usize, quads: &[[u32; 4]]) -> Result<Self, ContactError> {
        let mut count = vec![0u32; n_nodes + 1];
        for (e, q) in quads.iter().enumerate() {
            for &a in q {
                if a as usize >= n_nodes {
                    return Err(ContactError::Mesh(format!(
                        "element {e} refers to node {a}, but the blank has {n_nodes} nodes"
                    )));
                }
                count[a as usize + 1] += 1;
            }
        }
        for i in 0..n_nodes {
            count[i + 1] += count[i];
        }
        let offsets = count;
        let mut fill = offsets.clone();
        let mut around = vec![0u32; offsets[n_nodes] as usize];
        for (e, q) in quads.iter().enumerate() {
            for &a in q {
                around[fill[a as usize] as usize] = e as u32;
                fill[a as usize] += 1;
            }
        }
        let nq = quads.len();
        Ok(Self {
            quads: quads.to_vec(),
            offsets,
            around,
            area: vec![0.0; n_nodes],
            normal: vec![Vec3::z(); n_nodes],
            vel_grad: Vec::new(),
            f_old: Vec::new(),
            f_new: Vec::new(),
            vel_grad_evaluations: 0,
            def_grad_evaluations: 0,
            nodal_evaluations: 0,
            nodal_given: false,
            quad_area: vec![0.0; nq],
            quad_normal: vec![Vec3::z(); nq],
            quad_l: Vec::new(),
            quad_f: Vec::new(),
            quad_f0: Vec::new(),
        })
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.area.len()
    }

    /// The quads.
    pub fn quads(&self) -> &[[u32; 4]] {
        &self.quads
    }

    /// The quads around node `i`.
    pub fn quads_around(&self, i: usize) -> &[u32] {
        &self.around[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Nodal areas and normals of the configuration `x` (no allocation). For
    /// more than [`BlankGeometry::PARALLEL_MIN_QUADS`] quads the loops run in
    /// parallel (rayon); every quad and node is computed alone, in a fixed
    /// order of its own terms, so the result does not depend on the threads.
    pub fn update_areas(&mut self, x: &[Vec3]) {
        self.update_quads(x);
        self.update_nodes();
    }

    /// Take the nodal areas (mm²) and normals of the coming
    /// [`BlankGeometry::update`] from whoever computed them already (the
    /// blank's shells, through `fem-core`'s shared fields), so that the update
    /// computes only what else the step needs. `normal` holds the components
    /// of a vector along the normal of any length (the shells give the
    /// area-weighted sums of the element normals); it is normalised here, and
    /// a zero vector keeps the node's previous normal. Lengths must be the
    /// node count.
    pub fn set_nodal(&mut self, area: &[f64], normal: &[Vec3]) {
        let n = self.area.len();
        if area.len() != n || normal.len() != n {
            return;
        }
        self.area.copy_from_slice(area);
        for (o, v) in self.normal.iter_mut().zip(normal) {
            let len = v.norm();
            if len > 0.0 {
                *o = v / len;
            }
        }
        self.nodal_given = true;
    }

    /// Per-quad areas and normals of the configuration `x` (parallel for
    /// large blanks, as [`BlankGeometry::update_areas`]).
    fn update_quads(&mut self, x: &[Vec3]) {
        let quad = |q: &[u32; 4], area: &mut f64, normal: &mut Vec3| {
            if let Some(f) = centre_frame(q.map(|a| x[a as usize])) {
                *area = f.area;
                *normal = f.normal;
            } else {
                *area = 0.0;
            }
        };
        if self.quads.len() > Self::PARALLEL_MIN_QUADS && rayon::current_num_threads() > 1 {
            self.quads
                .par_iter()
                .zip(self.quad_area.par_iter_mut())
                .zip(self.quad_normal.par_iter_mut())
                .with_min_len(PARALLEL_CHUNK)
                .for_each(|((q, a), n)| quad(q, a, n));
        } else {
            for ((q, a), n) in self
                .quads
                .iter()
                .zip(&mut self.quad_area)
                .zip(&mut self.quad_normal)
            {
                quad(q, a, n);
            }
        }
    }

    /// Nodal areas and normals from the per-quad ones.
    fn update_nodes(&mut self) {
        let (offsets, around) = (&self.offsets, &self.around);
        let node = |i: usize,
                    quad_area: &[f64],
                    quad_normal: &[Vec3],
                    area: &mut f64,
                    normal: &mut Vec3| {
            let mut a = 0.0;
            let mut n = Vec3::zeros();
            for &e in &around[offsets[i] as usize..offsets[i + 1] as usize] {
                let ea = quad_area[e as usize];
                a += 0.25 * ea;
                n += quad_normal[e as usize] * ea;
            }
            *area = a;
            let nn = n.norm();
            if nn > 0.0 {
                *normal = n / nn;
            }
        };
        if self.quads.len() > Self::PARALLEL_MIN_QUADS && rayon::current_num_threads() > 1 {
            let (qa, qn) = (&self.quad_area, &self.quad_normal);
            self.area
                .par_iter_mut()
                .zip(self.normal.par_iter_mut())
                .enumerate()
                .with_min_len(PARALLEL_CHUNK)
                .for_each(|(i, (a, n))| node(i, qa, qn, a, n));
        } else {
            for (i, (a, n)) in self.area.iter_mut().zip(&mut self.normal).enumerate() {
                node(i, &self.quad_area, &self.quad_normal, a, n);
            }
        }
    }

    /// Everything the step needs for `needs`: areas and normals (unless
    /// [`BlankGeometry::set_nodal`] gave them for this update); the
    /// mid-step velocity gradient only for [`PointNeeds::SPIN`] or
    /// [`PointNeeds::VELOCITY_GRADIENT`]; the deformation gradients at `n`
    /// and `n+1` only for [`PointNeeds::DEFORMATION_GRADIENT`].
    pub fn update(&mut self, blank: &BlankView<'_>, dt: f64, needs: PointNeeds) {
        let want_l =
            needs.contains(PointNeeds::SPIN) || needs.contains(PointNeeds::VELOCITY_GRADIENT);
        let want_f = needs.contains(PointNeeds::DEFORMATION_GRADIENT);
        if !std::mem::take(&mut self.nodal_given) {
            self.nodal_evaluations += 1;
            self.update_areas(blank.x);
        } else if want_l || want_f {
            // The gradients' nodal means weigh the quads by their areas.
            self.update_quads(blank.x);
        }
        let nq = self.quads.len();
        let nn = self.area.len();
        if want_l {
            self.vel_grad_evaluations += 1;
            if self.quad_l.len() != nq {
                self.quad_l = vec![Mat3::zeros(); nq];
                self.vel_grad = vec![Mat3::zeros(); nn];
            }
            per_quad(&self.quads, &mut self.quad_l, |_, q, l| {
                // Geometry at mid-step x_{n+1/2} = x_{n+1} - ½Δt v_{n+1/2}.
                let xm = q.map(|a| blank.x[a as usize] - blank.v[a as usize] * (0.5 * dt));
                let vs = q.map(|a| blank.v[a as usize]);
                *l = match centre_frame(xm) {
                    Some(f) => {
                        // L = G - (Gᵀn)⊗n: the in-plane gradient plus the rate of
                        // the material normal, ṅ = -Gᵀn (exact for rigid motion).
                        let g = surface_gradient(vs, &f);
                        g - (g.transpose() * f.normal) * f.normal.transpose()
                    }
                    None => Mat3::zeros(),
                };
            });
            let quad_l = &self.quad_l;
            Self::average(
                &self.offsets,
                &self.around,
                &self.quad_area,
                |e| quad_l[e],
                &mut self.vel_grad,
            );
        }
        if want_f {
            self.def_grad_evaluations += 1;
            if self.quad_f.len() != nq {
                self.quad_f = vec![[Mat3::identity(); 2]; nq];
                self.f_old = vec![Mat3::identity(); nn];
                self.f_new = vec![Mat3::identity(); nn];
                // The initial configuration does not change: its frames once.
                self.quad_f0 = self
                    .quads
                    .iter()
                    .map(|q| centre_frame(q.map(|a| blank.x0[a as usize])))
                    .collect();
            }
            let f0s = &self.quad_f0;
            per_quad(&self.quads, &mut self.quad_f, |e, q, f| {
                let Some(f0) = f0s[e] else {
                    return;
                };
                let xn = q.map(|a| blank.x[a as usize] - blank.v[a as usize] * dt);
                let x1 = q.map(|a| blank.x[a as usize]);
                *f = [deformation_gradient(xn, &f0), deformation_gradient(x1, &f0)];
            });
            let (offsets, around, area) = (&self.offsets, &self.around, &self.quad_area);
            let quad_f = &self.quad_f;
            Self::average(offsets, around, area, |e| quad_f[e][0], &mut self.f_old);
            Self::average(offsets, around, area, |e| quad_f[e][1], &mut self.f_new);
        }
    }

    /// `out[i]` = the mean of `quad(e)` over the quads `e` around node `i`,
    /// weighted by `weight[e]` (in parallel for large blanks, each node alone).
    fn average(
        offsets: &[u32],
        around: &[u32],
        weight: &[f64],
        quad: impl Fn(usize) -> Mat3 + Sync,
        out: &mut [Mat3],
    ) {
        let node = |i: usize, o: &mut Mat3| {
            let mut m = Mat3::zeros();
            let mut w = 0.0;
            for &e in &around[offsets[i] as usize..offsets[i + 1] as usize] {
                let we = weight[e as usize];
                m += quad(e as usize) * we;
                w += we;
            }
            if w > 0.0 {
                *o = m / w;
            }
        };
        if weight.len() > PARALLEL_MIN_GRADIENT_QUADS && rayon::current_num_threads() > 1 {
            out.par_iter_mut()
                .enumerate()
                .with_min_len(GRADIENT_CHUNK)
                .for_each(|(i, o)| node(i, o));
        } else {
            out.iter_mut().enumerate().for_each(|(i, o)| node(i, o));
        }
    }
}

/// `F = Σ x_a ⊗ ∇₀N_a + n ⊗ n₀` at the quad centre (the membrane part of the
/// shell's deformation gradient, completed by the rotation of the normal; the
/// thickness stretch is not included).
fn deformation_gradient(x: [Vec3; 4], f0: &CentreFrame) -> Mat3 {
    let g = surface_gradient(x, f0);
    match centre_frame(x) {
        Some(f) => g + f.normal * f0.normal.transpose(),
        None => Mat3::identity(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plugins_api::kinematics::skew;

    fn square() -> (Vec<Vec3>, Vec<[u32; 4]>) {
        // 2×2 quads on [0,2]×[0,2], slightly distorted interior node.
        let mut x = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                x.push(Vec3::new(i as f64, j as f64, 0.0));
            }
        }
        x[4] = Vec3::new(1.1, 0.93, 0.0);
        let q = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
        (x, q)
    }

    /// Rigid rotation: L must be the spin matrix exactly and F the rotation
    /// (kinematic identities; tolerance 1e-12).
    #[test]
    fn rigid_rotation_gives_spin_and_rotation() {
        let (x0, quads) = square();
        let mut g = BlankGeometry::new(x0.len(), &quads).unwrap();
        let w = Vec3::new(0.3, -0.2, 0.7);
        let big_w = skew(&w);
        let dt = 1e-3;
        // Positions at n+1 after a rotation R about the origin; velocities of the rotation.
        let r = nalgebra::Rotation3::from_scaled_axis(w * 0.5).into_inner();
        let x: Vec<Vec3> = x0.iter().map(|p| r * p).collect();
        // v at mid-step such that x_{n+1/2} = x - ½ dt v: use v = W x_{n+1/2} with
        // x_{n+1/2} = x exactly is not possible for finite dt; any rigid v field
        // v = W y on the mid-step positions y reproduces W exactly.
        let y: Vec<Vec3> = x.clone();
        let v: Vec<Vec3> = y.iter().map(|p| big_w * p).collect();
        let x_shift: Vec<Vec3> = y
            .iter()
            .zip(&v)
            .map(|(p, vv)| p + vv * (0.5 * dt))
            .collect();
        let mass = vec![1.0; x0.len()];
        let thick = vec![1.0; x0.len()];
        let view = BlankView {
            x0: &x0,
            x: &x_shift,
            v: &v,
            mass: &mass,
            thickness: &thick,
            flow_stress: None,
        };
        g.update(
            &view,
            dt,
            PointNeeds::VELOCITY_GRADIENT | PointNeeds::DEFORMATION_GRADIENT,
        );
        for l in &g.vel_grad {
            assert!((l - big_w).norm() < 1e-12, "{l}");
        }
        // F at n+1 of positions x_shift = R x0 + rigid shift: the rotation R'
        // mapping x0 to x_shift is affine but not rigid, so test F at x instead.
        let view2 = BlankView {
            x: &x,
            v: &vec![Vec3::zeros(); x0.len()],
            ..view
        };
        g.update(&view2, dt, PointNeeds::DEFORMATION_GRADIENT);
        for f in &g.f_new {
            assert!((f - r).norm() < 1e-12, "{f}");
        }
        assert_eq!(g.vel_grad_evaluations, 1);
        assert_eq!(g.def_grad_evaluations, 2);
    }

    /// Uniform stretch of a flat sheet: area and F (tolerance 1e-12).
    #[test]
    fn uniform_stretch_area_and_gradient() {
        let (x0, quads) = square();
        let mut g = BlankGeometry::new(x0.len(), &quads).unwrap();
        let s = nalgebra::Matrix3::new(1.2, 0.1, 0.0, 0.0, 0.9, 0.0, 0.0, 0.0, 1.0);
        let x: Vec<Vec3> = x0.iter().map(|p| s * p).collect();
        let zero = vec![Vec3::zeros(); x0.len()];
        let mass = vec![1.0; x0.len()];
        let view = BlankView {
            x0: &x0,
            x: &x,
            v: &zero,
            mass: &mass,
            thickness: &mass,
            flow_stress: None,
        };
        g.update(&view, 1e-3, PointNeeds::DEFORMATION_GRADIENT);
        let total: f64 = g.area.iter().sum();
        assert!((total - 4.0 * s.determinant()).abs() < 1e-12);
        for f in &g.f_new {
            assert!((f - s).norm() < 1e-12);
        }
    }

    #[test]
    fn convective_needs_compute_no_gradients() {
        let (x0, quads) = square();
        let mut g = BlankGeometry::new(x0.len(), &quads).unwrap();
        let zero = vec![Vec3::zeros(); x0.len()];
        let one = vec![1.0; x0.len()];
        let view = BlankView {
            x0: &x0,
            x: &x0,
            v: &zero,
            mass: &one,
            thickness: &one,
            flow_stress: None,
        };
        g.update(&view, 1e-3, PointNeeds::NONE);
        assert_eq!((g.vel_grad_evaluations, g.def_grad_evaluations), (0, 0));
        assert!(g.vel_grad.is_empty() && g.f_new.is_empty());
    }

    /// Above `PARALLEL_MIN_QUADS` the areas and normals are computed in
    /// parallel; they must be the same bits as the plain serial sums over
    /// each node's quads (exact comparison), on one thread and on two.
    #[test]
    fn parallel_areas_match_serial_sums() {
        let m = 60;
        let mut x = Vec::new();
        for j in 0..=m {
            for i in 0..=m {
                let (u, v) = (i as f64, j as f64);
                x.push(Vec3::new(
                    u + 0.1 * (0.7 * v).sin(),
                    v,
                    0.3 * (0.2 * u).sin() * (0.3 * v).cos(),
                ));
            }
        }
        let mut quads = Vec::new();
        for j in 0..m {
            for i in 0..m {
                let a = (j * (m + 1) + i) as u32;
                quads.push([a, a + 1, a + 2 + m as u32, a + 1 + m as u32]);
            }
        }
        assert!(quads.len() > BlankGeometry::PARALLEL_MIN_QUADS);
        let mut expect_area = vec![0.0; x.len()];
        let mut expect_normal = vec![Vec3::zeros(); x.len()];
        let g0 = BlankGeometry::new(x.len(), &quads).unwrap();
        for i in 0..x.len() {
            let mut a = 0.0;
            let mut n = Vec3::zeros();
            for &e in g0.quads_around(i) {
                let f = centre_frame(quads[e as usize].map(|k| x[k as usize])).unwrap();
                a += 0.25 * f.area;
                n += f.normal * f.area;
            }
            expect_area[i] = a;
            expect_normal[i] = n / n.norm();
        }
        for threads in [1, 2] {
            let mut g = g0.clone();
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| g.update_areas(&x));
            assert_eq!(g.area, expect_area, "{threads} threads");
            assert_eq!(g.normal, expect_normal, "{threads} threads");
        }
        // The gradients: the same bits on one and two threads.
        let v: Vec<Vec3> = x
            .iter()
            .map(|p| Vec3::new(0.3 * p.y, -0.2 * p.x, 0.1 * p.x * p.y))
            .collect();
        let x0: Vec<Vec3> = x.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect();
        let (mass, thickness) = (vec![1.0; x.len()], vec![1.0; x.len()]);
        let view = BlankView {
            x0: &x0,
            x: &x,
            v: &v,
            mass: &mass,
            thickness: &thickness,
            flow_stress: None,
        };
        let all = PointNeeds::VELOCITY_GRADIENT | PointNeeds::DEFORMATION_GRADIENT;
        let on = |threads: usize| {
            let mut g = g0.clone();
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| g.update(&view, 1e-6, all));
            (g.vel_grad, g.f_old, g.f_new)
        };
        let (one, two) = (on(1), on(2));
        assert!(one.0.iter().any(|l| l.norm() > 0.1) && one.2.iter().any(|f| f[(2, 0)] != 0.0));
        assert_eq!(one, two);
    }

    #[test]
    fn bad_node_index_is_named() {
        let e = BlankGeometry::new(3, &[[0, 1, 2, 3]]).unwrap_err();
        assert!(e.to_string().contains("element 0 refers to node 3"), "{e}");
    }
}
