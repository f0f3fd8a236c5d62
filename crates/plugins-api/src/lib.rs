//! # plugins-api: the stable contract between formsim's engine and its friction models
//!
//! Place in the pipeline: stage 5 of an explicit step (contact,
//! docs/architecture.md §3) asks, for every contact point, for a friction
//! traction. This crate owns *how that question is
//! asked*: the [`FrictionLaw`] and [`KinematicFormulation`] traits
//! (docs/friction-math.md §2–§4), the point data a component may declare it needs
//! ([`PointNeeds`], §6), parameter schemas ([`ParamSpec`]), the one shared
//! return mapping that serves every isotropic law ([`return_mapping`], §2),
//! link-time registration ([`registry`]), loading of laws from shared libraries
//! through a versioned C-ABI table ([`abi`], [`loader`]), and the conformance
//! suite every law must pass ([`conformance`], §5), and the rigid-tool contract
//! that contact queries ([`tool`]: closest point, normal, curvature, pose).
//! It also reads users' files for every crate above it ([`input_file`]:
//! regular files only, within a size limit).
//!
//! It must not know about meshes, tool geometry, scenes or any particular law: the
//! built-in laws live in `friction-laws`, which depends on this crate like any
//! plugin does. A plugin author depends on this crate alone.
//!
//! The return mapping lives here rather than in `friction-laws` so that the
//! conformance suite (and so `formsim plugin check`) drives a plugin law through
//! exactly the code the engine runs.

pub mod abi;
pub mod conformance;
pub mod curved_region;
mod dylib;
pub mod error;
pub mod formulation;
pub mod input_file;
pub mod kinematics;
pub mod law;
pub mod loader;
pub mod material;
pub mod needs;
pub mod params;
pub mod registry;
pub mod return_mapping;
mod table;
pub mod tool;

pub use curved_region::{CurvedRegion, CurvedShape, ToolRegion};
pub use dylib::{PluginKind, plugin_kind};
pub use error::FrictionError;
pub use formulation::{DirectionInputs, KinematicFormulation, StepKinematics};
pub use law::{CriticalShear, FrictionLaw, ShearInputs};
pub use needs::PointNeeds;
pub use params::{AssignmentError, ParamSpec, Params, check_values};
pub use return_mapping::{
    PairedIntegrator, PointIntegrator, PointState, StepInput, StepOutput, TangentMode,
};
pub use tool::{
    Aabb, FlatRegion, Projection, ProjectionHint, RigidPose, RigidVelocity, ToolError, ToolSurface,
};

/// Re-export so that plugin authors need no direct nalgebra dependency.
pub use nalgebra;

/// A 3-vector in the global frame (mm, MPa, … as the quantity requires).
pub type Vec3 = nalgebra::Vector3<f64>;
/// A 3×3 matrix in the global frame.
pub type Mat3 = nalgebra::Matrix3<f64>;

/// Version of the C-ABI table that dynamic plugins export. A loader refuses a
/// plugin whose table carries another version.
pub const ABI_VERSION: u32 = 1;
