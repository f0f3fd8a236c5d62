//! Fitted parameters: `--fit KEY=LO..HI[:START]`, their bounds and the
//! transform that lets an unbounded optimiser respect them.

use super::IdentifyError;

/// One fitted scene value and its bounds.
#[derive(Debug, Clone, PartialEq)]
pub struct FitParam {
    /// The scene key (`contact.params.ac.mu`), as for `--set`.
    pub key: String,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Start value (`None`: the scene's own value, or the middle of the range
    /// when the scene's value is outside it).
    pub start: Option<f64>,
}

impl FitParam {
    /// Parse `KEY=LO..HI` or `KEY=LO..HI:START`.
    ///
    /// # Errors
    /// No `=`, no `..`, a bound or start that is not a finite number,
    /// `LO >= HI`, or a start outside `[LO, HI]`.
    pub fn parse(text: &str) -> Result<Self, IdentifyError> {
        let bad = |why: &str| IdentifyError::Fit {
            text: text.to_string(),
            message: why.to_string(),
        };
        let (key, range) = text.split_once('=').ok_or_else(|| {
            bad("expected KEY=LO..HI[:START], e.g. contact.params.ac.mu=0.05..0.3")
        })?;
        let key = key.trim();
        if key.is_empty() {
            return Err(bad("empty key"));
        }
        let (range, start) = match range.split_once(':') {
            Some((r, s)) => (r, Some(s)),
            None => (range, None),
        };
        let (lo, hi) = range
            .split_once("..")
            .ok_or_else(|| bad("the range must be LO..HI"))?;
        let number = |what: &str, s: &str| -> Result<f64, IdentifyError> {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(&format!("{what} `{}` is not a finite number", s.trim())))
        };
        let lo = number("LO", lo)?;
        let hi = number("HI", hi)?;
        if lo >= hi {
            return Err(bad(&format!("LO = {lo} must be below HI = {hi}")));
        }
        let start = start.map(|s| number("START", s)).transpose()?;
        if let Some(s) = start
            && !(lo..=hi).contains(&s)
        {
            return Err(bad(&format!("START = {s} is outside [{lo}, {hi}]")));
        }
        Ok(Self {
            key: key.to_string(),
            lo,
            hi,
            start,
        })
    }

    /// The range's width `HI − LO`.
    pub fn width(&self) -> f64 {
        self.hi - self.lo
    }

    /// `x` as a fraction of the range: 0 at `LO`, 1 at `HI`.
    pub fn to_unit(&self, x: f64) -> f64 {
        (x - self.lo) / self.width()
    }

    /// The value at fraction `u` of the range (clamped to `[0, 1]`).
    pub fn from_unit(&self, u: f64) -> f64 {
        self.lo + self.width() * u.clamp(0.0, 1.0)
    }

    /// The bounded value of the optimiser's free variable `z`:
    /// `x = LO + (HI − LO)(1 + sin z)/2`. Every real `z` maps into the range,
    /// so Nelder–Mead never proposes a value outside it.
    pub fn from_free(&self, z: f64) -> f64 {
        self.from_unit(0.5 * (1.0 + z.sin()))
    }

    /// The free variable of `x` (the inverse of [`Self::from_free`] on
    /// `z ∈ [−π/2, π/2]`).
    pub fn to_free(&self, x: f64) -> f64 {
        (2.0 * self.to_unit(x).clamp(0.0, 1.0) - 1.0).asin()
    }
}

/// The `--set` assignment of `value` to `param`'s key, written so that it
/// reads back as the same `f64` (Rust's shortest round-trip form, which TOML
/// accepts: `0.162`, `-8.757e-5`, `4900.0`).
pub fn assignment(param: &FitParam, value: f64) -> String {
    format!("{}={value:?}", param.key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_parses_range_and_start() {
        let p = FitParam::parse("contact.params.ac.mu=0.05..0.3:0.1").unwrap();
        assert_eq!(p.key, "contact.params.ac.mu");
        assert_eq!((p.lo, p.hi, p.start), (0.05, 0.3, Some(0.1)));
        let q = FitParam::parse("contact.params.wh.a1=-2e-4..0").unwrap();
        assert_eq!((q.lo, q.hi, q.start), (-2e-4, 0.0, None));
    }

    #[test]
    fn fit_rejects_bad_input_with_one_line() {
        for bad in [
            "mu",
            "=0..1",
            "mu=0.3..0.1",
            "mu=0..1:2",
            "mu=a..1",
            "mu=0..inf",
            "mu=0-1",
        ] {
            let e = FitParam::parse(bad).unwrap_err().to_string();
            assert!(e.contains(bad) && !e.contains('\n'), "{bad}: {e}");
        }
    }

    #[test]
    fn free_transform_stays_in_bounds_and_inverts() {
        let p = FitParam::parse("k=0.05..0.3").unwrap();
        for z in [-100.0, -1.0, 0.0, 0.7, 3.0, 1e6] {
            let x = p.from_free(z);
            assert!((0.05..=0.3).contains(&x), "{z} -> {x}");
        }
        for x in [0.05, 0.1, 0.162, 0.3] {
            assert!((p.from_free(p.to_free(x)) - x).abs() < 1e-15);
        }
    }

    #[test]
    fn assignment_reads_back_the_same_bits() {
        let p = FitParam::parse("contact.params.wh.a1=-1..1").unwrap();
        for v in [0.162, -8.757e-5, 4900.0, 1.0 / 3.0, 1e-300] {
            let text = assignment(&p, v);
            let (_, value) = crate::scene::overrides::parse_assignment(&text).unwrap();
            assert_eq!(value.as_float(), Some(v), "{text}");
        }
    }
}
