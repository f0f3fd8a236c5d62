//! The scene as formsim resolved it: every key with its value, the defaults
//! filled in and the overrides applied. `summary.json` carries it as
//! `settings`; `formsim scene check --resolved` prints it as dotted keys.

use super::Scene;

/// The resolved scene as a TOML value (unset options left out).
///
/// # Errors
/// A value TOML cannot hold (none of the scene's types should fail).
pub fn to_toml(scene: &Scene) -> Result<toml::Value, toml::ser::Error> {
    toml::Value::try_from(scene)
}

/// The resolved scene as `key = value` lines in dotted-key form, in key
/// order (`blank.hourglass = 0.05`, `steps[2].motions[0].damping = 0.0`, …),
/// each value written as in a scene file.
///
/// # Errors
/// As [`to_toml`].
pub fn dotted_lines(scene: &Scene) -> Result<Vec<String>, toml::ser::Error> {
    let mut lines = Vec::new();
    flatten(&to_toml(scene)?, String::new(), &mut lines);
    Ok(lines)
}

fn flatten(v: &toml::Value, at: String, out: &mut Vec<String>) {
    match v {
        toml::Value::Table(t) => {
            for (k, v) in t {
                let key = if at.is_empty() {
                    k.clone()
                } else {
                    format!("{at}.{k}")
                };
                flatten(v, key, out);
            }
        }
        toml::Value::Array(a) if a.iter().any(|x| x.is_table()) => {
            for (i, x) in a.iter().enumerate() {
                flatten(x, format!("{at}[{i}]"), out);
            }
        }
        other => out.push(format!("{at} = {other}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Defaults appear (the force motion's dashpot, the hourglass
    /// coefficient), overrides win, arrays of tables get indices.
    #[test]
    fn dotted_lines_show_defaults_and_overrides() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/square-cup.toml");
        let loaded = super::super::load(&path, &["blank.hourglass=0.07".to_string()]).unwrap();
        let lines = dotted_lines(&loaded.scene).unwrap();
        let has = |l: &str| lines.iter().any(|x| x == l);
        assert!(has("blank.hourglass = 0.07"), "{lines:#?}");
        assert!(has("steps[2].motions[0].damping = 0.0"), "{lines:#?}");
        assert!(has("steps[2].motions[0].relative_damping = 0.0"));
        assert!(has("contact.penalty_scale = 0.1"));
        assert!(has("solver.mass_scaling_dt = 0.0000005"), "{lines:#?}");
    }
}
