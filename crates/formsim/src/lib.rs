//! # formsim: the command-line tool and the library that composes the solvers
//!
//! Place in the pipeline: the top. It owns user-facing work: resolving
//! components named by the user (built-in laws, formulations, dynamic plugins)
//! into monomorphised point integrators ([`components`]), reading prescribed
//! contact-point histories ([`history`]) and integrating them
//! ([`point_driver`]), and plotting ([`plot`]), and the rigid-tool commands ([`tools_cli`]: export,
//! projection of points), and what accuracy costs in time ([`study`]). Scenes, forming runs and reports
//! join as the engine crates arrive. It must not re-implement physics: every
//! friction number comes from `plugins-api`'s return mapping and the laws.

pub mod batch;
pub mod compare;
pub mod components;
mod csv_records;
pub mod formability;
pub mod history;
pub mod identify;
pub mod output;
pub mod plot;
pub mod point_driver;
pub mod quantity;
pub mod records;
pub mod run;
pub mod scene;
pub mod state_file;
pub mod study;
pub mod tools_cli;
