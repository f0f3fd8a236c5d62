//! The shells' shared nodal fields: a plate stretched into plasticity thins
//! every step, and an effect reading the nodal thickness and outer-fibre
//! flow stress reads, in each step, the element values of that same step
//! averaged to the nodes (sum over the elements around the node times the
//! inverse valence), bit for bit. Without a flow-stress reader the shells
//! do not compute it.

use fem_core::{
    Control, Dof, Dofs, Effect, FemError, FieldAccess, Forces, MotionKind, NodalField, NodalState,
    Solver, SolverSettings, StepContext, rectangle,
};
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, Section, ShellSet};

type Shells = ShellSet<BelytschkoTsay, J2PlaneStress>;

/// Records the fields it reads, per call: (thickness, top, bottom), empty when absent.
struct Reader {
    reads: &'static [NodalField],
    seen: Vec<[Vec<f64>; 3]>,
}

impl Effect for Reader {
    fn name(&self) -> &str {
        "reader"
    }
    fn reads(&self) -> &[NodalField] {
        self.reads
    }
    fn add_forces(
        &mut self,
        _ctx: &StepContext,
        _state: &NodalState,
        _forces: &mut Forces,
        fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        let get = |f| fields.read(f).map_or(Vec::new(), <[f64]>::to_vec);
        self.seen.push([
            get(NodalField::THICKNESS),
            get(NodalField::FLOW_STRESS_TOP),
            get(NodalField::FLOW_STRESS_BOTTOM),
        ]);
        Ok(())
    }
}

/// A 3 × 2 plate (valences 1, 2 and 4), left edge held in x, right edge
/// pulled at 2 m/s, with `reader` added before the shells.
fn stretched_plate(
    reads: &'static [NodalField],
) -> (Solver, fem_core::EffectId, fem_core::EffectId) {
    let mesh = rectangle(30.0, 20.0, 3, 2).unwrap();
    let settings = SolverSettings {
        mass_scaling_dt: Some(2e-7),
        ..SolverSettings::default()
    };
    let mut solver = Solver::new(&mesh, settings).unwrap();
    let reader = solver.add_effect(Reader {
        reads,
        seen: Vec::new(),
    });
    let steel = J2PlaneStress::new(
        2.06e5,
        0.3,
        7.85e-9,
        Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
    )
    .unwrap();
    let section = Section::new(1.0).unwrap();
    let shells = solver.add_effect(
        ShellSet::new(
            "plate",
            &mesh.nodes,
            &mesh.quads,
            section,
            BelytschkoTsay::default(),
            steel,
        )
        .unwrap(),
    );
    solver.fix("x0", Dofs::of(&[Dof::Ux])).unwrap();
    solver.fix("y0", Dofs::of(&[Dof::Uy])).unwrap();
    solver
        .fix("all", Dofs::of(&[Dof::Uz, Dof::Rx, Dof::Ry]))
        .unwrap();
    solver
        .prescribe(
            "x1",
            Dof::Ux,
            MotionKind::Velocity,
            2e3,
            fem_core::Amplitude::Constant,
        )
        .unwrap();
    (solver, reader, shells)
}

/// `Σ_e∋n value(e) × (1 / valence(n))`, in element order.
fn nodal_mean(shells: &Shells, nodes: usize, value: impl Fn(usize) -> f64) -> Vec<f64> {
    let mut sum = vec![0.0; nodes];
    let mut valence = vec![0usize; nodes];
    for (e, q) in shells.quads().iter().enumerate() {
        for &n in q {
            sum[n as usize] += value(e);
            valence[n as usize] += 1;
        }
    }
    sum.iter()
        .zip(&valence)
        .map(|(s, &v)| s * (1.0 / v as f64))
        .collect()
}

#[test]
fn reader_sees_this_steps_nodal_thickness_and_flow_stress() {
    let all = &[
        NodalField::THICKNESS,
        NodalField::FLOW_STRESS_TOP,
        NodalField::FLOW_STRESS_BOTTOM,
    ];
    let (mut solver, reader, shells) = stretched_plate(all);
    solver.initialize().unwrap();
    assert_eq!(solver.effect_order(), &[1, 0], "the shells run first");
    let nodes = solver.state().len();
    let mut previous: Option<Vec<f64>> = None;
    let mut changed = 0;
    solver
        .run_until(2e-4, &mut |s: &Solver, _| {
            let sh: &Shells = s.effect(shells).unwrap();
            let [t, top, bottom] = s
                .effect::<Reader>(reader)
                .unwrap()
                .seen
                .last()
                .unwrap()
                .clone();
            assert_eq!(t, nodal_mean(sh, nodes, |e| sh.thickness(e)));
            assert_eq!(top, nodal_mean(sh, nodes, |e| sh.outer_flow_stress(e)[1]));
            assert_eq!(
                bottom,
                nodal_mean(sh, nodes, |e| sh.outer_flow_stress(e)[0])
            );
            assert_eq!(s.field(NodalField::THICKNESS), Some(&t[..]));
            if previous.as_ref().is_some_and(|p| *p != t) {
                changed += 1;
            }
            previous = Some(t);
            Control::Continue
        })
        .unwrap();
    let steps = solver.steps();
    assert!(
        changed + 1 >= steps as usize,
        "thickness changed in {changed} of {steps} steps"
    );
    let sh: &Shells = solver.effect(shells).unwrap();
    assert!(
        sh.thickness(0) < 0.995,
        "the plate thins: {}",
        sh.thickness(0)
    );
    assert!(
        sh.outer_flow_stress(0)[1] > 170.0,
        "and hardens (initial yield 157 MPa): {:?}",
        sh.outer_flow_stress(0)
    );
}

/// Only the thickness is read: the flow-stress fields are not allocated and
/// the reader sees none.
#[test]
fn flow_stress_is_not_computed_without_a_reader() {
    let (mut solver, reader, _) = stretched_plate(&[NodalField::THICKNESS]);
    solver
        .run_until(2e-6, &mut |_, _| Control::Continue)
        .unwrap();
    assert!(solver.field(NodalField::FLOW_STRESS_TOP).is_none());
    assert!(solver.field(NodalField::FLOW_STRESS_BOTTOM).is_none());
    let seen = &solver.effect::<Reader>(reader).unwrap().seen;
    assert!(
        seen.iter()
            .all(|[t, top, bottom]| !t.is_empty() && top.is_empty() && bottom.is_empty())
    );
}
