//! Run outputs: summary, sections, histories, VTK series and plots.
pub mod csv_text;
pub mod error;
pub mod field_plots;
pub mod vtk;
pub use error::OutputError;
