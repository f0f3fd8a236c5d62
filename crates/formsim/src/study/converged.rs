//! The converged answer a study measures its variants against: each
//! quantity extrapolated over the refinement sequence (`--converge`,
//! [`richardson`]), numbers as numbers and curves point by point.

use super::quantity::Measured;
use super::richardson::{self, Estimate};
use serde::Serialize;

/// The converged answer of one quantity.
#[derive(Debug, Clone, Serialize)]
pub struct ConvergedQuantity {
    /// The quantity's name.
    pub name: String,
    /// A number's value at each level, coarse to fine (`None` for a curve).
    pub levels: Vec<Option<f64>>,
    /// A number's estimate (`None` for a curve).
    pub estimate: Option<Estimate>,
    /// The uncertainty relative to the estimate: a number's
    /// `uncertainty / |value|`; a curve's RMS of the points' uncertainties
    /// over the estimated curve's largest magnitude.
    pub relative_uncertainty: f64,
    /// A curve's points extrapolated (the others keep the finest level's
    /// value), and its points in all.
    pub points_extrapolated: Option<(usize, usize)>,
    /// Why a number was not extrapolated (not in the asymptotic range).
    pub not_asymptotic: Option<String>,
}

/// The converged answer of a study.
#[derive(Debug, Clone, Serialize)]
pub struct Converged {
    /// The refined keys.
    pub keys: Vec<String>,
    /// The refinement ratio between consecutive levels.
    pub ratio: f64,
    /// The levels' labels, coarse to fine.
    pub levels: Vec<String>,
    /// One per quantity, in the study's order.
    pub quantities: Vec<ConvergedQuantity>,
    /// The estimate of each quantity as the variants are measured against.
    #[serde(skip)]
    pub measured: Vec<Measured>,
}

impl Converged {
    /// Extrapolate every quantity from `levels[l][q]` (coarse to fine).
    pub fn new(
        keys: Vec<String>,
        ratio: f64,
        labels: Vec<String>,
        names: Vec<String>,
        levels: &[&[Measured]],
    ) -> Result<Self, String> {
        let mut quantities = Vec::new();
        let mut measured = Vec::new();
        for (q, name) in names.into_iter().enumerate() {
            let at: Vec<&Measured> = levels.iter().map(|l| &l[q]).collect();
            let (c, m) = quantity(name, &at, ratio)?;
            quantities.push(c);
            measured.push(m);
        }
        Ok(Self {
            keys,
            ratio,
            levels: labels,
            quantities,
            measured,
        })
    }

    /// One line per quantity not in its asymptotic range, and per quantity
    /// whose converged answer is less certain than `tolerance` (a variant's
    /// error below that is not resolved).
    pub fn warnings(&self, tolerance: f64) -> Vec<String> {
        let mut w = Vec::new();
        for q in &self.quantities {
            if q.relative_uncertainty > tolerance {
                w.push(format!(
                    "{}: the converged answer is uncertain by {}, more than the tolerance {}: \
                     errors below that are not resolved (refine the sequence further)",
                    q.name,
                    super::report::percent(q.relative_uncertainty),
                    super::report::percent(tolerance)
                ));
            }
            if let Some(why) = &q.not_asymptotic {
                w.push(format!(
                    "{}: not extrapolated ({why}): the finest level is taken, with the \
                     levels' spread as its uncertainty",
                    q.name
                ));
            }
            if let Some((done, all)) = q.points_extrapolated
                && 2 * done < all
            {
                w.push(format!(
                    "{}: only {done} of {all} points in the asymptotic range",
                    q.name
                ));
            }
        }
        w
    }
}

fn quantity(
    name: String,
    at: &[&Measured],
    ratio: f64,
) -> Result<(ConvergedQuantity, Measured), String> {
    if let Some(values) = at
        .iter()
        .map(|m| match m {
            Measured::Scalar(x) => Some(*x),
            Measured::Curve(_) => None,
        })
        .collect::<Option<Vec<f64>>>()
    {
        let (e, why) = richardson::extrapolate(&values, ratio);
        let c = ConvergedQuantity {
            name,
            levels: values.iter().map(|v| Some(*v)).collect(),
            relative_uncertainty: e.uncertainty / e.value.abs(),
            estimate: Some(e),
            points_extrapolated: None,
            not_asymptotic: why.map(|w| w.to_string()),
        };
        return Ok((c, Measured::Scalar(e.value)));
    }
    let curves: Vec<&[(f64, f64)]> = at
        .iter()
        .map(|m| match m {
            Measured::Curve(c) => Ok(c.as_slice()),
            Measured::Scalar(_) => {
                Err(format!("{name}: a number at one level, a curve at another"))
            }
        })
        .collect::<Result<_, _>>()?;
    let (finest, coarser) = curves.split_last().expect("three levels");
    let (mut points, mut squares, mut done) = (Vec::new(), 0.0, 0);
    for &(x, f) in *finest {
        let mut values: Vec<f64> = coarser
            .iter()
            .filter_map(|c| crate::identify::observe::interpolate(c, x))
            .collect();
        if values.len() < coarser.len() {
            points.push((x, f));
            continue;
        }
        values.push(f);
        let (e, why) = richardson::extrapolate(&values, ratio);
        done += usize::from(why.is_none());
        squares += e.uncertainty * e.uncertainty;
        points.push((x, e.value));
    }
    let scale = points.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    let rms = (squares / points.len().max(1) as f64).sqrt();
    let c = ConvergedQuantity {
        name,
        levels: vec![None; at.len()],
        estimate: None,
        relative_uncertainty: if scale > 0.0 { rms / scale } else { 0.0 },
        points_extrapolated: Some((done, points.len())),
        not_asymptotic: None,
    };
    Ok((c, Measured::Curve(points)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three curves `y = x (1 + 0.001 h²)` on meshes of spacing `h = 4,
    /// 2, 1` (the coarser ones interpolated at the finest one's points,
    /// where the line is exact): the estimate is `y = x` at every point,
    /// each point's uncertainty `1.25 · 0.003 x / 3`, their RMS over the
    /// points `x = 0…8` relative to the curve's largest value 8.
    #[test]
    fn curves_extrapolate_point_by_point() {
        let curve = |h: f64| -> Measured {
            let n = (8.0 / h) as usize;
            Measured::Curve(
                (0..=n)
                    .map(|i| {
                        let x = i as f64 * h;
                        (x, x * (1.0 + 0.001 * h * h))
                    })
                    .collect(),
            )
        };
        let levels = [vec![curve(4.0)], vec![curve(2.0)], vec![curve(1.0)]];
        let refs: Vec<&[Measured]> = levels.iter().map(Vec::as_slice).collect();
        let c = Converged::new(
            vec!["h".into()],
            2.0,
            vec!["1".into(), "2".into(), "3".into()],
            vec!["y".into()],
            &refs,
        )
        .unwrap();
        let Measured::Curve(points) = &c.measured[0] else {
            panic!("a curve")
        };
        assert_eq!(points.len(), 9);
        for &(x, y) in points.iter().skip(1) {
            assert!((y - x).abs() < 1e-12, "{x}: {y}");
        }
        // x = 0 is the same at every level: taken as converged, no warning
        // beyond the points' count.
        assert_eq!(c.quantities[0].points_extrapolated, Some((8, 9)));
        let rms_x = ((0..=8).map(|i| (i * i) as f64).sum::<f64>() / 9.0).sqrt();
        let expected = 1.25e-3 * rms_x / 8.0;
        let got = c.quantities[0].relative_uncertainty;
        assert!(
            (got / expected - 1.0).abs() < 1e-9,
            "{got} against {expected}"
        );
        assert!(c.warnings(0.02).is_empty());
        assert_eq!(c.warnings(1e-4).len(), 1, "{:?}", c.warnings(1e-4));
    }
}
