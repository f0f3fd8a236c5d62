//! Shared nodal fields through the solver: a reader added before its writer
//! still runs after it and reads, in every step, the value written in that
//! same step; a field nobody reads is not computed; cycles are refused.

use fem_core::{
    Control, Effect, FemError, FieldAccess, Forces, NodalField, NodalState, Solver, SolverSettings,
    StepContext, Vec3,
};
use std::collections::BTreeMap;

const STAMP: NodalField = NodalField::new("stamp", "-");
const OTHER: NodalField = NodalField::new("other", "-");

/// Writes `STAMP = time` at every node (when read), and counts the writes.
struct Writer {
    writes: &'static [NodalField],
    reads: &'static [NodalField],
    written: u64,
}

impl Effect for Writer {
    fn name(&self) -> &str {
        "writer"
    }
    fn writes(&self) -> &[NodalField] {
        self.writes
    }
    fn reads(&self) -> &[NodalField] {
        self.reads
    }
    fn add_forces(
        &mut self,
        ctx: &StepContext,
        _state: &NodalState,
        _forces: &mut Forces,
        fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        if let Some(v) = fields.write(STAMP) {
            v.iter_mut().for_each(|x| *x = ctx.time);
            self.written += 1;
        }
        Ok(())
    }
}

/// Records, per call, the time and the `STAMP` it read (NaN when absent).
struct Reader {
    writes: &'static [NodalField],
    seen: Vec<(f64, f64)>,
}

impl Effect for Reader {
    fn name(&self) -> &str {
        "reader"
    }
    fn writes(&self) -> &[NodalField] {
        self.writes
    }
    fn reads(&self) -> &[NodalField] {
        &[STAMP]
    }
    fn add_forces(
        &mut self,
        ctx: &StepContext,
        _state: &NodalState,
        _forces: &mut Forces,
        fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        let v = fields.read(STAMP).map_or(f64::NAN, |v| v[1]);
        self.seen.push((ctx.time, v));
        Ok(())
    }
}

fn solver() -> Solver {
    let nodes = [Vec3::zeros(), Vec3::x()];
    let settings = SolverSettings {
        dt_max: Some(1e-3),
        ..Default::default()
    };
    Solver::from_nodes(&nodes, BTreeMap::new(), settings).unwrap()
}

fn writer(reads: &'static [NodalField]) -> Writer {
    Writer {
        writes: &[STAMP],
        reads,
        written: 0,
    }
}

/// The reader is added first, yet runs after the writer and reads, at every
/// force computation (the initial one included), the stamp of that same
/// time: no one-step lag (exact comparison).
#[test]
fn reader_added_first_reads_the_value_written_in_the_same_step() {
    let mut s = solver();
    let r = s.add_effect(Reader {
        writes: &[],
        seen: Vec::new(),
    });
    let w = s.add_effect(writer(&[]));
    s.initialize().unwrap();
    assert_eq!(s.effect_order(), &[1, 0]);
    s.run_until(5e-3, &mut |_, _| Control::Continue).unwrap();
    let seen = &s.effect::<Reader>(r).unwrap().seen;
    assert_eq!(seen.len(), 6);
    for &(time, stamp) in seen {
        assert_eq!(stamp, time);
    }
    assert_eq!(s.effect::<Writer>(w).unwrap().written, 6);
    assert_eq!(s.field(STAMP).unwrap(), &[5e-3, 5e-3]);
}

/// Without a reader the field is not allocated and the writer never
/// computes it; without a writer the reader reads nothing.
#[test]
fn a_field_nobody_reads_is_not_computed() {
    let mut s = solver();
    let w = s.add_effect(writer(&[]));
    s.run_until(3e-3, &mut |_, _| Control::Continue).unwrap();
    assert_eq!(s.effect::<Writer>(w).unwrap().written, 0);
    assert!(s.field(STAMP).is_none());

    let mut s = solver();
    let r = s.add_effect(Reader {
        writes: &[],
        seen: Vec::new(),
    });
    s.run_until(1e-3, &mut |_, _| Control::Continue).unwrap();
    assert!(s.effect::<Reader>(r).unwrap().seen[1].1.is_nan());
}

/// Two effects each reading what the other writes: set-up fails, naming both.
#[test]
fn a_cycle_of_fields_is_refused_at_set_up() {
    let mut s = solver();
    s.add_effect(writer(&[OTHER]));
    s.add_effect(Reader {
        writes: &[OTHER],
        seen: Vec::new(),
    });
    let msg = s.initialize().unwrap_err().to_string();
    assert!(msg.contains("cycle"), "{msg}");
    assert!(
        msg.contains("`writer` reads `other` (-) written by `reader`"),
        "{msg}"
    );
    assert!(
        msg.contains("`reader` reads `stamp` (-) written by `writer`"),
        "{msg}"
    );
}
