//! # formsim-examples: teaching examples, one step at a time
//!
//! Six small programs, in the spirit of deal.II's step-N tutorials, each
//! building on the one before. Every example prints what it computes, checks
//! it against an analytic or published value with a stated tolerance, and is
//! also a test (`cargo test --release -p formsim-examples` runs all six).
//! The order and what each teaches are in `examples/README.md`:
//!
//! 1. `step1_friction_point`: one contact point through a friction law (stick,
//!    slip, dissipation), no mesh;
//! 2. `step2_block_on_plane`: the explicit engine, springs and a contact pair:
//!    a block starts to slide at `T = μ N`;
//! 3. `step3_capstan`: a shell strip over a drum from a scene file:
//!    `T_out/T_in = exp(μ θ)`;
//! 4. `step4_square_cup_in_code`: the NUMISHEET'93 square cup assembled from
//!    the engine crates by hand, checked bit for bit against the scene;
//! 5. `step5_my_friction_law`: a new friction law in about 40 lines, paired
//!    with every formulation and put through the conformance suite;
//! 6. `step6_springback`: the static Newton solver bends a plastic strip and
//!    releases it: its springback against the plane-strain closed form.
//!
//! Run one with `cargo run --release -p formsim-examples --example NAME`.
//!
//! This library holds no code: Cargo needs a library or binary target in a
//! package, and this one carries the package's documentation.
