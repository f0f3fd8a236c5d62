//! Patch test of a 3D spring lattice under a large affine deformation: the
//! largest static model of the suite, with the solver's time split.

use fem_core::statics::{NewtonSettings, StaticProblem, StaticSolver};
use fem_core::{Dof, Mat3, Spring, Springs, Vec3};

/// Nodes per edge of the cube lattice.
const N: usize = 18;
/// Lattice spacing (mm).
const SPACING: f64 = 5.0;

/// The 13 half-directions of a node's 26 neighbours (axes, face and body
/// diagonals), each with its spring stiffness (N/mm).
const DIRECTIONS: [([i64; 3], f64); 13] = [
    ([1, 0, 0], 100.0),
    ([0, 1, 0], 100.0),
    ([0, 0, 1], 100.0),
    ([1, 1, 0], 40.0),
    ([1, -1, 0], 40.0),
    ([1, 0, 1], 40.0),
    ([1, 0, -1], 40.0),
    ([0, 1, 1], 40.0),
    ([0, 1, -1], 40.0),
    ([1, 1, 1], 25.0),
    ([1, 1, -1], 25.0),
    ([1, -1, 1], 25.0),
    ([1, -1, -1], 25.0),
];

fn id(i: usize, j: usize, k: usize) -> u32 {
    ((i * N + j) * N + k) as u32
}

/// An `N³` cube lattice, every node tied to its 26 neighbours by springs
/// free at the start.
fn lattice() -> (Vec<Vec3>, Vec<Spring>) {
    let mut nodes = Vec::with_capacity(N * N * N);
    let mut springs = Vec::new();
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                nodes.push(Vec3::new(i as f64, j as f64, k as f64) * SPACING);
                for (d, stiffness) in DIRECTIONS {
                    let to = [i as i64 + d[0], j as i64 + d[1], k as i64 + d[2]];
                    if to.iter().all(|&c| (0..N as i64).contains(&c)) {
                        let length =
                            SPACING * ((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) as f64).sqrt();
                        springs.push(Spring {
                            a: id(i, j, k),
                            b: id(to[0] as usize, to[1] as usize, to[2] as usize),
                            k: stiffness,
                            length0: length,
                        });
                    }
                }
            }
        }
    }
    (nodes, springs)
}

/// The deformation gradient: 25 % stretch, 10 % compression, shear.
fn deformation() -> Mat3 {
    Mat3::new(1.25, 0.10, 0.0, -0.05, 0.90, 0.08, 0.0, 0.06, 1.10)
}

/// Patch test: every boundary node of an 18³ lattice (5832 nodes, 59 177
/// springs) is moved by the affine map `x = F X` (25 % stretch, 10 %
/// compression and shears), the 4096 interior nodes are free (12 288
/// equations; rotations dropped). Every interior node's neighbourhood is
/// centrally symmetric, so the affine field is an exact equilibrium of the
/// geometrically nonlinear springs (opposite springs carry opposite
/// forces). Reference: that symmetry argument (the discrete patch test).
/// Tolerances: interior positions `|x − F X| <= 1e-9 · spacing`, and the
/// reactions on the boundary in global balance to 1e-9 of their sum of
/// magnitudes (no external load). Prints the time split and the factor's size.
#[test]
fn spring_lattice_under_affine_boundary_motion_stays_affine() {
    let (nodes, springs) = lattice();
    let f = deformation();
    let mut p = StaticProblem::new(&nodes).unwrap();
    p.add_effect(Springs::new("lattice", nodes.len(), springs).unwrap());
    let on_boundary = |c: usize| c == 0 || c == N - 1;
    let mut boundary = Vec::new();
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                if on_boundary(i) || on_boundary(j) || on_boundary(k) {
                    let n = id(i, j, k);
                    let u = (f - Mat3::identity()) * nodes[n as usize];
                    for (dof, value) in [Dof::Ux, Dof::Uy, Dof::Uz].into_iter().zip(u.iter()) {
                        p.prescribe(&[n], dof, *value).unwrap();
                    }
                    boundary.push(n as usize);
                }
            }
        }
    }
    let settings = NewtonSettings {
        initial_increment: 0.25,
        ..Default::default()
    };
    let mut solver = StaticSolver::new(p, settings).unwrap();
    let report = solver.solve().unwrap();
    print!("{report}");
    let worst = (0..nodes.len())
        .map(|n| (solver.positions()[n] - f * nodes[n]).norm())
        .fold(0.0f64, f64::max);
    let (mut sum, mut magnitude) = (Vec3::zeros(), 0.0);
    for &n in &boundary {
        let r = Vec3::new(
            solver.reaction(n, Dof::Ux),
            solver.reaction(n, Dof::Uy),
            solver.reaction(n, Dof::Uz),
        );
        sum += r;
        magnitude += r.norm();
    }
    println!(
        "max |x − F X| = {worst:.3e} mm; |Σ reactions| / Σ |reactions| = {:.3e} (Σ |R| = {magnitude:.3e} N)",
        sum.norm() / magnitude
    );
    assert_eq!(report.system.equations, 3 * (N - 2).pow(3));
    assert!(worst <= 1e-9 * SPACING, "max |x − F X| = {worst:e}");
    assert!(sum.norm() <= 1e-9 * magnitude);
}
