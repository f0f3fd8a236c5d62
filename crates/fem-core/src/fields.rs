//! Nodal fields shared between effects: one effect writes a field, others
//! read it in the same step.
//!
//! An effect declares the fields it writes ([`Effect::writes`]) and those it
//! reads ([`Effect::reads`]). At set-up ([`Solver::initialize`]) the solver
//! allocates one value per node (an `f64`, or a [`Vec3`] for a vector field)
//! for each field that has both a writer and a reader, and orders the effects so that every writer runs before its
//! readers within a step (see [`effect_order`]). During the step each effect
//! sees the fields through its own [`FieldAccess`]: it may write only what it
//! declared it writes and read only what it declared it reads.
//!
//! A field nobody reads is not allocated, and its writer's
//! [`FieldAccess::write`] returns `None`: the writer skips computing it. A
//! field nobody writes is not allocated either: its readers'
//! [`FieldAccess::read`] returns `None` and they fall back on their own
//! values (contact keeps the blank's initial thickness, say).
//!
//! [`Effect::writes`]: crate::Effect::writes
//! [`Effect::reads`]: crate::Effect::reads
//! [`Solver::initialize`]: crate::Solver::initialize

use crate::{FemError, Vec3};

/// The key of a nodal field shared between effects: a name, a unit and
/// whether each node holds a scalar (`f64`) or a vector ([`Vec3`]).
///
/// Two keys are the same field when their names are equal; keys of the same
/// name with different units or kinds are refused at set-up. The fields
/// formsim's effects share are the associated constants; an effect may
/// define its own with [`NodalField::new`] or [`NodalField::vector`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodalField {
    name: &'static str,
    unit: &'static str,
    vector: bool,
}

impl NodalField {
    /// Current shell thickness at the node (mm): the mean of the thicknesses
    /// of the elements around it. Written by the blank's shells, read by contact.
    pub const THICKNESS: NodalField = NodalField::new("thickness", "mm");
    /// Flow stress of the top fibre (side of the shell normal) at the node
    /// (MPa), the mean over the elements around it. Written by the shells
    /// when read; read by contact when a friction law needs the flow stress.
    pub const FLOW_STRESS_TOP: NodalField = NodalField::new("flow-stress-top", "MPa");
    /// Flow stress of the bottom fibre at the node (MPa); as
    /// [`NodalField::FLOW_STRESS_TOP`].
    pub const FLOW_STRESS_BOTTOM: NodalField = NodalField::new("flow-stress-bottom", "MPa");
    /// Tributary area of the node (mm²): a quarter of the (projected) areas
    /// of the shells around it. Written by the blank's shells from the
    /// element frames they build anyway; read by contact, which then does not
    /// compute the blank's quad geometry a second time.
    pub const AREA: NodalField = NodalField::new("area", "mm2");
    /// The nodal normal as the area-weighted sum of the unit normals of the
    /// shells around the node, `Σ A_e n_e` (a vector, mm²; its direction is
    /// the nodal normal, its length is not used). Written and read with
    /// [`NodalField::AREA`].
    pub const NORMAL: NodalField = NodalField::vector("normal", "mm2");

    /// A scalar field named `name` (kebab-case, unique) in `unit`.
    pub const fn new(name: &'static str, unit: &'static str) -> Self {
        Self {
            name,
            unit,
            vector: false,
        }
    }

    /// A vector field ([`Vec3`] per node) named `name` in `unit`.
    pub const fn vector(name: &'static str, unit: &'static str) -> Self {
        Self {
            name,
            unit,
            vector: true,
        }
    }

    /// Whether each node holds a vector ([`Vec3`]) rather than a scalar.
    pub fn is_vector(&self) -> bool {
        self.vector
    }

    /// The field's name.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// The field's unit.
    pub fn unit(&self) -> &'static str {
        self.unit
    }
}

impl std::fmt::Display for NodalField {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "`{}` ({})", self.name, self.unit)
    }
}

/// One allocated field: its key, the index of its writer, the indices of its
/// readers and its nodal values (`scalars` for a scalar field, `vectors`
/// for a vector field; the other is empty).
#[derive(Debug, Clone, PartialEq)]
struct Slot {
    field: NodalField,
    writer: usize,
    readers: Vec<usize>,
    scalars: Vec<f64>,
    vectors: Vec<Vec3>,
}

/// The shared nodal fields of a solver: those with a writer and a reader.
///
/// Built once at set-up by [`SharedFields::new`]; the step loop only hands
/// out views ([`SharedFields::access`]) and never allocates.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SharedFields {
    slots: Vec<Slot>,
}

/// What each effect declares: its name, the fields it writes and those it reads.
#[derive(Debug, Clone, Copy)]
pub struct Declared<'a> {
    /// The effect's name (for messages).
    pub name: &'a str,
    /// Fields it writes.
    pub writes: &'a [NodalField],
    /// Fields it reads.
    pub reads: &'a [NodalField],
}

impl SharedFields {
    /// Fields over `nodes` nodes for the effects `declared` (indexed as the
    /// solver's effects): one zeroed `Vec` per field written by one effect
    /// and read by another.
    ///
    /// # Errors
    /// A field written by two effects; one name with two units.
    pub fn new(nodes: usize, declared: &[Declared<'_>]) -> Result<Self, FemError> {
        check_units(declared)?;
        let mut slots: Vec<Slot> = Vec::new();
        for (w, d) in declared.iter().enumerate() {
            for &field in d.writes {
                if let Some(other) = writer_of(declared, field, w) {
                    return Err(FemError::InvalidSetup(format!(
                        "field {field} is written by two effects, `{}` and `{}`",
                        declared[other].name, d.name
                    )));
                }
                let readers: Vec<usize> = (0..declared.len())
                    .filter(|&r| r != w && reads(&declared[r], field))
                    .collect();
                if !readers.is_empty() {
                    let (n_scalar, n_vector) = if field.vector { (0, nodes) } else { (nodes, 0) };
                    slots.push(Slot {
                        field,
                        writer: w,
                        readers,
                        scalars: vec![0.0; n_scalar],
                        vectors: vec![Vec3::zeros(); n_vector],
                    });
                }
            }
        }
        Ok(Self { slots })
    }

    /// The view of effect `effect` (its index in the solver).
    pub fn access(&mut self, effect: usize) -> FieldAccess<'_> {
        FieldAccess {
            slots: &mut self.slots,
            effect,
        }
    }

    /// The values of the scalar `field` (`None` when it is not allocated:
    /// no writer or no reader).
    pub fn get(&self, field: NodalField) -> Option<&[f64]> {
        self.slots
            .iter()
            .find(|s| s.field.name == field.name && !s.field.vector)
            .map(|s| s.scalars.as_slice())
    }

    /// The values of the vector `field`, as [`SharedFields::get`].
    pub fn get_vec3(&self, field: NodalField) -> Option<&[Vec3]> {
        self.slots
            .iter()
            .find(|s| s.field.name == field.name && s.field.vector)
            .map(|s| s.vectors.as_slice())
    }

    /// The allocated fields, in order of their writers.
    pub fn fields(&self) -> impl Iterator<Item = NodalField> + '_ {
        self.slots.iter().map(|s| s.field)
    }
}

fn reads(d: &Declared<'_>, field: NodalField) -> bool {
    d.reads.iter().any(|f| f.name == field.name)
}

fn writes(d: &Declared<'_>, field: NodalField) -> bool {
    d.writes.iter().any(|f| f.name == field.name)
}

/// Another effect than `but` that writes `field`.
fn writer_of(declared: &[Declared<'_>], field: NodalField, but: usize) -> Option<usize> {
    (0..but).find(|&k| writes(&declared[k], field))
}

/// Refuse one field name declared with two units, or as a scalar and a vector.
fn check_units(declared: &[Declared<'_>]) -> Result<(), FemError> {
    let all = || declared.iter().flat_map(|d| d.writes.iter().chain(d.reads));
    for a in all() {
        if let Some(b) = all().find(|b| b.name == a.name && b.unit != a.unit) {
            return Err(FemError::InvalidSetup(format!(
                "field `{}` is declared in two units, {} and {}",
                a.name, a.unit, b.unit
            )));
        }
        if all().any(|b| b.name == a.name && b.vector != a.vector) {
            return Err(FemError::InvalidSetup(format!(
                "field `{}` is declared both as a scalar and as a vector",
                a.name
            )));
        }
    }
    Ok(())
}

/// The order in which the solver calls the effects' `add_forces`: every
/// writer of a field before its readers, otherwise the order of addition
/// (of the effects ready to run, the one added first runs first).
///
/// # Errors
/// Effects whose fields depend on each other in a cycle, named with the
/// fields that close it.
pub fn effect_order(declared: &[Declared<'_>]) -> Result<Vec<usize>, FemError> {
    let n = declared.len();
    let feeds =
        |w: usize, r: usize| w != r && declared[w].writes.iter().any(|&f| reads(&declared[r], f));
    let mut order = Vec::with_capacity(n);
    let mut placed = vec![false; n];
    while order.len() < n {
        let ready = (0..n).find(|&r| !placed[r] && (0..n).all(|w| placed[w] || !feeds(w, r)));
        match ready {
            Some(r) => {
                placed[r] = true;
                order.push(r);
            }
            None => return Err(cycle_error(declared, &placed)),
        }
    }
    Ok(order)
}

/// The error for the effects not yet placed: each waits on a field written by another.
fn cycle_error(declared: &[Declared<'_>], placed: &[bool]) -> FemError {
    let mut waits = Vec::new();
    for (r, d) in declared.iter().enumerate().filter(|(r, _)| !placed[*r]) {
        for (w, dw) in declared.iter().enumerate() {
            if w == r || placed[w] {
                continue;
            }
            for &f in dw.writes.iter().filter(|&&f| reads(d, f)) {
                waits.push(format!("`{}` reads {f} written by `{}`", d.name, dw.name));
            }
        }
    }
    FemError::InvalidSetup(format!(
        "the effects share fields in a cycle, so no order runs every writer before its readers: {}",
        waits.join("; ")
    ))
}

/// What [`FieldAccess::write_each`] hands out: the scalar fields' values,
/// then the vector fields', each `None` when not written or not read.
pub type Writable<'a, const N: usize, const M: usize> =
    ([Option<&'a mut [f64]>; N], [Option<&'a mut [Vec3]>; M]);

/// One effect's view of the shared fields during a step.
///
/// Built by the solver for each effect ([`SharedFields::access`]); an effect
/// called outside a solver (a test, a benchmark) can use [`FieldAccess::none`].
#[derive(Debug)]
pub struct FieldAccess<'a> {
    slots: &'a mut [Slot],
    effect: usize,
}

impl FieldAccess<'static> {
    /// A view of no fields: every read and write returns `None`.
    pub fn none() -> Self {
        FieldAccess {
            slots: &mut [],
            effect: usize::MAX,
        }
    }
}

impl FieldAccess<'_> {
    /// Whether another effect reads `field`, which this effect writes: if
    /// not, the writer need not compute it.
    pub fn is_read(&self, field: NodalField) -> bool {
        self.slots
            .iter()
            .any(|s| s.writer == self.effect && s.field.name == field.name)
    }

    /// The values of the scalar `field` to write (one per node), when this
    /// effect declared it writes it and another effect reads it; `None`
    /// otherwise.
    pub fn write(&mut self, field: NodalField) -> Option<&mut [f64]> {
        let ([values], []) = self.write_each([field], []);
        values
    }

    /// [`FieldAccess::write`] for several scalar fields and vector fields at
    /// once (distinct names): the scalars' values, then the vectors'.
    pub fn write_each<const N: usize, const M: usize>(
        &mut self,
        scalars: [NodalField; N],
        vectors: [NodalField; M],
    ) -> Writable<'_, N, M> {
        let mut out_s = [const { None }; N];
        let mut out_v = [const { None }; M];
        for slot in self.slots.iter_mut().filter(|s| s.writer == self.effect) {
            let name = slot.field.name;
            if slot.field.vector {
                if let Some(k) = vectors.iter().position(|f| f.name == name) {
                    out_v[k] = Some(slot.vectors.as_mut_slice());
                }
            } else if let Some(k) = scalars.iter().position(|f| f.name == name) {
                out_s[k] = Some(slot.scalars.as_mut_slice());
            }
        }
        (out_s, out_v)
    }

    /// The slot of `field` this effect reads, if allocated.
    fn readable(&self, field: NodalField) -> Option<&Slot> {
        self.slots
            .iter()
            .find(|s| s.field.name == field.name && s.readers.contains(&self.effect))
    }

    /// The values of the scalar `field` (one per node) as its writer left
    /// them in this step, when this effect declared it reads it and another
    /// effect writes it; `None` otherwise.
    pub fn read(&self, field: NodalField) -> Option<&[f64]> {
        self.readable(field)
            .filter(|s| !s.field.vector)
            .map(|s| s.scalars.as_slice())
    }

    /// The values of the vector `field`, as [`FieldAccess::read`].
    pub fn read_vec3(&self, field: NodalField) -> Option<&[Vec3]> {
        self.readable(field)
            .filter(|s| s.field.vector)
            .map(|s| s.vectors.as_slice())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: NodalField = NodalField::new("a", "mm");
    const B: NodalField = NodalField::new("b", "MPa");

    fn d<'a>(name: &'a str, writes: &'a [NodalField], reads: &'a [NodalField]) -> Declared<'a> {
        Declared {
            name,
            writes,
            reads,
        }
    }

    /// Readers added before their writer run after it; the rest keep their
    /// order of addition.
    #[test]
    fn writers_run_before_readers_else_order_of_addition() {
        let e = [d("r", &[], &[A]), d("x", &[], &[]), d("w", &[A], &[])];
        assert_eq!(effect_order(&e).unwrap(), vec![1, 2, 0]);
        let e = [d("w", &[A], &[]), d("x", &[], &[]), d("r", &[], &[A])];
        assert_eq!(effect_order(&e).unwrap(), vec![0, 1, 2]);
    }

    #[test]
    fn a_cycle_is_refused_naming_effects_and_fields() {
        let e = [d("p", &[A], &[B]), d("q", &[B], &[A]), d("x", &[], &[])];
        let msg = effect_order(&e).unwrap_err().to_string();
        assert!(msg.contains("cycle"), "{msg}");
        assert!(msg.contains("`p` reads `b` (MPa) written by `q`"), "{msg}");
        assert!(msg.contains("`q` reads `a` (mm) written by `p`"), "{msg}");
    }

    #[test]
    fn two_writers_or_two_units_are_refused() {
        let e = [d("p", &[A], &[]), d("q", &[A], &[])];
        let msg = SharedFields::new(3, &e).unwrap_err().to_string();
        assert!(msg.contains("written by two effects, `p` and `q`"), "{msg}");
        let a_in_m = [NodalField::new("a", "m")];
        let e = [d("p", &[A], &[]), d("q", &[], &a_in_m)];
        let msg = SharedFields::new(3, &e).unwrap_err().to_string();
        assert!(msg.contains("two units"), "{msg}");
    }

    /// Only a field with a writer and a reader is allocated; each effect
    /// writes and reads only what it declared.
    #[test]
    fn only_fields_written_and_read_are_allocated_and_views_follow_declarations() {
        let e = [d("w", &[A, B], &[]), d("r", &[], &[A]), d("x", &[], &[])];
        let mut f = SharedFields::new(2, &e).unwrap();
        assert_eq!(f.fields().collect::<Vec<_>>(), vec![A]);
        {
            let mut w = f.access(0);
            assert!(w.is_read(A) && !w.is_read(B));
            assert!(w.write(B).is_none());
            w.write(A).unwrap().copy_from_slice(&[1.0, 2.0]);
            assert!(w.read(A).is_none(), "the writer did not declare it reads");
        }
        assert_eq!(f.access(1).read(A), Some(&[1.0, 2.0][..]));
        assert!(f.access(1).write(A).is_none());
        assert!(f.access(2).read(A).is_none());
        assert_eq!(f.get(A), Some(&[1.0, 2.0][..]));
        assert!(FieldAccess::none().read(A).is_none());
    }

    /// A vector field holds a `Vec3` per node, written and read as vectors
    /// only; one name cannot be a scalar for one effect and a vector for another.
    #[test]
    fn vector_fields_hold_vectors_and_kinds_must_agree() {
        const V: NodalField = NodalField::vector("v", "mm");
        let e = [d("w", &[A], &[]), d("r", &[], &[A])];
        let _ = SharedFields::new(1, &e).unwrap();
        let e = [d("w", &[A, V], &[]), d("r", &[], &[V, A])];
        let mut f = SharedFields::new(2, &e).unwrap();
        {
            let mut w = f.access(0);
            let ([a], [v]) = w.write_each([A], [V]);
            a.unwrap().fill(3.0);
            v.unwrap()[1] = Vec3::new(1.0, 2.0, 3.0);
        }
        let r = f.access(1);
        assert_eq!(r.read_vec3(V).unwrap()[1], Vec3::new(1.0, 2.0, 3.0));
        assert!(r.read(V).is_none(), "a vector field is not read as scalars");
        assert!(r.read_vec3(A).is_none());
        assert_eq!(r.read(A), Some(&[3.0, 3.0][..]));
        let v_scalar = [NodalField::new("v", "mm")];
        let e = [d("w", &[V], &[]), d("r", &[], &v_scalar)];
        let msg = SharedFields::new(2, &e).unwrap_err().to_string();
        assert!(msg.contains("both as a scalar and as a vector"), "{msg}");
    }
}
