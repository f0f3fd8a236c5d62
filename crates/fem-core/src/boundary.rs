//! Boundary conditions and nodal loads: degrees of freedom, fixed DOFs, symmetry planes, prescribed motion, point loads.

use crate::Amplitude;

/// One nodal degree of freedom: a translation or a rotation about a global axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Dof {
    /// Translation along x.
    Ux = 0,
    /// Translation along y.
    Uy = 1,
    /// Translation along z.
    Uz = 2,
    /// Rotation about x.
    Rx = 3,
    /// Rotation about y.
    Ry = 4,
    /// Rotation about z.
    Rz = 5,
}

impl Dof {
    /// All six, in order.
    pub const ALL: [Dof; 6] = [Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz];

    /// 0..6 (translations 0..3, rotations 3..6).
    pub fn index(self) -> usize {
        self as usize
    }

    /// Global axis 0..3 of this translation or rotation.
    pub fn axis(self) -> usize {
        self as usize % 3
    }

    /// Whether this is a rotation.
    pub fn is_rotation(self) -> bool {
        (self as usize) >= 3
    }

    /// Name as in the docs (`ux` … `rz`).
    pub fn name(self) -> &'static str {
        ["ux", "uy", "uz", "rx", "ry", "rz"][self as usize]
    }

    /// The DOF named `name` (`ux` … `rz`, as [`Dof::name`] spells it).
    pub fn from_name(name: &str) -> Option<Dof> {
        Dof::ALL.into_iter().find(|d| d.name() == name)
    }
}

/// A set of DOFs as a bit mask (bit `Dof::index`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Dofs(pub u8);

impl Dofs {
    /// No DOF.
    pub const NONE: Dofs = Dofs(0);
    /// The three translations.
    pub const TRANSLATIONS: Dofs = Dofs(0b000111);
    /// The three rotations.
    pub const ROTATIONS: Dofs = Dofs(0b111000);
    /// All six (clamped).
    pub const ALL: Dofs = Dofs(0b111111);

    /// The mask holding exactly the given DOFs.
    pub fn of(dofs: &[Dof]) -> Dofs {
        Dofs(dofs.iter().fold(0, |m, d| m | 1 << d.index()))
    }

    /// Whether `dof` is in the set.
    pub fn contains(self, dof: Dof) -> bool {
        self.0 & (1 << dof.index()) != 0
    }

    /// Union.
    pub fn with(self, other: Dofs) -> Dofs {
        Dofs(self.0 | other.0)
    }

    /// The DOFs a symmetry plane with normal along global `axis` (0 = x)
    /// fixes: the normal translation and the two rotations about the in-plane
    /// axes. For the plane `x = const`: `ux`, `ry`, `rz`.
    pub fn symmetry(axis: usize) -> Dofs {
        let t = 1 << axis;
        let r = 0b111000 & !(1 << (3 + axis));
        Dofs(t | r)
    }
}

/// What a prescribed motion prescribes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    /// Velocity `value · A(t)` (mm/s or rad/s).
    Velocity,
    /// Displacement from the initial position `value · A(t)` (mm or rad);
    /// reached exactly at every step.
    Displacement,
}

/// A boundary condition on a node set, as given by the user (resolved by the solver).
#[derive(Debug, Clone, PartialEq)]
pub enum BoundaryCondition {
    /// Fixed DOFs (zero velocity).
    Fixed {
        /// Node set name.
        set: String,
        /// DOFs to fix.
        dofs: Dofs,
    },
    /// A symmetry plane with normal along global `axis` (0 = x, 1 = y, 2 = z):
    /// fixes the normal translation and the two in-plane rotations
    /// (plane `x = const`: `ux`, `ry`, `rz`), see [`Dofs::symmetry`].
    Symmetry {
        /// Node set name (the nodes on the plane).
        set: String,
        /// Axis of the plane's normal (0, 1 or 2).
        axis: usize,
    },
    /// Prescribed motion of one DOF of every node in the set.
    Prescribed {
        /// Node set name.
        set: String,
        /// The DOF.
        dof: Dof,
        /// Velocity or displacement.
        kind: MotionKind,
        /// Magnitude (mm, mm/s, rad or rad/s) scaled by the amplitude.
        value: f64,
        /// Time function.
        amplitude: Amplitude,
    },
}

/// A point load on every node of a set: force (N) on a translation DOF,
/// moment (N·mm) on a rotation DOF, `value · A(t)` per node, fixed global direction.
#[derive(Debug, Clone, PartialEq)]
pub struct NodalLoad {
    /// Node set name.
    pub set: String,
    /// The DOF the load acts on.
    pub dof: Dof,
    /// Force (N) or moment (N·mm) per node.
    pub value: f64,
    /// Time function.
    pub amplitude: Amplitude,
}
