//! The one quantity language of the commands that read runs: what `study`
//! compares across variants and what `identify` fits to measurements.
//!
//! A quantity is a number of `summary.json` by its dotted key
//! (`draw_in.DX`, `punch_force_max`, `states.40.draw_in.DD`), a section
//! curve (`SECTION:COLUMN` at the end of the run, `SECTION@STROKE:COLUMN`
//! at a report stroke, `COLUMN` one of `major`, `minor`,
//! `thickness_strain`, `thinning`), or the punch force at a stroke
//! (`punch_force@STROKE`, N, full part, interpolated in the run's
//! history). [`Quantity::check`] refuses, before any run, a quantity the
//! scene will not report.

use crate::run::post::SectionRow;
use crate::run::probe::Probe;
use crate::run::summary::stroke_key;

/// The name of the punch force at a stroke: `punch_force@STROKE`.
pub const FORCE: &str = "punch_force";

/// A column of a section curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CurveColumn {
    /// Major strain (-).
    Major,
    /// Minor strain (-).
    Minor,
    /// Thickness strain (-).
    ThicknessStrain,
    /// Thinning (-).
    Thinning,
}

impl CurveColumn {
    /// Parse a column name.
    pub fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "major" => Self::Major,
            "minor" => Self::Minor,
            "thickness_strain" => Self::ThicknessStrain,
            "thinning" => Self::Thinning,
            _ => return None,
        })
    }

    /// The column's value in a row of a section curve.
    pub fn of(self, row: &SectionRow) -> f64 {
        match self {
            Self::Major => row.major,
            Self::Minor => row.minor,
            Self::ThicknessStrain => row.thickness_strain,
            Self::Thinning => row.thinning,
        }
    }

    /// The column's name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Major => "major",
            Self::Minor => "minor",
            Self::ThicknessStrain => "thickness_strain",
            Self::Thinning => "thinning",
        }
    }
}

/// What a run is read for.
#[derive(Debug, Clone, PartialEq)]
pub enum Quantity {
    /// A number of `summary.json` by its dotted key.
    Scalar {
        /// The dotted key, e.g. `draw_in.DX`.
        key: String,
    },
    /// A section curve.
    Curve {
        /// Section name (`output.sections`).
        section: String,
        /// Report stroke (mm); `None`: the end of the run.
        stroke: Option<f64>,
        /// Which column of the section's rows.
        column: CurveColumn,
    },
    /// The punch force (full part, N) at a stroke.
    Force {
        /// Stroke (mm).
        stroke: f64,
    },
}

/// Why a quantity's name does not parse: the message, for the caller to
/// prefix with where the name came from.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ParseError {
    /// An empty name.
    #[error("an empty name")]
    Empty,
    /// The column after `:` is not one of the section columns.
    #[error("the column after `:` must be major, minor, thickness_strain or thinning")]
    Column,
    /// The stroke after `@` is not a number.
    #[error("the stroke after `@` must be a number (mm)")]
    StrokeNotNumber,
    /// The stroke after `@` is infinite or NaN.
    #[error("the stroke must be finite (mm)")]
    StrokeNotFinite,
    /// Nothing before `:`.
    #[error("no section before `:`")]
    NoSection,
}

/// A finite stroke after `@`.
fn stroke(text: &str) -> Result<f64, ParseError> {
    let s: f64 = text
        .trim()
        .parse()
        .map_err(|_| ParseError::StrokeNotNumber)?;
    if s.is_finite() {
        Ok(s)
    } else {
        Err(ParseError::StrokeNotFinite)
    }
}

impl Quantity {
    /// Parse `KEY`, `SECTION:COLUMN`, `SECTION@STROKE:COLUMN` or
    /// `punch_force@STROKE`.
    ///
    /// # Errors
    /// An empty name, an unknown column, a stroke that is not a finite number.
    pub fn parse(text: &str) -> Result<Self, ParseError> {
        let text = text.trim();
        if text.is_empty() {
            return Err(ParseError::Empty);
        }
        let Some((place, column)) = text.split_once(':') else {
            return match text.split_once('@') {
                Some((name, s)) if name.trim() == FORCE => {
                    Ok(Quantity::Force { stroke: stroke(s)? })
                }
                _ => Ok(Quantity::Scalar { key: text.into() }),
            };
        };
        let column = CurveColumn::parse(column.trim()).ok_or(ParseError::Column)?;
        let (section, stroke) = match place.split_once('@') {
            None => (place.trim(), None),
            Some((s, k)) => (s.trim(), Some(stroke(k)?)),
        };
        if section.is_empty() {
            return Err(ParseError::NoSection);
        }
        Ok(Quantity::Curve {
            section: section.into(),
            stroke,
            column,
        })
    }

    /// The quantity as it is written on the command line.
    pub fn name(&self) -> String {
        match self {
            Quantity::Scalar { key } => key.clone(),
            Quantity::Curve {
                section,
                stroke: None,
                column,
            } => format!("{section}:{}", column.name()),
            Quantity::Curve {
                section,
                stroke: Some(s),
                column,
            } => format!("{section}@{}:{}", stroke_key(*s), column.name()),
            Quantity::Force { stroke } => format!("{FORCE}@{}", stroke_key(*stroke)),
        }
    }

    /// The report stroke the quantity is read at, if any (a curve's, or a
    /// `states.STROKE.…` key's).
    pub fn report_stroke(&self) -> Option<f64> {
        match self {
            Quantity::Curve { stroke, .. } => *stroke,
            Quantity::Scalar { key } => state_stroke(key),
            Quantity::Force { .. } => None,
        }
    }

    /// Check, before any run, that a run of the probed scene reports the
    /// quantity (the punch force is always reported).
    ///
    /// # Errors
    /// One line: what is missing and what the scene reports instead.
    pub fn check(&self, probe: &Probe) -> Result<(), String> {
        match self {
            Quantity::Scalar { key } => probe.check_key(key),
            Quantity::Curve {
                section, stroke, ..
            } => probe.check_curve(section, *stroke),
            Quantity::Force { .. } => Ok(()),
        }
    }
}

/// The stroke of a `states.STROKE.…` key (the stroke may hold a dot).
pub fn state_stroke(key: &str) -> Option<f64> {
    let rest = key.strip_prefix("states.")?;
    // The stroke is the longest prefix of dotted parts that parses.
    let parts: Vec<&str> = rest.split('.').collect();
    (1..parts.len())
        .rev()
        .find_map(|n| parts[..n].join(".").parse::<f64>().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_print_back() {
        for name in [
            "draw_in.DX",
            "OD:major",
            "OD@20:thinning",
            "OD@12.5:minor",
            "punch_force@20",
            "punch_force_max",
        ] {
            assert_eq!(Quantity::parse(name).unwrap().name(), name);
        }
        assert_eq!(
            Quantity::parse("punch_force@20").unwrap(),
            Quantity::Force { stroke: 20.0 }
        );
        assert_eq!(Quantity::parse(" "), Err(ParseError::Empty));
        assert_eq!(Quantity::parse("OD:majr"), Err(ParseError::Column));
        assert_eq!(
            Quantity::parse("OD@x:major"),
            Err(ParseError::StrokeNotNumber)
        );
        assert_eq!(
            Quantity::parse("OD@inf:major"),
            Err(ParseError::StrokeNotFinite)
        );
        assert_eq!(
            Quantity::parse("punch_force@x"),
            Err(ParseError::StrokeNotNumber)
        );
        assert_eq!(Quantity::parse(":major"), Err(ParseError::NoSection));
    }

    #[test]
    fn report_strokes_are_read_from_curves_and_state_keys() {
        let q = |s: &str| Quantity::parse(s).unwrap().report_stroke();
        assert_eq!(q("states.12.5.draw_in.DX"), Some(12.5));
        assert_eq!(q("states.40.punch_force"), Some(40.0));
        assert_eq!(q("OD@20:major"), Some(20.0));
        assert_eq!(q("OD:major"), None);
        assert_eq!(q("draw_in.DX"), None);
    }
}
