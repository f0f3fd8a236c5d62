//! `[formability]`: the scene's forming limit curve and the zones'
//! thresholds (docs/formability.md).

use super::curve::Measure;
use serde::{Deserialize, Serialize};

/// `[formability]`: present, every run evaluates the forming limit diagram
/// at its report strokes and at the end.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FormabilitySection {
    /// `"keeler-brazier"` (default) or `"table"`.
    #[serde(default)]
    pub curve: CurveKind,
    /// Keeler–Brazier's hardening exponent (-); default the Swift `n` of
    /// `blank.material.hardening`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub n: Option<f64>,
    /// A table's CSV file of `minor,major` rows (relative to the scene).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// A table's strain measure; Keeler–Brazier's is engineering.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measure: Option<Measure>,
    /// Width of the marginal band below the curve, major strain in the
    /// curve's measure (-); default 0.10.
    #[serde(default = "default_margin")]
    pub margin: f64,
    /// Least major true strain of a stretched sheet (-); default 0.02.
    #[serde(default = "default_stretch")]
    pub insufficient_stretch: f64,
}

/// Where the curve comes from.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CurveKind {
    /// From the sheet's hardening exponent and thickness.
    #[default]
    KeelerBrazier,
    /// A measured curve from `file`.
    Table,
}

fn default_margin() -> f64 {
    0.10
}

fn default_stretch() -> f64 {
    0.02
}
