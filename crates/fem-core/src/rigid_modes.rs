//! Rigid-body modes of a node cloud under its constraints: which ones the
//! constraints leave free, a minimal 3-2-1 set of DOFs that removes them,
//! and the removal of their best fit from a displacement field.
//!
//! When the tools of a formed part open (springback) the blank is held only
//! by its symmetry conditions. The rigid-body modes these leave free must be
//! removed by a minimal, statically determinate set of constraints (the
//! 3-2-1 rule: [`three_two_one`]), and the springback displacement reported
//! should not depend on which nodes were chosen ([`remove_rigid_motion`]).
//! The 3-2-1 set is translational; [`three_two_one_with_rotations`] also
//! accepts rotational DOFs when the candidate nodes are collinear.
//!
//! # Modes and the rank test
//!
//! A rigid motion with small rotations moves the point `p` by
//! `u(p) = t + θ × (p − c)` and turns every node's rotational DOFs by `θ`;
//! `c` is the centroid of the cloud. With `L` the cloud's size (the largest
//! coordinate difference from `c`), the six coordinates
//! `q = (t_x, t_y, t_z, L θ_x, L θ_y, L θ_z)` are all lengths (mm). Each
//! constrained DOF is one row `a` with `a · q` the motion of that DOF (a
//! translation, or `L` times a rotation), so every entry of `a` is
//! dimensionless and of order one. The Gram matrix `G = Σ a aᵀ` (6×6) gives
//! `qᵀ G q = Σ (a · q)²`, the squared motion of the constrained DOFs. A
//! combination `q` is *free* when it is an eigenvector of `G` with eigenvalue
//! `λ ≤ FREE_TOL · λ_max` ([`FREE_TOL`] = 1e-10): the constrained DOFs move,
//! in the root-sum-square sense, by at most 1e-5 of what the most blocked
//! combination moves them. With no constrained DOF all six are free. The test
//! does not depend on the unit of length nor on where the cloud sits.
//!
//! The free combinations are reported in reduced row-echelon form over `q`
//! ([`free_modes`]): each mode has a leading coordinate equal to 1 that the
//! other modes have at 0, leading coordinates as early in `q` as possible,
//! coordinates below 1e-12 set to 0. A free translation along, or rotation
//! about, a global axis through `c` thus comes out as exactly that mode
//! ([`RigidMode::axis_mode`]).
//!
//! ```
//! use fem_core::rigid_modes::{free_modes, three_two_one};
//! use fem_core::{Dof, Dofs, Vec3};
//!
//! // A plate in z = 0 with symmetry on its edge y = 0 (uy, rx, rz fixed there).
//! let x: Vec<Vec3> = (0..9).map(|i| Vec3::new((i % 3) as f64, (i / 3) as f64, 0.0)).collect();
//! let masks: Vec<u8> = x.iter().map(|p| if p.y == 0.0 { Dofs::symmetry(1).0 } else { 0 }).collect();
//! let free: Vec<_> = free_modes(&x, &masks)?.iter().map(|m| m.axis_mode()).collect();
//! assert_eq!(free, [Some(Dof::Ux), Some(Dof::Uz), Some(Dof::Ry)]);
//! assert_eq!(three_two_one(&x, &masks, None)?.len(), 3);
//! # Ok::<(), fem_core::FemError>(())
//! ```

use nalgebra::{DMatrix, DVector, Matrix6, SymmetricEigen, Vector6};

use crate::{Dof, FemError, Vec3};

/// Relative tolerance of the rank test: an eigenvector of the constraints'
/// Gram matrix is a free mode when its eigenvalue is at most `FREE_TOL`
/// times the largest (so the constrained DOFs move by at most
/// `√FREE_TOL` = 1e-5 of the most blocked combination's motion).
pub const FREE_TOL: f64 = 1e-10;

/// Coordinates of a reported mode below this (in `q`, see the module docs) are set to 0.
const CLEAN_TOL: f64 = 1e-12;

/// A cloud smaller than this fraction of its distance from the origin is a point.
const POINT_TOL: f64 = 1e-12;

/// Smallest pivot (of rows of unit length) in the row-echelon form.
const PIVOT_TOL: f64 = 1e-6;

/// Relative eigenvalue below which a mode's least-squares fit is dropped (it moves no node).
const FIT_TOL: f64 = 1e-12;

/// Iteration cap of the 6×6 and k×k symmetric eigen-decompositions.
const EIGEN_MAX_ITER: usize = 1000;

/// One rigid-body mode: `u(p) = translation + rotation × (p − centre)` on the
/// translational DOFs, `rotation` on the rotational DOFs of every node, per
/// unit amplitude. The amplitude is a length (mm): a unit amplitude of a
/// rotation mode turns the cloud by `1/L` rad, `L` its size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMode {
    /// Translation per unit amplitude (mm/mm, dimensionless).
    pub translation: Vec3,
    /// Rotation vector per unit amplitude (rad/mm).
    pub rotation: Vec3,
    /// The point the rotation turns about: the centroid of the cloud (mm).
    pub centre: Vec3,
}

impl RigidMode {
    /// Displacement of the point `p` (mm per unit amplitude).
    pub fn displacement(&self, p: &Vec3) -> Vec3 {
        self.translation + self.rotation.cross(&(p - self.centre))
    }

    /// Motion of DOF `dof` of a node at `p` per unit amplitude: a component
    /// of [`RigidMode::displacement`] or of the rotation.
    pub fn dof_motion(&self, p: &Vec3, dof: Dof) -> f64 {
        if dof.is_rotation() {
            self.rotation[dof.axis()]
        } else {
            self.displacement(p)[dof.axis()]
        }
    }

    /// The global-axis mode this is, if exactly one of its six components
    /// (translation, rotation) is non-zero: `Uz` for the translation along
    /// z, `Ry` for the rotation about the axis parallel to y through
    /// [`RigidMode::centre`]; `None` for a combination.
    pub fn axis_mode(&self) -> Option<Dof> {
        let mut nonzero = Dof::ALL.into_iter().filter(|d| {
            let v = if d.is_rotation() {
                self.rotation[d.axis()]
            } else {
                self.translation[d.axis()]
            };
            v != 0.0
        });
        match (nonzero.next(), nonzero.next()) {
            (Some(d), None) => Some(d),
            _ => None,
        }
    }
}

/// The rigid modes of `x` (one position per node, mm) that the constrained
/// DOFs leave free; `constrained[i]` is node `i`'s DOF mask (bit
/// `1 << Dof::index()`, as [`crate::Dofs`]). A combination of modes is
/// blocked when it moves a constrained DOF; the rank test and the form of
/// the returned basis are in the module docs. An empty list: nothing free.
///
/// # Errors
/// An empty cloud, a non-finite coordinate, a mask count other than the
/// node count, a mask with bits above `rz`.
pub fn free_modes(x: &[Vec3], constrained: &[u8]) -> Result<Vec<RigidMode>, FemError> {
    check_cloud(x, constrained)?;
    let frame = Frame::of(x)?;
    let g = gram(&frame, x, constrained)?;
    let free = free_space(&g)?;
    Ok(echelon(&free).iter().map(|q| frame.mode(q)).collect())
}

/// A minimal set of translational DOFs `(node, dof)` to fix so that, with
/// the `constrained` ones, no rigid mode of `x` stays free (the 3-2-1 rule);
/// empty when nothing is free.
///
/// Nodes come from `candidates` (all nodes when `None`): `n1` the one
/// nearest the centroid of the whole cloud, `n2` the one farthest from `n1`,
/// `n3` the one farthest from the line `n1`–`n2` (first in candidate order
/// on ties). The DOFs `ux, uy, uz` of `n1`, then of `n2`, then of `n3` are
/// taken in that order, each one kept when it lowers the number of free
/// modes ([`free_modes`]' test), until none is free. A free cloud gets three
/// DOFs on `n1`, two on `n2`, one on `n3`.
///
/// # Errors
/// Those of [`free_modes`]; a candidate that is not a node; no candidate
/// while a mode is free; modes that the candidates' translations cannot
/// remove (candidates at one point or on one line leave rotations free; see
/// [`three_two_one_with_rotations`]).
pub fn three_two_one(
    x: &[Vec3],
    constrained: &[u8],
    candidates: Option<&[u32]>,
) -> Result<Vec<(u32, Dof)>, FemError> {
    choose_constraints(x, constrained, candidates, false)
}

/// As [`three_two_one`], but when the translations of `n1`, `n2`, `n3`
/// leave a mode free (candidates at one point or on one line), the
/// rotational DOFs `rx, ry, rz` of `n1` are tried next, in that order. Such
/// a rotational DOF holds the part through the bending stiffness of the
/// shells at one node.
///
/// # Errors
/// As [`three_two_one`], but for candidates at one point or on one line.
pub fn three_two_one_with_rotations(
    x: &[Vec3],
    constrained: &[u8],
    candidates: Option<&[u32]>,
) -> Result<Vec<(u32, Dof)>, FemError> {
    choose_constraints(x, constrained, candidates, true)
}

/// Subtracts from the displacement field `d` (mm, one per node at the
/// positions `x`) its least-squares fit by `modes`, linearised (small
/// rotations), every node weighted equally, and returns the fit's
/// amplitudes (one per mode; the removed motion is `Σ a_j u_j`).
///
/// Only translations are fitted and changed: the field's rotational DOFs are
/// not read, and a caller who keeps them subtracts the fit's rotation
/// `Σ a_j modes[j].rotation` itself. A mode that moves no node (a rotation
/// of a cloud on one line about that line) is not fitted (amplitude 0).
///
/// With `modes` the free modes of the constraints ([`free_modes`]), the
/// result does not depend on which further constraints removed them: two
/// fields that differ by a combination of the modes give the same result, to
/// rounding for a linearised rigid motion; for a finite rotation by `θ` (rad)
/// about a point `o`, to the motion's second-order part, whose root mean
/// square over the nodes is at most `θ² max|p − o| / 2`.
///
/// # Errors
/// An empty cloud, a non-finite coordinate, displacement or mode, a field
/// length other than the node count, modes too large to fit.
pub fn remove_rigid_motion(
    x: &[Vec3],
    d: &mut [Vec3],
    modes: &[RigidMode],
) -> Result<Vec<f64>, FemError> {
    check_positions(x)?;
    if d.len() != x.len() {
        return Err(FemError::InvalidSetup(format!(
            "the displacement field `d` has {} vectors for {} nodes: give one per node",
            d.len(),
            x.len()
        )));
    }
    for (i, v) in d.iter().enumerate() {
        check_vector(v, || format!("d[{i}]"), "mm")?;
    }
    for (j, m) in modes.iter().enumerate() {
        check_vector(&m.translation, || format!("modes[{j}].translation"), "-")?;
        check_vector(&m.rotation, || format!("modes[{j}].rotation"), "rad/mm")?;
        check_vector(&m.centre, || format!("modes[{j}].centre"), "mm")?;
    }
    if modes.is_empty() {
        return Ok(Vec::new());
    }
    let k = modes.len();
    let mut u = vec![Vec3::zeros(); k];
    let mut m = DMatrix::<f64>::zeros(k, k);
    for p in x {
        for (uj, mode) in u.iter_mut().zip(modes) {
            *uj = mode.displacement(p);
        }
        for a in 0..k {
            for b in a..k {
                m[(a, b)] += u[a].dot(&u[b]);
            }
        }
    }
    for a in 0..k {
        for b in 0..a {
            m[(a, b)] = m[(b, a)];
        }
    }
    let solve = pseudo_inverse(&m)?;
    let mut amplitudes = DVector::<f64>::zeros(k);
    // One projection, then one more of what is left (iterative refinement).
    for _ in 0..2 {
        let mut rhs = DVector::<f64>::zeros(k);
        for (p, v) in x.iter().zip(d.iter()) {
            for (j, mode) in modes.iter().enumerate() {
                rhs[j] += mode.displacement(p).dot(v);
            }
        }
        let a = &solve * rhs;
        for (p, v) in x.iter().zip(d.iter_mut()) {
            for (j, mode) in modes.iter().enumerate() {
                *v -= mode.displacement(p) * a[j];
            }
        }
        amplitudes += a;
    }
    Ok(amplitudes.iter().copied().collect())
}

/// Centroid and size of a cloud: the frame of the mode coordinates `q`.
struct Frame {
    /// Centroid (mm).
    centre: Vec3,
    /// Size `L` (mm): the largest coordinate difference from the centroid.
    length: f64,
}

impl Frame {
    /// The frame of the (non-empty, finite) cloud `x`.
    fn of(x: &[Vec3]) -> Result<Frame, FemError> {
        let mut centre = Vec3::zeros();
        for (k, p) in x.iter().enumerate() {
            centre += (p - centre) / (k + 1) as f64;
        }
        let radius = x.iter().map(|p| (p - centre).amax()).fold(0.0, f64::max);
        let reach = x.iter().map(|p| p.amax()).fold(0.0, f64::max);
        let length = if radius > POINT_TOL * reach {
            radius
        } else if reach > 0.0 {
            reach
        } else {
            1.0
        };
        if !(centre.iter().all(|v| v.is_finite()) && length.is_finite()) {
            return Err(FemError::InvalidSetup(format!(
                "node coordinates up to {reach:e} mm are too large to take the centroid of"
            )));
        }
        Ok(Frame { centre, length })
    }

    /// Position of `p` relative to the centroid, in units of the size.
    fn scaled(&self, p: &Vec3) -> Vec3 {
        (p - self.centre) / self.length
    }

    /// The constraint row `a` of DOF `dof` of a node at `p`: `a · q` is that
    /// DOF's motion (a translation, or `L` times a rotation).
    fn row(&self, p: &Vec3, dof: Dof) -> Vector6<f64> {
        let mut a = Vector6::zeros();
        if dof.is_rotation() {
            a[dof.index()] = 1.0;
        } else {
            let k = dof.axis();
            let s = self.scaled(p);
            a[k] = 1.0;
            for b in 0..3 {
                a[3 + b] = Vec3::ith(b, 1.0).cross(&s)[k];
            }
        }
        a
    }

    /// The mode of coordinates `q`.
    fn mode(&self, q: &Vector6<f64>) -> RigidMode {
        RigidMode {
            translation: Vec3::new(q[0], q[1], q[2]),
            rotation: Vec3::new(q[3], q[4], q[5]) / self.length,
            centre: self.centre,
        }
    }
}

/// Checks that the cloud is not empty and its coordinates are finite.
fn check_positions(x: &[Vec3]) -> Result<(), FemError> {
    if x.is_empty() {
        return Err(FemError::InvalidSetup(
            "the node cloud `x` is empty: rigid modes need at least one node".to_string(),
        ));
    }
    for (node, p) in x.iter().enumerate() {
        for (axis, &value) in ["x", "y", "z"].into_iter().zip(p.iter()) {
            if !value.is_finite() {
                return Err(FemError::NonFiniteCoordinate { node, axis, value });
            }
        }
    }
    Ok(())
}

/// Checks [`check_positions`] and one valid DOF mask per node.
fn check_cloud(x: &[Vec3], constrained: &[u8]) -> Result<(), FemError> {
    check_positions(x)?;
    if constrained.len() != x.len() {
        return Err(FemError::InvalidSetup(format!(
            "`constrained` has {} DOF masks for {} nodes: give one mask per node",
            constrained.len(),
            x.len()
        )));
    }
    if let Some((i, &mask)) = constrained.iter().enumerate().find(|(_, m)| **m >= 1 << 6) {
        return Err(FemError::InvalidParameter {
            field: format!("constrained[{i}]"),
            value: f64::from(mask),
            unit: "-",
            range: "a DOF mask below 64 (bits ux to rz)",
        });
    }
    Ok(())
}

/// Checks that every component of `v` is finite; `field` names it.
fn check_vector(v: &Vec3, field: impl Fn() -> String, unit: &'static str) -> Result<(), FemError> {
    for (axis, &value) in ["x", "y", "z"].into_iter().zip(v.iter()) {
        if !value.is_finite() {
            return Err(FemError::InvalidParameter {
                field: format!("{}.{axis}", field()),
                value,
                unit,
                range: "finite",
            });
        }
    }
    Ok(())
}

/// The Gram matrix `Σ a aᵀ` of the constrained DOFs' rows.
fn gram(frame: &Frame, x: &[Vec3], constrained: &[u8]) -> Result<Matrix6<f64>, FemError> {
    let mut g = Matrix6::zeros();
    for (p, &mask) in x.iter().zip(constrained) {
        for dof in Dof::ALL {
            if mask & (1 << dof.index()) != 0 {
                let a = frame.row(p, dof);
                g += a * a.transpose();
            }
        }
    }
    if g.iter().all(|v| v.is_finite()) {
        Ok(g)
    } else {
        Err(FemError::InvalidSetup(
            "the constraint Gram matrix of the rigid modes is not finite (node coordinates too large)"
                .to_string(),
        ))
    }
}

/// An orthonormal basis of the free combinations of `G` (see [`FREE_TOL`]).
fn free_space(g: &Matrix6<f64>) -> Result<Vec<Vector6<f64>>, FemError> {
    let eig = SymmetricEigen::try_new(*g, f64::EPSILON, EIGEN_MAX_ITER).ok_or_else(|| {
        FemError::InvalidSetup(
            "the eigen-decomposition of the constraint Gram matrix did not converge".to_string(),
        )
    })?;
    let largest = eig.eigenvalues.iter().copied().fold(0.0, f64::max);
    let tol = FREE_TOL * largest;
    Ok((0..6)
        .filter(|&i| eig.eigenvalues[i] <= tol)
        .map(|i| eig.eigenvectors.column(i).into_owned())
        .collect())
}

/// The reduced row-echelon form of the span of `basis` (see the module docs).
fn echelon(basis: &[Vector6<f64>]) -> Vec<Vector6<f64>> {
    let mut rows = basis.to_vec();
    let k = rows.len();
    let mut pivots = 0;
    for col in 0..6 {
        if pivots == k {
            break;
        }
        for row in &mut rows[pivots..] {
            let n = row.norm();
            if n > 0.0 {
                *row /= n;
            }
        }
        let mut best = pivots;
        for r in pivots + 1..k {
            if rows[r][col].abs() > rows[best][col].abs() {
                best = r;
            }
        }
        if rows[best][col].abs() < PIVOT_TOL {
            continue;
        }
        rows.swap(pivots, best);
        let pivot = rows[pivots] / rows[pivots][col];
        for (r, row) in rows.iter_mut().enumerate() {
            if r == pivots {
                *row = pivot;
            } else {
                let f = row[col];
                *row -= pivot * f;
                row[col] = 0.0;
            }
        }
        pivots += 1;
    }
    for row in &mut rows {
        row.apply(|v| {
            if v.abs() < CLEAN_TOL {
                *v = 0.0;
            }
        });
    }
    rows
}

/// The Moore–Penrose inverse of the symmetric positive semi-definite `m`,
/// with Jacobi scaling; directions below [`FIT_TOL`] are dropped.
fn pseudo_inverse(m: &DMatrix<f64>) -> Result<DMatrix<f64>, FemError> {
    let k = m.nrows();
    if !m.iter().all(|v| v.is_finite()) {
        return Err(FemError::InvalidSetup(
            "the rigid modes are too large to fit (their Gram matrix is not finite)".to_string(),
        ));
    }
    let scale = DVector::from_iterator(
        k,
        m.diagonal()
            .iter()
            .map(|&v| if v > 0.0 { 1.0 / v.sqrt() } else { 0.0 }),
    );
    let scaled = DMatrix::from_fn(k, k, |a, b| m[(a, b)] * scale[a] * scale[b]);
    let eig = SymmetricEigen::try_new(scaled, f64::EPSILON, EIGEN_MAX_ITER).ok_or_else(|| {
        FemError::InvalidSetup(
            "the eigen-decomposition of the rigid modes' Gram matrix did not converge".to_string(),
        )
    })?;
    let largest = eig.eigenvalues.iter().copied().fold(0.0, f64::max);
    let mut inverse = DMatrix::<f64>::zeros(k, k);
    for (i, &lambda) in eig.eigenvalues.iter().enumerate() {
        if lambda > FIT_TOL * largest {
            let v = eig.eigenvectors.column(i);
            inverse += v * v.transpose() / lambda;
        }
    }
    Ok(DMatrix::from_fn(k, k, |a, b| {
        inverse[(a, b)] * scale[a] * scale[b]
    }))
}

/// The 3-2-1 choice of [`three_two_one`], with the rotations of `n1` as a
/// last resort when `rotations` is set.
fn choose_constraints(
    x: &[Vec3],
    constrained: &[u8],
    candidates: Option<&[u32]>,
    rotations: bool,
) -> Result<Vec<(u32, Dof)>, FemError> {
    check_cloud(x, constrained)?;
    let candidates = candidate_list(x.len(), candidates)?;
    let frame = Frame::of(x)?;
    let mut g = gram(&frame, x, constrained)?;
    let mut free = free_space(&g)?.len();
    if free == 0 {
        return Ok(Vec::new());
    }
    if candidates.is_empty() {
        return Err(FemError::InvalidSetup(format!(
            "three_two_one: `candidates` is empty but {free} rigid mode(s) are free"
        )));
    }
    let picked = Picked::of(&frame, x, &candidates);
    let [n1, n2, n3] = picked.nodes;
    let mut order: Vec<(u32, Dof)> = [n1, n2, n3]
        .into_iter()
        .flat_map(|n| [Dof::Ux, Dof::Uy, Dof::Uz].map(|d| (n, d)))
        .collect();
    if rotations {
        order.extend([Dof::Rx, Dof::Ry, Dof::Rz].map(|d| (n1, d)));
    }
    let mut chosen = Vec::new();
    for (n, dof) in order {
        if free == 0 {
            break;
        }
        if constrained[n as usize] & (1 << dof.index()) != 0 || chosen.contains(&(n, dof)) {
            continue;
        }
        let a = frame.row(&x[n as usize], dof);
        let trial = g + a * a.transpose();
        let left = free_space(&trial)?.len();
        if left < free {
            g = trial;
            free = left;
            chosen.push((n, dof));
        }
    }
    if free == 0 {
        Ok(chosen)
    } else {
        Err(picked.stuck(free, frame.length))
    }
}

/// The candidate nodes: `candidates` checked against the node count, or all nodes.
fn candidate_list(n_nodes: usize, candidates: Option<&[u32]>) -> Result<Vec<u32>, FemError> {
    let n = u32::try_from(n_nodes).map_err(|_| {
        FemError::InvalidSetup(format!(
            "three_two_one: {n_nodes} nodes do not fit u32 node numbers"
        ))
    })?;
    match candidates {
        Some(c) => match c.iter().enumerate().find(|(_, m)| **m >= n) {
            Some((k, m)) => Err(FemError::InvalidSetup(format!(
                "three_two_one: candidates[{k}] = {m} is not a node (the cloud has {n})"
            ))),
            None => Ok(c.to_vec()),
        },
        None => Ok((0..n).collect()),
    }
}

/// The three nodes of the 3-2-1 rule and how far apart they are.
struct Picked {
    /// `n1` (nearest the centroid), `n2` (farthest from `n1`), `n3`
    /// (farthest from the line `n1`–`n2`).
    nodes: [u32; 3],
    /// Distance `n1`–`n2`, in units of the cloud's size.
    spread: f64,
    /// Distance of `n3` from the line `n1`–`n2`, in units of the cloud's size.
    offset: f64,
}

impl Picked {
    /// Picks the nodes among the (non-empty) `candidates`, first on ties.
    fn of(frame: &Frame, x: &[Vec3], candidates: &[u32]) -> Picked {
        let s = |n: u32| frame.scaled(&x[n as usize]);
        let best = |f: &dyn Fn(Vec3) -> f64| {
            let mut best = (candidates[0], f(s(candidates[0])));
            for &n in &candidates[1..] {
                let v = f(s(n));
                if v > best.1 {
                    best = (n, v);
                }
            }
            best
        };
        let n1 = best(&|p| -p.norm()).0;
        let s1 = s(n1);
        let (n2, spread) = best(&|p| (p - s1).norm());
        let line = (s(n2) - s1).try_normalize(0.0);
        let (n3, offset) = best(&|p| match line {
            Some(e) => (p - s1).cross(&e).norm(),
            None => (p - s1).norm(),
        });
        Picked {
            nodes: [n1, n2, n3],
            spread,
            offset,
        }
    }

    /// The error when `free` modes stay free, `size` the cloud's size (mm).
    fn stuck(&self, free: usize, size: f64) -> FemError {
        let [n1, n2, n3] = self.nodes;
        let why = if self.spread <= FREE_TOL.sqrt() {
            format!(
                "the candidate nodes sit at one point (all within {:.3e} mm of node {n1}): \
                 add candidates spread over the part",
                self.spread * size
            )
        } else if self.offset <= FREE_TOL.sqrt() {
            format!(
                "the candidate nodes are collinear (node {n3}, the farthest from the line of \
                 nodes {n1} and {n2}, is {:.3e} mm off it): add a candidate off that line",
                self.offset * size
            )
        } else {
            format!("the DOFs of nodes {n1}, {n2} and {n3} do not reach them")
        };
        FemError::InvalidSetup(format!(
            "three_two_one: {free} rigid mode(s) stay free because {why}"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Dofs;

    /// A doubly curved panel on `[0, 120] × [0, 80]` mm, `nx × ny` nodes,
    /// with its corner at the origin: the quarter of a part whose symmetry
    /// planes are `x = 0` and `y = 0`.
    fn panel(nx: usize, ny: usize) -> Vec<Vec3> {
        let mut x = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let px = 120.0 * i as f64 / (nx - 1) as f64;
                let py = 80.0 * j as f64 / (ny - 1) as f64;
                x.push(Vec3::new(px, py, 20.0 - 1e-3 * px * px - 2e-3 * py * py));
            }
        }
        x
    }

    /// Symmetry masks: `Dofs::symmetry(axis)` on the nodes of the plane
    /// through the origin normal to each of `axes`.
    fn symmetry(x: &[Vec3], axes: &[usize]) -> Vec<u8> {
        x.iter()
            .map(|p| {
                axes.iter()
                    .filter(|&&a| p[a] == 0.0)
                    .fold(Dofs::NONE, |m, &a| m.with(Dofs::symmetry(a)))
                    .0
            })
            .collect()
    }

    /// `masks` with `dofs` added.
    fn with_fixed(masks: &[u8], dofs: &[(u32, Dof)]) -> Vec<u8> {
        let mut m = masks.to_vec();
        for &(n, d) in dofs {
            m[n as usize] |= 1 << d.index();
        }
        m
    }

    fn axis_modes(modes: &[RigidMode]) -> Vec<Option<Dof>> {
        modes.iter().map(RigidMode::axis_mode).collect()
    }

    /// A smooth non-rigid field (mm): bending, twist and in-plane stretch.
    fn deformation(x: &[Vec3]) -> Vec<Vec3> {
        x.iter()
            .map(|p| {
                Vec3::new(
                    2e-4 * p.x * p.y / 10.0 + 0.03 * (p.z / 7.0).sin(),
                    1e-3 * p.y + 0.02 * (p.x / 30.0).cos(),
                    3e-5 * p.x * p.x + 1e-5 * p.x * p.y - 4e-5 * p.y * p.y,
                )
            })
            .collect()
    }

    /// Finite rigid motion: rotation vector `theta` (rad) about `o`, then `t`.
    fn finite_rigid(x: &[Vec3], t: Vec3, theta: Vec3, o: Vec3) -> Vec<Vec3> {
        let r = nalgebra::Rotation3::new(theta);
        x.iter().map(|p| t + (r * (p - o) - (p - o))).collect()
    }

    fn max_norm(v: &[Vec3]) -> f64 {
        v.iter().map(|a| a.norm()).fold(0.0, f64::max)
    }

    fn rms_diff(a: &[Vec3], b: &[Vec3]) -> f64 {
        let s: f64 = a.iter().zip(b).map(|(p, q)| (p - q).norm_squared()).sum();
        (s / a.len() as f64).sqrt()
    }

    fn max_diff(a: &[Vec3], b: &[Vec3]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max)
    }

    /// No constraint: all six modes, each a pure global-axis mode.
    #[test]
    fn free_cloud_has_six_free_modes() {
        let x = panel(7, 5);
        let modes = free_modes(&x, &vec![0; x.len()]).unwrap();
        assert_eq!(axis_modes(&modes), Dof::ALL.map(Some));
    }

    /// Symmetry on `x = 0` (ux, ry, rz) and `y = 0` (uy, rx, rz): only the
    /// translation along z, exactly `(0, 0, 1)`.
    #[test]
    fn quarter_model_leaves_z_translation_free() {
        let x = panel(7, 5);
        let modes = free_modes(&x, &symmetry(&x, &[0, 1])).unwrap();
        assert_eq!(axis_modes(&modes), [Some(Dof::Uz)]);
        assert_eq!(modes[0].translation, Vec3::z());
        assert_eq!(modes[0].rotation, Vec3::zeros());
    }

    /// Symmetry on `y = 0` (uy, rx, rz) of a curved panel: the
    /// translations along x and z and the rotation about y.
    #[test]
    fn half_model_leaves_three_modes_free() {
        let x = panel(7, 5);
        let modes = free_modes(&x, &symmetry(&x, &[1])).unwrap();
        assert_eq!(
            axis_modes(&modes),
            [Some(Dof::Ux), Some(Dof::Uz), Some(Dof::Ry)]
        );
    }

    /// One node with all six DOFs fixed holds every mode.
    #[test]
    fn clamped_node_leaves_no_mode_free() {
        let x = panel(7, 5);
        let mut masks = vec![0; x.len()];
        masks[9] = Dofs::ALL.0;
        assert!(free_modes(&x, &masks).unwrap().is_empty());
    }

    /// A rigid rotation turns the rotational DOFs: `rz` fixed on one node
    /// blocks the rotation about z and nothing else.
    #[test]
    fn rotational_dof_blocks_its_rotation() {
        let x = panel(7, 5);
        let mut masks = vec![0; x.len()];
        masks[12] = Dofs::of(&[Dof::Rz]).0;
        let modes = free_modes(&x, &masks).unwrap();
        assert!(modes.iter().all(|m| m.dof_motion(&x[12], Dof::Rz) == 0.0));
        assert!(modes.iter().any(|m| m.dof_motion(&x[12], Dof::Rx) != 0.0));
        assert_eq!(
            axis_modes(&modes),
            [Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry].map(Some)
        );
    }

    /// The same panel in metres 1 km from the origin and in micrometres:
    /// the same free modes for the half model, for a 3-2-1 set chosen in mm
    /// (none) and for that set without its last DOF (one), so the rank test
    /// is unit-free.
    #[test]
    fn free_modes_do_not_depend_on_units_or_position() {
        let x = panel(7, 5);
        let half = symmetry(&x, &[1]);
        let free = vec![0; x.len()];
        let chosen = three_two_one(&x, &free, None).unwrap();
        let cases = [
            half,
            with_fixed(&free, &chosen),
            with_fixed(&free, &chosen[..chosen.len() - 1]),
        ];
        for masks in &cases {
            let expect = free_modes(&x, masks).unwrap();
            for (scale, shift) in [(1e-3, 1e6), (1e3, 0.0)] {
                let moved: Vec<Vec3> = x
                    .iter()
                    .map(|p| p * scale + Vec3::new(shift, 0.0, -shift))
                    .collect();
                let got = free_modes(&moved, masks).unwrap();
                assert_eq!(got.len(), expect.len(), "scale {scale}, shift {shift}");
                // Coordinates q = (t, L θ), L = 60 mm; the moved clouds are
                // rounded to 1e-16 of 1e6 m, 2e-9 of their size, hence 1e-6.
                let q = |m: &RigidMode, s: f64| {
                    let r = m.rotation * s * 60.0;
                    Vector6::new(
                        m.translation.x,
                        m.translation.y,
                        m.translation.z,
                        r.x,
                        r.y,
                        r.z,
                    )
                };
                for (g, e) in got.iter().zip(&expect) {
                    let err = (q(g, scale) - q(e, 1.0)).norm();
                    assert!(err <= 1e-6 * q(e, 1.0).norm(), "{g:?} vs {e:?}");
                }
            }
        }
        assert_eq!(free_modes(&x, &cases[2]).unwrap().len(), 1);
    }

    /// A free cloud: six translational DOFs, 3 on `n1`, 2 on `n2`, 1 on
    /// `n3`, three non-collinear nodes, after which nothing is free.
    #[test]
    fn three_two_one_on_free_cloud_fixes_six_dofs_on_three_nodes() {
        let x = panel(7, 5);
        let masks = vec![0; x.len()];
        let chosen = three_two_one(&x, &masks, None).unwrap();
        assert_eq!(chosen.len(), 6, "{chosen:?}");
        assert!(chosen.iter().all(|(_, d)| !d.is_rotation()));
        let mut nodes: Vec<u32> = chosen.iter().map(|c| c.0).collect();
        nodes.dedup();
        assert_eq!(nodes.len(), 3, "{chosen:?}");
        let [a, b, c] = [0, 1, 2].map(|k| x[nodes[k] as usize]);
        let area = (b - a).cross(&(c - a)).norm();
        assert!(
            area > 1e3,
            "nodes {nodes:?} are (nearly) collinear: |ab × ac| = {area} mm²"
        );
        let count = |n| chosen.iter().filter(|c| c.0 == n).count();
        assert_eq!(
            nodes.iter().map(|&n| count(n)).collect::<Vec<_>>(),
            [3, 2, 1]
        );
        assert!(
            free_modes(&x, &with_fixed(&masks, &chosen))
                .unwrap()
                .is_empty()
        );
    }

    /// The quarter model: one DOF, `uz` of the node nearest the centroid
    /// (found here by brute force).
    #[test]
    fn three_two_one_on_quarter_model_fixes_uz_of_node_nearest_centroid() {
        let x = panel(7, 5);
        let masks = symmetry(&x, &[0, 1]);
        let c = x.iter().sum::<Vec3>() / x.len() as f64;
        let nearest = (0..x.len())
            .min_by(|&a, &b| (x[a] - c).norm().total_cmp(&(x[b] - c).norm()))
            .unwrap() as u32;
        assert_eq!(
            three_two_one(&x, &masks, None).unwrap(),
            [(nearest, Dof::Uz)]
        );
    }

    /// The half model: three DOFs, after which nothing is free.
    #[test]
    fn three_two_one_on_half_model_fixes_three_dofs() {
        let x = panel(7, 5);
        let masks = symmetry(&x, &[1]);
        let chosen = three_two_one(&x, &masks, None).unwrap();
        assert_eq!(chosen.len(), 3, "{chosen:?}");
        assert!(
            free_modes(&x, &with_fixed(&masks, &chosen))
                .unwrap()
                .is_empty()
        );
    }

    /// Nothing free: nothing to fix.
    #[test]
    fn three_two_one_with_nothing_free_is_empty() {
        let x = panel(7, 5);
        let mut masks = vec![0; x.len()];
        masks[3] = Dofs::ALL.0;
        assert!(three_two_one(&x, &masks, None).unwrap().is_empty());
    }

    /// Candidates on one straight line (the edge `y = 0` of a panel curved
    /// only along y): a one-line error naming the collinearity; allowing
    /// rotations, one rotational DOF of `n1` removes the last mode.
    #[test]
    fn three_two_one_collinear_candidates_are_an_error() {
        let x: Vec<Vec3> = panel(7, 5)
            .iter()
            .map(|p| Vec3::new(p.x, p.y, -2e-3 * p.y * p.y))
            .collect();
        let masks = vec![0; x.len()];
        let line: Vec<u32> = (0..7).collect();
        let err = three_two_one(&x, &masks, Some(&line))
            .unwrap_err()
            .to_string();
        assert!(err.contains("collinear") && !err.contains('\n'), "{err}");
        let chosen = three_two_one_with_rotations(&x, &masks, Some(&line)).unwrap();
        assert_eq!(chosen.len(), 6, "{chosen:?}");
        assert_eq!(
            chosen.iter().filter(|c| c.1.is_rotation()).count(),
            1,
            "{chosen:?}"
        );
        assert!(
            free_modes(&x, &with_fixed(&masks, &chosen))
                .unwrap()
                .is_empty()
        );
        let one = [3];
        let err = three_two_one(&x, &masks, Some(&one))
            .unwrap_err()
            .to_string();
        assert!(err.contains("one point") && !err.contains('\n'), "{err}");
    }

    /// The deformation plus a linearised rigid motion of the free modes
    /// gives the deformation's own residual to 1e-12 of the field, whichever
    /// motion was added; free cloud (six modes) and half model (three).
    #[test]
    fn removed_field_does_not_depend_on_added_linear_rigid_motion() {
        let x = panel(9, 6);
        for masks in [vec![0; x.len()], symmetry(&x, &[1])] {
            let modes = free_modes(&x, &masks).unwrap();
            let w = deformation(&x);
            let mut reference = w.clone();
            remove_rigid_motion(&x, &mut reference, &modes).unwrap();
            for amplitudes in [
                [0.7, -1.3, 0.4, 2.1, -0.6, 0.9],
                [-5.0, 0.2, 3.3, -0.8, 1.7, -2.4],
            ] {
                let mut d = w.clone();
                for (p, v) in x.iter().zip(&mut d) {
                    for (m, a) in modes.iter().zip(amplitudes) {
                        *v += m.displacement(p) * a;
                    }
                }
                let size = max_norm(&d);
                let a = remove_rigid_motion(&x, &mut d, &modes).unwrap();
                assert_eq!(a.len(), modes.len());
                let err = max_diff(&d, &reference);
                assert!(err <= 1e-12 * size, "max |Δ| = {err:e} mm, field {size} mm");
            }
        }
    }

    /// A finite rigid motion (rotation by 1e-6 rad about a point off the
    /// part, plus a translation): the residual matches the deformation's own
    /// within the second-order part of the rotation, whose root mean square
    /// is at most `θ² max|p − o| / 2` (≈ 1e-10 mm here), plus 1e-12 of the
    /// field for rounding.
    #[test]
    fn removed_field_does_not_depend_on_added_small_finite_rotation() {
        let x = panel(9, 6);
        let w = deformation(&x);
        let cases = [
            (
                vec![0; x.len()],
                Vec3::new(0.4, -0.9, 0.3),
                Vec3::new(3e-7, -5e-7, 8e-7),
            ),
            (
                symmetry(&x, &[1]),
                Vec3::new(-0.6, 0.0, 1.1),
                Vec3::new(0.0, 1e-6, 0.0),
            ),
        ];
        for (masks, t, theta) in cases {
            let modes = free_modes(&x, &masks).unwrap();
            let mut reference = w.clone();
            remove_rigid_motion(&x, &mut reference, &modes).unwrap();
            let o = Vec3::new(-50.0, 0.0, 35.0);
            let rigid = finite_rigid(&x, t, theta, o);
            let mut d: Vec<Vec3> = w.iter().zip(&rigid).map(|(a, b)| a + b).collect();
            let size = max_norm(&d);
            remove_rigid_motion(&x, &mut d, &modes).unwrap();
            let reach = x.iter().map(|p| (p - o).norm()).fold(0.0, f64::max);
            let bound = 0.5 * theta.norm_squared() * reach + 1e-12 * size;
            let err = rms_diff(&d, &reference);
            assert!(err <= bound, "rms |Δ| = {err:e} mm > {bound:e} mm");
        }
    }

    /// A pure linearised rigid motion of the free modes is removed to 1e-12
    /// of its size, and the amplitudes are recovered.
    #[test]
    fn pure_rigid_motion_is_removed() {
        let x = panel(9, 6);
        let modes = free_modes(&x, &vec![0; x.len()]).unwrap();
        let amplitudes = [1.5, -0.25, 0.75, -3.0, 0.5, 2.0];
        let mut d: Vec<Vec3> = x
            .iter()
            .map(|p| {
                modes
                    .iter()
                    .zip(amplitudes)
                    .map(|(m, a)| m.displacement(p) * a)
                    .sum()
            })
            .collect();
        let size = max_norm(&d);
        let a = remove_rigid_motion(&x, &mut d, &modes).unwrap();
        assert!(
            max_norm(&d) <= 1e-12 * size,
            "left {:e} mm of {size} mm",
            max_norm(&d)
        );
        for (got, want) in a.iter().zip(amplitudes) {
            assert!(
                (got - want).abs() <= 1e-12 * size,
                "amplitude {got} vs {want}"
            );
        }
    }

    /// A mode that moves no node (the rotation of a straight line of nodes
    /// about itself) is not fitted: amplitude 0, no NaN.
    #[test]
    fn mode_moving_no_node_is_not_fitted() {
        let x: Vec<Vec3> = (0..5)
            .map(|i| Vec3::new(10.0 * i as f64, 0.0, 0.0))
            .collect();
        let modes = free_modes(&x, &vec![0; x.len()]).unwrap();
        let mut d: Vec<Vec3> = x
            .iter()
            .map(|p| Vec3::new(0.0, 1.0 + 1e-2 * p.x, 0.0))
            .collect();
        let a = remove_rigid_motion(&x, &mut d, &modes).unwrap();
        assert_eq!(a[3], 0.0, "rotation about x: {a:?}");
        assert!(max_norm(&d) <= 1e-12, "{d:?}");
    }

    /// Bad input gives a one-line error, not a panic.
    #[test]
    fn bad_inputs_are_errors() {
        let x = panel(3, 3);
        let masks = vec![0; x.len()];
        let one_line = |e: FemError| {
            let s = e.to_string();
            assert!(!s.contains('\n'), "{s}");
            s
        };
        let mut nan = x.clone();
        nan[4].y = f64::NAN;
        assert!(one_line(free_modes(&nan, &masks).unwrap_err()).contains("node 4: coordinate y"));
        assert!(one_line(three_two_one(&nan, &masks, None).unwrap_err()).contains("node 4"));
        assert!(one_line(free_modes(&x, &masks[1..]).unwrap_err()).contains("`constrained`"));
        assert!(
            one_line(three_two_one(&x, &masks[1..], None).unwrap_err()).contains("`constrained`")
        );
        assert!(one_line(free_modes(&[], &[]).unwrap_err()).contains("empty"));
        assert!(one_line(three_two_one(&[], &[], None).unwrap_err()).contains("empty"));
        let mut wide = masks.clone();
        wide[2] = 0b100_0000;
        assert!(one_line(free_modes(&x, &wide).unwrap_err()).contains("constrained[2]"));
        assert!(
            one_line(three_two_one(&x, &masks, Some(&[0, 9])).unwrap_err())
                .contains("candidates[1]")
        );
        assert!(one_line(three_two_one(&x, &masks, Some(&[])).unwrap_err()).contains("empty"));

        let modes = free_modes(&x, &masks).unwrap();
        let mut d = vec![Vec3::zeros(); x.len()];
        d[5].z = f64::INFINITY;
        assert!(one_line(remove_rigid_motion(&x, &mut d, &modes).unwrap_err()).contains("d[5].z"));
        let mut short = vec![Vec3::zeros(); 2];
        assert!(one_line(remove_rigid_motion(&x, &mut short, &modes).unwrap_err()).contains("`d`"));
        assert!(
            one_line(remove_rigid_motion(&nan, &mut vec![Vec3::zeros(); 9], &modes).unwrap_err())
                .contains("node 4")
        );
        assert!(one_line(remove_rigid_motion(&[], &mut [], &modes).unwrap_err()).contains("empty"));
        let mut bad = modes.clone();
        bad[1].rotation.x = f64::NAN;
        let mut d = vec![Vec3::zeros(); x.len()];
        assert!(
            one_line(remove_rigid_motion(&x, &mut d, &bad).unwrap_err())
                .contains("modes[1].rotation.x")
        );
        let huge = [
            Vec3::new(1e308, 0.0, 0.0),
            Vec3::new(-1e308, 1.0, 0.0),
            Vec3::zeros(),
        ];
        match free_modes(&huge, &[0, 0, 0]) {
            Ok(modes) => assert!(
                modes
                    .iter()
                    .all(|m| m.rotation.iter().all(|v| v.is_finite()))
            ),
            Err(e) => assert!(one_line(e).contains("too large")),
        }
    }
}
