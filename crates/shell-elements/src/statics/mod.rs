//! Belytschko–Tsay and fully integrated shells for the static Newton
//! solver ([`fem_core::statics`]): [`StaticShells`], internal forces at a
//! trial state from the committed state, and their exact consistent
//! tangent.
//!
//! # Formulation: one explicit step from the committed state
//!
//! Each element keeps, committed, its thickness, the stress and history
//! of every integration point (in its co-rotational frame; one in-plane
//! point for Belytschko–Tsay, the 2×2 Gauss points of the fully integrated
//! shell, each with its through-thickness stack), its transverse shear
//! stresses (per in-plane point), hourglass generalised forces
//! (Belytschko–Tsay only) and drilling moments; the committed geometry is
//! the solver's committed positions
//! ([`TrialState::x_committed`](fem_core::statics::TrialState)). At a trial
//! state (positions `x`, rotation vectors `Δθ` since the commit) the
//! element runs its explicit kernel
//! ([`BelytschkoTsay`](crate::BelytschkoTsay) or
//! [`FullyIntegrated`](crate::FullyIntegrated)) as one step of length 1
//! whose "velocities" are the increments `Δx = x − x_committed` and `Δθ`:
//!
//! - the strain increments (membrane from the in-plane translation
//!   increments, curvature from the rotation increments, with the warping
//!   correction when on; Bathe–Dvorkin transverse shear) are read in the
//!   **midpoint configuration** `½ (x_committed + x)`, in its
//!   co-rotational frame (`corotational_basis`), and turned into the trial
//!   configuration's frame (Hughes–Winget: the increments of a rigid
//!   rotation of any size are zero); Belytschko–Tsay reads them at the
//!   centre, the fully integrated shell at each of its 2×2 Gauss points
//!   (exact bilinear B, the warped element's rigid rotation removed);
//! - every through-thickness point is updated by [`Material::update`]
//!   from its committed stress and history (the section's rule, committed
//!   thickness), giving `N` and `M` (per Gauss point for the fully
//!   integrated shell);
//! - transverse shear (elastic, shear correction factor of the section),
//!   hourglass control of Belytschko–Tsay (`Q = Q_committed + C q(Δ)`, the
//!   explicit element's stiffness-type control with its coefficients
//!   `r E t A ΣB²/8`, …; the fully integrated shell has none) and the
//!   relative drilling penalty (`k = γ G t A / 4` per node) are
//!   incremental from their committed values;
//! - the nodal forces and moments are the explicit element's, with the
//!   trial configuration's frame and B-matrices.
//!
//! So the static element follows the explicit one exactly, step for step:
//! same frame, same increments, same stress update, same resultants,
//! same nodal forces; the explicit element's hourglass control is already
//! stiffness-type (incremental in the hourglass rates), so it carries over
//! unchanged, and no viscous term exists in either. What differs is only
//! the size of the step: a static increment may rotate an element by a
//! sizeable angle `α`, and the midpoint configuration of a finite
//! rotation is shortened by `cos(α/2)`, so an element that turns by `α`
//! in one increment reads its curvature increment `1/cos(α/2)` too large
//! and, under a given moment, bends by about `α²/8` too little (measured:
//! an end moment rolling a strip falls short of the exact tip rotation
//! by `Δθ_tip²/24`, the mean over the strip); and its rigid rotation
//! leaves transverse shear and drilling increments of
//! `α − 2 tan(α/2) ≈ −α³/12` (the translations give the midpoint rule's
//! Cayley angle `2 tan(α/2)`, the nodes the rotation vector `α`). Load
//! increments that turn an element by at most 0.1–0.2 rad keep the
//! curvature's error below 0.5 % (`docs/springback.md` has the figures).
//! `commit` re-evaluates the converged state and keeps its point states;
//! `revert` drops the trial ones.
//!
//! # Tangent: forward-mode automatic differentiation
//!
//! Each kernel is generic over the scalar ([`Real`](crate::Real)): run on a
//! dual number carrying the derivatives with respect to the element's 24
//! DOFs (trial positions and rotation increments of its 4 nodes), it gives
//! the forces' exact derivatives — material and geometric (initial-stress)
//! terms, the frame's and the B-matrices' dependence on the nodes, the
//! turn between the midpoint and trial frames. The material stays `f64`:
//! the stress derivative enters by the chain rule,
//! `∂σ = C_alg ∂Δε` with `C_alg` = [`Material::consistent_tangent`] at the
//! point's committed state and trial increment. The tangent is exact to
//! rounding wherever the material's `C_alg` is (`tests/static_shell_tangent.rs`
//! and `tests/static_fi_shell_tangent.rs` check it against central
//! differences). It is not symmetric (the
//! co-rotational frame, the rotation increments as parameters), so the
//! solver factorises it by LU.
//!
//! [`Material::update`]: crate::Material::update
//! [`Material::consistent_tangent`]: crate::Material::consistent_tangent

mod dual;
mod element;
mod shells;
mod state;
mod tangent;

pub use shells::StaticShells;
pub(crate) use shells::{absorb_static_into, static_form_of};
