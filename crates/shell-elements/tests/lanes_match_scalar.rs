//! The four-lane (SIMD) element path against the one-element path, element
//! by element and step by step.
//!
//! `ShellFormulation::compute_x4` promises each element of a block what
//! `compute` gives it. BT's lane kernel does every operation lane by lane in
//! IEEE arithmetic, in the one-element order, with branches as masks, except
//! that its `Real::madd` products are fused (one rounding) where the
//! one-element code rounds twice. So each step is started from the same
//! state both ways (the lane path's) and compared within
//! [`BT_TOL`] of each quantity's scale in the block; the formulations that
//! keep the default (element by element) must match bit for bit. Checked on
//! warped, distorted blocks driven through elastic loading, plastic flow with
//! small and large increments (the Swift series and its `powf` fallback),
//! unloading, mixed elastic/plastic lanes, a degenerate element (its state
//! must stay untouched, bit for bit), both hardening kinds, 3/4/5/7-point
//! rules and every BT option; and with the Hill'48 material, whose lanes
//! run their own return (`Hill48PlaneStress::update_points_x4`) while one
//! element runs the scalar update.

use fem_core::Vec3;
use shell_elements::material::Hill48PlaneStress;
use shell_elements::{
    BelytschkoTsay, BlockNodes, ElementBlock, ElementResult, ElementState, F4, FullyIntegrated,
    Hardening, J2PlaneStress, Material, RuleKind, Section, ShellFormulation, ThroughThickness, V3,
};

/// A small deterministic generator (xorshift64*), uniform in [-1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let r = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (r >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// Per-element state in the shell set's layout (`(ε_p, σ_y)` of each
/// point besides the material's history, for the comparison).
#[derive(Clone, PartialEq, Debug)]
struct State<H> {
    t: [f64; 4],
    stress: Vec<[f64; 3]>,
    hist: Vec<H>,
    shear: Vec<[f64; 2]>,
    hg: Vec<f64>,
    dr: [[f64; 4]; 4],
}

/// The block's state in the lane-major layout of `ElementBlock`.
fn to_lane_major<H: Clone>(s: &State<H>, np: usize, ip: usize, nhg: usize) -> State<H> {
    let mut o = s.clone();
    for l in 0..4 {
        for k in 0..np {
            for c in 0..3 {
                let i = (3 * k + c) * 4 + l;
                o.stress[i / 3][i % 3] = s.stress[l * np + k][c];
            }
        }
        for p in 0..ip {
            for c in 0..2 {
                let i = (2 * p + c) * 4 + l;
                o.shear[i / 2][i % 2] = s.shear[l * ip + p][c];
            }
        }
        for k in 0..nhg {
            o.hg[4 * k + l] = s.hg[l * nhg + k];
        }
        for i in 0..4 {
            o.dr[i][l] = s.dr[l][i];
        }
    }
    o
}

/// Back from [`to_lane_major`].
fn from_lane_major<H: Clone>(s: &State<H>, np: usize, ip: usize, nhg: usize) -> State<H> {
    let mut o = s.clone();
    for l in 0..4 {
        for k in 0..np {
            for c in 0..3 {
                let i = (3 * k + c) * 4 + l;
                o.stress[l * np + k][c] = s.stress[i / 3][i % 3];
            }
        }
        for p in 0..ip {
            for c in 0..2 {
                let i = (2 * p + c) * 4 + l;
                o.shear[l * ip + p][c] = s.shear[i / 2][i % 2];
            }
        }
        for k in 0..nhg {
            o.hg[l * nhg + k] = s.hg[4 * k + l];
        }
        for i in 0..4 {
            o.dr[l][i] = s.dr[i][l];
        }
    }
    o
}

/// Relative tolerance of the BT lane kernel against the one-element kernel
/// over one step, on each quantity's largest magnitude in the block: the
/// fused products change the last bits of single operations (measured:
/// at most 2.4e-14 here), while a lane path that ran a different
/// computation (e.g. its return mapping stopped at 1e-6 instead of
/// `RETURN_TOL`) differs by orders of magnitude more.
const BT_TOL: f64 = 1e-12;

/// The quantities of a result, grouped by scale: forces, moments, the
/// energy increments (whose sum the ledger keeps; a small hourglass or
/// drilling increment is a difference of larger terms), and the length.
fn result_groups(r: &ElementResult) -> Vec<Vec<f64>> {
    vec![
        r.f.iter().flatten().copied().collect(),
        r.m.iter().flatten().copied().collect(),
        vec![r.d_internal, r.d_drilling, r.d_hourglass, r.d_plastic],
        vec![r.length],
    ]
}

/// The quantities of a state, grouped by scale.
fn state_groups<M: Material>(mat: &M, s: &State<M::History>) -> Vec<Vec<f64>> {
    vec![
        s.t.to_vec(),
        s.stress.iter().flatten().copied().collect(),
        s.hist.iter().map(|h| mat.plastic_strain(h)).collect(),
        s.hist.iter().map(|h| mat.flow_stress(h)).collect(),
        s.shear.iter().flatten().copied().collect(),
        s.hg.clone(),
        s.dr.iter().flatten().copied().collect(),
    ]
}

/// Whether `a` and `b` agree: bit for bit (`tol = None`), or each entry
/// within `tol` times the group's largest magnitude. The largest relative
/// difference seen is kept in `worst`.
fn agree(a: &[Vec<f64>], b: &[Vec<f64>], tol: Option<f64>, worst: &mut f64) -> bool {
    a.iter().zip(b).all(|(ga, gb)| {
        let scale = ga.iter().chain(gb).fold(0.0f64, |m, x| m.max(x.abs()));
        ga.iter().zip(gb).all(|(x, y)| match tol {
            None => x.to_bits() == y.to_bits(),
            Some(t) => {
                let d = (x - y).abs();
                if scale > 0.0 {
                    *worst = worst.max(d / scale);
                }
                d <= t * scale
            }
        })
    })
}

/// Run 60 steps of one block, each step both ways from the same state, and
/// compare (see [`agree`]); returns the largest relative difference.
fn check<F: ShellFormulation, M: Material>(
    form: F,
    mat: &M,
    sec: &Section,
    seed: u64,
    degenerate: bool,
    tol: Option<f64>,
) -> f64 {
    let mut worst = 0.0f64;
    let mut rng = Rng(seed);
    let np = F::IN_PLANE_POINTS * sec.rule.n;
    let nhg = F::HOURGLASS_VARS.max(1);
    // Four warped, distorted unit-ish quads (element 2 optionally folded flat).
    let mut x = [[[0.0; 3]; 4]; 4];
    for (l, xe) in x.iter_mut().enumerate() {
        let base = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        for i in 0..4 {
            xe[i] = [
                base[i][0] + 0.15 * rng.next() + l as f64,
                base[i][1] + 0.15 * rng.next(),
                0.08 * rng.next(),
            ];
        }
    }
    if degenerate {
        // Corners 1 and 3 on top of each other: zero projected area.
        x[2][2] = x[2][0];
    }
    let init = State {
        t: [0.8, 0.78, 0.81, 0.79],
        stress: vec![[0.0; 3]; 4 * np],
        hist: vec![mat.initial_history(); 4 * np],
        shear: vec![[0.0; 2]; 4 * F::IN_PLANE_POINTS],
        hg: vec![0.0; 4 * nhg],
        dr: [[0.0; 4]; 4],
    };
    let mut a = init;
    let dt = 1e-6;
    for step in 0..60 {
        // Velocities: loading with a random pattern, growing, then unloading.
        let amp = match step {
            0..20 => 40.0,
            20..40 => 400.0,
            _ => -60.0,
        };
        let mut v = [[[0.0; 3]; 4]; 4];
        let mut w = [[[0.0; 3]; 4]; 4];
        for l in 0..4 {
            // Lane 3 stays nearly at rest (elastic beside plastic lanes).
            let s = if l == 3 { 0.01 } else { 1.0 };
            for i in 0..4 {
                v[l][i] = [
                    s * amp * (x[l][i][0] - l as f64 + 0.3 * rng.next()),
                    s * amp * (0.5 * x[l][i][1] + 0.3 * rng.next()),
                    s * amp * 0.2 * rng.next(),
                ];
                w[l][i] = [
                    s * amp * 0.5 * rng.next(),
                    s * amp * 0.5 * rng.next(),
                    s * amp * 0.3 * rng.next(),
                ];
            }
        }
        if degenerate {
            // The folded element stays folded.
            v[2] = [[0.0; 3]; 4];
        }
        // Nodal arrays: element l's node i is node 4l + i.
        let nodal = |a: &[[V3; 4]; 4]| -> Vec<Vec3> {
            (0..16)
                .map(|k| Vec3::new(a[k / 4][k % 4][0], a[k / 4][k % 4][1], a[k / 4][k % 4][2]))
                .collect()
        };
        let (xn, vn, wn) = (nodal(&x), nodal(&v), nodal(&w));
        let q = [[0, 1, 2, 3], [4, 5, 6, 7], [8, 9, 10, 11], [12, 13, 14, 15]];
        let nodes = BlockNodes::new(&xn, &vn, &wn, &q).expect("indices in range");
        // Both paths start the step from the same state.
        let mut b = a.clone();
        let mut out4 = ElementResult::<F4>::default();
        let lane_major = form.lane_major(sec);
        let mut blk = if lane_major {
            to_lane_major(&a, np, F::IN_PLANE_POINTS, nhg)
        } else {
            a.clone()
        };
        form.compute_x4(
            mat,
            sec,
            &nodes,
            dt,
            ElementBlock {
                thickness: &mut blk.t,
                stress: &mut blk.stress,
                history: &mut blk.hist,
                shear: &mut blk.shear,
                hourglass: &mut blk.hg,
                drilling: &mut blk.dr,
            },
            &mut out4,
        );
        let out_a = [0, 1, 2, 3].map(|l| out4.lane(l));
        a = if lane_major {
            from_lane_major(&blk, np, F::IN_PLANE_POINTS, nhg)
        } else {
            blk
        };
        for l in 0..4 {
            let ip = F::IN_PLANE_POINTS;
            let out_b = form.compute(
                mat,
                sec,
                &x[l],
                &v[l],
                &w[l],
                dt,
                ElementState {
                    thickness: &mut b.t[l],
                    stress: &mut b.stress[l * np..(l + 1) * np],
                    history: &mut b.hist[l * np..(l + 1) * np],
                    shear: &mut b.shear[l * ip..(l + 1) * ip],
                    hourglass: &mut b.hg[l * nhg..l * nhg + F::HOURGLASS_VARS],
                    drilling: &mut b.dr[l],
                },
            );
            assert!(
                agree(
                    &result_groups(&out_a[l]),
                    &result_groups(&out_b),
                    tol,
                    &mut worst
                ),
                "{} step {step} element {l}: results differ\n{:?}\n{:?}",
                F::NAME,
                out_a[l],
                out_b
            );
            for (k, r) in [&out_a[l], &out_b].iter().enumerate() {
                let ok = r.f.iter().chain(&r.m).flatten().all(|x| x.is_finite());
                assert!(ok, "non-finite force in path {k}");
            }
        }
        assert!(
            agree(
                &state_groups(mat, &a),
                &state_groups(mat, &b),
                tol,
                &mut worst
            ),
            "{} step {step}: states differ\n{a:?}\n{b:?}",
            F::NAME
        );
        for l in 0..4 {
            x[l] = std::array::from_fn(|i| std::array::from_fn(|c| x[l][i][c] + dt * v[l][i][c]));
        }
    }
    if degenerate {
        assert_eq!(a.t[2], 0.81, "the degenerate element's thickness changed");
        assert!(a.stress[2 * np..3 * np].iter().flatten().all(|s| *s == 0.0));
        assert!(
            a.hist[2 * np..3 * np]
                .iter()
                .all(|h| mat.plastic_strain(h) == 0.0)
        );
    }
    // Plastic flow did happen (the comparison covered the return mapping).
    assert!(
        a.hist.iter().any(|h| mat.plastic_strain(h) > 1e-3),
        "no plastic flow"
    );
    worst
}

fn swift() -> J2PlaneStress {
    J2PlaneStress::new(
        206_000.0,
        0.3,
        7.85e-9,
        Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
    )
    .unwrap()
}

fn section(rule: RuleKind, n: usize) -> Section {
    let mut s = Section::new(0.8).unwrap();
    s.rule = ThroughThickness::new(rule, n).unwrap();
    s
}

/// BT's lane kernel against its one-element kernel. Tolerance: [`BT_TOL`].
#[test]
fn bt_four_lanes_match_one_element_to_rounding() {
    let mat = swift();
    let mut worst = 0.0f64;
    for (n, seed) in [(5, 1), (3, 2), (7, 3), (4, 4)] {
        for warp in [false, true] {
            for shear_projection in [true, false] {
                let bt = BelytschkoTsay {
                    warping_correction: warp,
                    shear_projection,
                    ..Default::default()
                };
                let sec = section(RuleKind::Gauss, n);
                worst = worst.max(check(bt, &mat, &sec, seed, false, Some(BT_TOL)));
            }
        }
    }
    let lobatto = section(RuleKind::Lobatto, 5);
    let bt = BelytschkoTsay::default();
    worst = worst.max(check(bt, &mat, &lobatto, 5, false, Some(BT_TOL)));
    println!("largest relative difference: {worst:.2e}");
}

/// A degenerate element in a block keeps its state bit for bit; the others
/// match. Tolerance: [`BT_TOL`].
#[test]
fn bt_four_lanes_leave_a_degenerate_element_untouched() {
    let sec = section(RuleKind::Gauss, 5);
    check(
        BelytschkoTsay::default(),
        &swift(),
        &sec,
        6,
        true,
        Some(BT_TOL),
    );
}

/// Tabulated hardening (its lanes run the one-element return one by one).
/// Tolerance: [`BT_TOL`].
#[test]
fn bt_four_lanes_with_tabulated_hardening_match_to_rounding() {
    let table =
        Hardening::table(&[(0.0, 300.0), (0.05, 420.0), (0.2, 520.0), (1.0, 700.0)]).unwrap();
    let mat = J2PlaneStress::new(206_000.0, 0.3, 7.85e-9, table).unwrap();
    let sec = section(RuleKind::Gauss, 5);
    check(
        BelytschkoTsay::default(),
        &mat,
        &sec,
        7,
        false,
        Some(BT_TOL),
    );
}

/// Hill'48 (the square cup steel's and the aluminium's r-values, rolling
/// directions 0, 0.7 and −1.2 rad from the elements' e1, Swift and
/// tabulated hardening): BT's lane kernel, whose material update runs the
/// four-lane Hill return, against its one-element kernel, whose update is
/// the scalar return; the same warped blocks, paths and rules as J2's.
/// Tolerance: [`BT_TOL`] (the two returns agree to rounding:
/// `hill48_tests.rs`, `LANE_TOL`).
#[test]
fn bt_four_lanes_with_hill48_match_one_element_to_rounding() {
    let table =
        Hardening::table(&[(0.0, 300.0), (0.05, 420.0), (0.2, 520.0), (1.0, 700.0)]).unwrap();
    let swift = Hardening::swift(565.32, 0.007117, 0.2589).unwrap();
    let mut worst = 0.0f64;
    for (k, (hard, r, theta)) in [
        (swift.clone(), [1.79, 1.51, 2.27], 0.0),
        (swift.clone(), [1.79, 1.51, 2.27], 0.7),
        (swift, [0.71, 0.58, 0.70], -1.2),
        (table, [1.79, 1.51, 2.27], 0.7),
    ]
    .into_iter()
    .enumerate()
    {
        let mat = Hill48PlaneStress::new(206_000.0, 0.3, 7.85e-9, hard, r)
            .unwrap()
            .with_rolling_angle(theta)
            .unwrap();
        for (n, rule) in [
            (5, RuleKind::Gauss),
            (3, RuleKind::Gauss),
            (5, RuleKind::Lobatto),
        ] {
            let sec = section(rule, n);
            let seed = 11 + k as u64 * 7 + n as u64;
            let bt = BelytschkoTsay::default();
            worst = worst.max(check(bt, &mat, &sec, seed, false, Some(BT_TOL)));
        }
    }
    println!("largest relative difference: {worst:.2e}");
}

/// The default four-element path (element by element) is the one-element
/// path. Tolerance: none (bitwise).
#[test]
fn fully_integrated_default_four_element_path_matches() {
    let sec = section(RuleKind::Gauss, 5);
    check(FullyIntegrated::default(), &swift(), &sec, 8, false, None);
}

/// The shell set's accessors read the lane-major blocks right: a 3 × 3 blank
/// (two blocks of four and one element on its own, stored element-major) in a
/// uniform stretch-and-bend field must show the same stresses at every
/// element, point by point (they differ through the thickness), and the same
/// transverse shear and drilling moments (the nodes' drilling rate is uniform
/// and the field has no in-plane spin). Tolerance: 1e-9 relative.
#[test]
fn shell_set_accessors_read_lane_major_blocks() {
    use fem_core::{Effect, Forces, NodalState, StepContext, Vec3, rectangle};
    use shell_elements::ShellSet;
    let n = 3;
    let mesh = rectangle(3.0, 3.0, n, n).unwrap();
    let mut set = ShellSet::from_mesh(
        "blank",
        &mesh,
        "all",
        Section::new(0.8).unwrap(),
        BelytschkoTsay::default(),
        swift(),
    )
    .unwrap();
    let mut state = NodalState::at_rest(&mesh.nodes);
    let dt = 2e-5;
    for (i, p) in mesh.nodes.iter().enumerate() {
        // Uniform stretch, curvature and transverse shear: w = (x − 1.5)²/3
        // balances the bending rotation's share of γ_xz (the nodes stay put).
        // The field is uniform in the flat configuration, where the rates are
        // read: the step's midpoint, so its end lies ½Δt v beyond.
        state.v[i] = Vec3::new(p.x - 1.5, 0.5 * (p.y - 1.5), (p.x - 1.5).powi(2) / 3.0);
        state.w[i] = Vec3::new(0.3, -2.0 * (p.x - 1.5) / 3.0, 0.05);
        state.x[i] = p + 0.5 * dt * state.v[i];
    }
    let mut forces = Forces::zeros(mesh.nodes.len());
    let ctx = StepContext {
        time: 0.0,
        dt,
        step: 1,
        press: None,
    };
    for _ in 0..200 {
        forces.clear();
        set.add_forces(
            &ctx,
            &state,
            &mut forces,
            &mut fem_core::FieldAccess::none(),
        )
        .unwrap();
    }
    let last = set.len() - 1;
    assert_eq!(set.len(), 9);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + b.abs());
    for e in 0..set.len() {
        for k in 0..5 {
            let (s, r) = (set.stress(e, 0, k), set.stress(last, 0, k));
            assert!(
                s.iter().zip(&r).all(|(a, b)| close(*a, *b)),
                "element {e} point {k}: {s:?} vs {r:?}"
            );
        }
        let (s, r) = (set.transverse_shear(e, 0), set.transverse_shear(last, 0));
        assert!(
            s.iter().zip(&r).all(|(a, b)| close(*a, *b)),
            "shear {e}: {s:?} vs {r:?}"
        );
        assert!(close(set.thickness(e), set.thickness(last)));
        let (d, r) = (set.drilling_moments(e), set.drilling_moments(last));
        assert!(
            d.iter().zip(&r).all(|(a, b)| close(*a, *b)),
            "drilling {e}: {d:?} vs {r:?}"
        );
    }
    // The points do differ through the thickness (bending), so a mixed-up
    // index would show.
    let (bottom, top) = (set.stress(0, 0, 0), set.stress(0, 0, 4));
    assert!((bottom[0] - top[0]).abs() > 1.0, "{bottom:?} {top:?}");
}
