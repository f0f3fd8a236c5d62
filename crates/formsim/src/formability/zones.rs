//! The formability zone of a strain state: where it stands against the
//! forming limit curve, and where it thickens or barely stretches.

use super::curve::FormingLimitCurve;
use serde::Serialize;

/// A formability zone, in the order of precedence of [`classify`]. The
/// number ([`Zone::code`]) is the VTK field `fld_zone`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Zone {
    /// On or above the forming limit curve: the sheet necks and splits.
    Failure,
    /// Within the margin below the curve: a risk of splits.
    Marginal,
    /// Stretched enough, and below the margin line.
    Safe,
    /// Major strain below the stretch threshold: the sheet is barely
    /// formed (a loose panel, springback-prone).
    InsufficientStretch,
    /// Thickening (`ε1 + ε2 < 0`) between pure shear and uniaxial
    /// compression: a drawn flange, normal under a holder.
    Compression,
    /// Thickening beyond uniaxial compression (`ε1 < −ε2/2`): compressed
    /// without the lateral stretch that keeps a sheet flat.
    WrinklingTendency,
}

impl Zone {
    /// Every zone, in order.
    pub const ALL: [Zone; 6] = [
        Zone::Failure,
        Zone::Marginal,
        Zone::Safe,
        Zone::InsufficientStretch,
        Zone::Compression,
        Zone::WrinklingTendency,
    ];

    /// The zone's number in the VTK field `fld_zone`.
    pub fn code(self) -> u8 {
        self as u8
    }

    /// The zone's name as `summary.json` writes it.
    pub fn name(self) -> &'static str {
        match self {
            Zone::Failure => "failure",
            Zone::Marginal => "marginal",
            Zone::Safe => "safe",
            Zone::InsufficientStretch => "insufficient_stretch",
            Zone::Compression => "compression",
            Zone::WrinklingTendency => "wrinkling_tendency",
        }
    }

    /// The zone's label on the plot.
    pub fn label(self) -> &'static str {
        match self {
            Zone::Failure => "failure",
            Zone::Marginal => "marginal",
            Zone::Safe => "safe",
            Zone::InsufficientStretch => "insufficient stretch",
            Zone::Compression => "compression",
            Zone::WrinklingTendency => "wrinkling tendency",
        }
    }
}

/// The thresholds of the zones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thresholds {
    /// Width of the marginal band below the curve, in major strain of the
    /// curve's measure (-).
    pub margin: f64,
    /// The least major true strain of a stretched sheet, and the least
    /// compressive minor true strain that counts as compression (-).
    pub stretch: f64,
}

/// One element's point on the diagram.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FldPoint {
    /// Major strain in the curve's measure (-).
    pub major: f64,
    /// Minor strain in the curve's measure (-).
    pub minor: f64,
    /// Its zone.
    pub zone: Zone,
    /// Safety margin: the curve's limit at `minor` less `major` (-;
    /// negative beyond the curve).
    pub margin: f64,
}

/// The zone of the in-plane true strains `eps1 ≥ eps2` (major, minor)
/// against `curve`. The curve is read in its own measure; the thickening
/// and stretch tests use true strain, where `ε1 + ε2 < 0` is exactly a
/// thicker sheet.
pub fn classify(curve: &FormingLimitCurve, t: &Thresholds, eps1: f64, eps2: f64) -> FldPoint {
    let m = curve.measure();
    let (major, minor) = (m.from_true(eps1), m.from_true(eps2));
    let margin = curve.limit(minor) - major;
    let zone = if margin <= 0.0 {
        Zone::Failure
    } else if margin <= t.margin {
        Zone::Marginal
    } else if eps2 <= -t.stretch && eps1 + 0.5 * eps2 < 0.0 {
        Zone::WrinklingTendency
    } else if eps2 <= -t.stretch && eps1 + eps2 < 0.0 {
        Zone::Compression
    } else if eps1 < t.stretch {
        Zone::InsufficientStretch
    } else {
        Zone::Safe
    };
    FldPoint {
        major,
        minor,
        zone,
        margin,
    }
}
