//! # tools-nurbs: rigid tools for contact — exact NURBS surfaces, faceted meshes, closest-point projection, builders
//!
//! Place in the pipeline: stage 5 of an explicit step (contact) asks every
//! candidate blank node for its closest point on each tool, with the signed
//! distance, the oriented normal and the curvature tensor `K = ∇_s n`; this
//! crate answers through `plugins_api::ToolSurface`. It owns the tool
//! geometry: rational B-spline patches ([`surface`]), their differential
//! geometry ([`differential`]), multi-patch tools with a BVH and a
//! warm-started, never-failing projection ([`nurbs_tool`], [`closest_point`]),
//! faceted tools read from STL/OBJ ([`faceted`], [`mesh_io`]), exact builders
//! for the benchmark tool sets ([`builders`]), the tool kinds a scene may
//! name, each registered from its own file ([`kinds`]), the TOML tools
//! section of a scene ([`spec`]) and VTU/OBJ export ([`export`]). It must not know about
//! blanks, contact enforcement, friction or press schedules: the scheduler
//! moves a tool only through its rigid pose.
//!
//! ## Why a hand-written evaluator rather than `curvo`
//!
//! Contact projects every blank node on every tool at every explicit step,
//! warm-started: the aim is ≥ 5 M projections/s per core, i.e. a few surface
//! evaluations within ~200 ns, with no allocation. `curvo` (0.3) is a general
//! NURBS modelling library built on nalgebra's generic dimensions and
//! heap-allocated control nets and knot vectors; its evaluation allocates and
//! its closest-point search is not bounded-constrained Newton with warm start.
//! A small rational tensor-product evaluator (degree ≤ [`basis::MAX_DEGREE`])
//! is a few hundred lines, allocation-free and fast: at build time every
//! patch is split by knot insertion into its Bézier pieces (exact up to
//! rounding: the surface, its patch index and its `(u, v)` are unchanged) and
//! every piece is rewritten as a polynomial about its centre, so an
//! evaluation locates its piece and runs two short Horner schemes for the
//! point and its first and second derivatives on stack buffers, monomorphised
//! for the degrees the builders use; flat pieces with a linear
//! parametrisation (planes, straight walls) are recognised and evaluated, and
//! Newton-stepped, in closed form. The Cox–de Boor basis
//! ([`basis::basis_ders`]) stays as the reference the extraction and the
//! polynomial pieces are tested against. The exactness checks
//! (plane, cylinder, sphere, torus against closed forms to 1e-9) verify it
//! directly, so curvo is not a dependency.
//!
//! ## Orientation
//!
//! Every tool's normal points out of the tool's material towards the blank
//! side (punch: out of the punch; die: up on the face and towards the opening
//! axis on its walls; blankholder: its face normal, down when it sits above
//! the blank). `distance` is positive on that side.

pub mod basis;
pub mod builders;
pub mod bvh;
pub mod closest_point;
pub mod curved;
pub mod differential;
pub mod error;
pub mod free_edges;
pub mod nurbs_tool;
pub mod planar;
pub mod surface;

pub use error::NurbsError;
pub use nurbs_tool::{NurbsTool, OrientedPatch, TIE_TOL};
pub use surface::{Derivs, NurbsSurface, PatchDef};
pub mod export;
pub mod faceted;
pub mod faceted_edges;
pub mod kinds;
pub mod mesh_io;
pub mod spec;

pub use faceted::FacetedTool;
pub use spec::Tool;

/// Keep this crate's registrations ([`kinds`]) in a binary that names none
/// of its items otherwise; returns the number of registered tool kinds.
pub fn ensure_linked() -> usize {
    kinds::anchor()
}
