//! # test-broken-material: j2-voce broken on request (a test fixture, not an example)
//!
//! The material of `plugins/j2-voce` with one extra parameter, `fault`, for
//! the tests of formsim's material conformance suite and loader:
//!
//! - `0`: none (the material passes the suite);
//! - `1`: a wrong elastic modulus (reports 0.9 E, computes with E);
//! - `2`: returns NaN stresses once the point has yielded;
//! - `3`: panics once the point has yielded.

/// The example's material, compiled from its own file (not a dependency on
/// the `j2-voce` crate, whose library exports its own entry point).
#[path = "../../j2-voce/src/material.rs"]
mod j2_voce;

use j2_voce::J2Voce;
use plugins_api::ParamSpec;
use plugins_api::material::{Elastic, PointResult, UserMaterial};

/// j2-voce with a fault.
#[derive(Clone, Copy, Debug)]
pub struct Broken {
    inner: J2Voce,
    fault: u8,
}

/// j2-voce's schema and `fault`.
const PARAMS: [ParamSpec; 8] = {
    let p = J2Voce::PARAMS;
    [
        p[0],
        p[1],
        p[2],
        p[3],
        p[4],
        p[5],
        p[6],
        ParamSpec::optional(
            "fault",
            "-",
            0.0,
            0.0,
            3.0,
            "0 none, 1 wrong modulus, 2 NaN, 3 panic",
        ),
    ]
};

impl UserMaterial for Broken {
    const NAME: &'static str = "test-broken-material";
    const SUMMARY: &'static str = "j2-voce with a fault on request (test fixture)";
    const PARAMS: &'static [ParamSpec] = &PARAMS;
    const N_STATE: usize = J2Voce::N_STATE;
    const ISOTROPIC: bool = true;

    fn from_values(v: &[f64]) -> Result<Self, String> {
        let fault = v[7];
        if fault.fract() != 0.0 {
            return Err(format!("fault = {fault} must be 0, 1, 2 or 3"));
        }
        Ok(Self {
            inner: J2Voce::from_values(&v[..7])?,
            fault: fault as u8,
        })
    }

    fn elastic(&self) -> Elastic {
        let mut e = self.inner.elastic();
        if self.fault == 1 {
            e.young *= 0.9;
        }
        e
    }

    fn initial_state(&self, state: &mut [f64]) -> f64 {
        self.inner.initial_state(state)
    }

    fn update(
        &self,
        deps: [f64; 3],
        stress: &mut [f64; 3],
        state: &mut [f64],
    ) -> Result<PointResult, String> {
        let r = self.inner.update(deps, stress, state)?;
        if r.plastic_strain > 0.0 {
            match self.fault {
                2 => *stress = [f64::NAN; 3],
                3 => panic!(
                    "test-broken-material: fault 3 at plastic strain {}",
                    r.plastic_strain
                ),
                _ => {}
            }
        }
        Ok(r)
    }
}

plugins_api::export_material!(Broken);

#[cfg(test)]
mod tests {
    use super::*;
    use plugins_api::Params;
    use plugins_api::material::conformance::{MaterialReport, check_material};
    use plugins_api::material::loader::MaterialLibrary;

    fn report(fault: f64) -> MaterialReport {
        let lib = MaterialLibrary::linked::<Broken>().expect("table");
        let params = Params::new()
            .with("youngs_modulus", 206_000.0)
            .with("density", 7.85e-9)
            .with("sigma0", 170.0)
            .with("q", 250.0)
            .with("b", 9.0)
            .with("fault", fault);
        check_material(&lib.build(&params).expect("material"))
    }

    fn failed(r: &MaterialReport) -> Vec<&'static str> {
        r.results
            .iter()
            .filter(|c| !c.passed)
            .map(|c| c.check)
            .collect()
    }

    /// Without a fault the fixture passes; each fault fails the checks that
    /// should catch it, with a message that says what happened.
    #[test]
    fn each_fault_fails_the_suite_with_a_readable_report() {
        let clean = report(0.0);
        assert!(clean.passed(), "{clean}");

        let modulus = report(1.0);
        println!("{modulus}");
        assert!(failed(&modulus).contains(&"elastic"), "{modulus}");
        assert!(
            modulus
                .to_string()
                .contains("Hooke's law with the reported E = 185400")
        );

        let nan = report(2.0);
        println!("{nan}");
        assert!(failed(&nan).contains(&"yield-surface"), "{nan}");
        assert!(
            nan.to_string().contains("returned a non-finite value"),
            "{nan}"
        );

        let panic = report(3.0);
        println!("{panic}");
        assert!(failed(&panic).contains(&"yield-surface"), "{panic}");
        let text = panic.to_string();
        assert!(
            text.contains("panicked: test-broken-material: fault 3"),
            "{text}"
        );
        assert!(text.contains("lib.rs:"), "the panic's location: {text}");
    }
}
