//! The swept values (`--values a,b,c`, `--values-range a:b:n`) and the check that `--param`
//! names a value of the scene.

use crate::error::PipelineError;
use crate::scene::Scene;

use squeal_solver::Real;

fn bad(option: &str, text: &str, why: String) -> PipelineError {
    PipelineError::Option {
        option: option.into(),
        message: format!("`{text}`: {why}"),
    }
}

/// A number as short as it prints at 12 significant digits (`0.30000000000000004` → `0.3`),
/// in exponent form when very large or small (a valid TOML number either way).
fn tidy(x: Real) -> String {
    let r: Real = format!("{x:.11e}").parse().unwrap_or(x);
    if r != 0.0 && !(1e-4..1e15).contains(&r.abs()) {
        format!("{r:e}")
    } else {
        format!("{r}")
    }
}

/// The values, as TOML value texts in sweep order: the comma-separated `list`, then `range`
/// FIRST:LAST:COUNT evenly spaced (integers when FIRST, LAST and every step are whole).
pub fn parse_values(list: Option<&str>, range: Option<&str>) -> Result<Vec<String>, PipelineError> {
    let mut out: Vec<String> = Vec::new();
    if let Some(list) = list {
        for v in list.split(',').map(str::trim) {
            if v.is_empty() {
                return Err(bad("--values", list, "an empty value".into()));
            }
            out.push(v.to_string());
        }
    }
    if let Some(text) = range {
        let why = |w: &str| {
            bad(
                "--values-range",
                text,
                format!("{w}; write FIRST:LAST:COUNT, e.g. 0.3:0.7:5"),
            )
        };
        let parts: Vec<&str> = text.split(':').map(str::trim).collect();
        if parts.len() != 3 {
            return Err(why("expected three fields"));
        }
        let a: Real = parts[0].parse().map_err(|_| why("FIRST is not a number"))?;
        let b: Real = parts[1].parse().map_err(|_| why("LAST is not a number"))?;
        let n: usize = parts[2]
            .parse()
            .map_err(|_| why("COUNT is not a whole number"))?;
        if !(a.is_finite() && b.is_finite()) || n == 0 {
            return Err(why("FIRST and LAST must be finite and COUNT at least 1"));
        }
        let whole = parts[0].parse::<i64>().is_ok()
            && parts[1].parse::<i64>().is_ok()
            && (n == 1 || ((b - a) / (n - 1) as Real).fract() == 0.0);
        for i in 0..n {
            let x = if n == 1 {
                a
            } else {
                a + (b - a) * i as Real / (n - 1) as Real
            };
            out.push(if whole {
                format!("{}", x.round() as i64)
            } else {
                tidy(x)
            });
        }
    }
    if out.is_empty() {
        return Err(PipelineError::Option {
            option: "--values".into(),
            message:
                "no values to sweep: give --values a,b,c and/or --values-range FIRST:LAST:COUNT"
                    .into(),
        });
    }
    Ok(out)
}

/// A value text as JSON (number, string, bool, array…), parsed as `--set` parses it.
pub fn value_json(text: &str) -> serde_json::Value {
    let doc = format!("v = {text}");
    doc.parse::<toml::Table>()
        .ok()
        .and_then(|mut t| t.remove("v"))
        .and_then(|v| serde_json::to_value(v).ok())
        .unwrap_or_else(|| serde_json::Value::String(text.to_string()))
}

/// The scene of one value: `base` with `param=value`, validated. Errors name the parameter:
/// the key must be a value the scene accepts and holds once resolved.
pub fn scene_for(base: &Scene, param: &str, value: &str) -> Result<Scene, PipelineError> {
    scene_for_all(base, &[(param.to_string(), value.to_string())])
}

/// [`scene_for`] for several parameters set together (one point of a grid, or keys that must
/// change together such as both pads' arc), validated once all are set.
pub fn scene_for_all(
    base: &Scene,
    assignments: &[(String, String)],
) -> Result<Scene, PipelineError> {
    let params: Vec<&str> = assignments.iter().map(|(p, _)| p.as_str()).collect();
    let wrap = |message: String| PipelineError::Option {
        option: format!("--param {}", params.join(", ")),
        message,
    };
    for p in &params {
        if p.trim().is_empty() || p.contains('=') {
            return Err(wrap(format!(
                "`{p}` must be a dotted scene key such as friction.law.mu"
            )));
        }
    }
    let texts: Vec<String> = assignments
        .iter()
        .map(|(p, v)| format!("{p}={v}"))
        .collect();
    let values: Vec<&str> = assignments.iter().map(|(_, v)| v.as_str()).collect();
    let mut scene = base.clone();
    scene.set_all(&texts).map_err(|e| {
        wrap(format!(
            "not a value this scene accepts (set to {}): {e}",
            values.join(", ")
        ))
    })?;
    let resolved = toml::Value::try_from(&scene).map_err(|e| wrap(e.to_string()))?;
    for p in &params {
        let mut node = &resolved;
        let segs: Vec<&str> = p.split('.').collect();
        for (i, seg) in segs.iter().enumerate() {
            let next = match node {
                toml::Value::Table(t) => t.get(*seg),
                toml::Value::Array(a) => seg.parse::<usize>().ok().and_then(|i| a.get(i)),
                _ => None,
            };
            // A key of a typed table (it was set without error) that the resolved scene
            // omits at its default, e.g. `components.1.rotate_deg = 0`.
            if next.is_none() && i + 1 == segs.len() && matches!(node, toml::Value::Table(_)) {
                break;
            }
            node = next.ok_or_else(|| {
                wrap(format!(
                    "the resolved scene has no such value (no `{seg}` in `{p}`)"
                ))
            })?;
        }
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_and_ranges() {
        let v = parse_values(Some("0.3, 0.5,hex8"), Some("0.1:0.3:3")).unwrap();
        assert_eq!(v, ["0.3", "0.5", "hex8", "0.1", "0.2", "0.3"]);
        assert_eq!(
            parse_values(None, Some("32:64:3")).unwrap(),
            ["32", "48", "64"]
        );
        assert_eq!(
            parse_values(None, Some("1:2:3")).unwrap(),
            ["1", "1.5", "2"]
        );
        assert_eq!(parse_values(None, Some("0.5:0.5:1")).unwrap(), ["0.5"]);
        assert_eq!(
            parse_values(None, Some("1e-6:3e-6:3")).unwrap(),
            ["1e-6", "2e-6", "3e-6"]
        );
        let e = parse_values(None, Some("0.1:x:3")).unwrap_err().to_string();
        assert!(e.contains("--values-range") && e.contains("LAST"), "{e}");
        assert!(parse_values(None, None).is_err());
        assert!(parse_values(Some("1,,2"), None).is_err());
    }

    #[test]
    fn values_as_json() {
        assert_eq!(value_json("0.5"), serde_json::json!(0.5));
        assert_eq!(value_json("32"), serde_json::json!(32));
        assert_eq!(value_json("hex8"), serde_json::json!("hex8"));
        assert_eq!(value_json("[1, 2]"), serde_json::json!([1, 2]));
    }

    /// Keys that must change together (both pads' arc on the study brake) are set together
    /// and validated once; one at a time the first is refused; an invalid key names the keys.
    #[test]
    fn keys_set_together() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../examples/sample-brake/base.toml");
        let base = Scene::load(&path, &[]).unwrap();
        let pair = |k: &str, v: &str| (k.to_string(), v.to_string());
        let both = [
            pair("components.1.geometry.n_elements", "3"),
            pair("components.2.geometry.n_elements", "3"),
        ];
        let e = scene_for(&base, &both[0].0, &both[0].1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("inboard pad"), "{e}");
        let s = scene_for_all(&base, &both).unwrap();
        let doc = toml::Value::try_from(&s).unwrap();
        assert_eq!(
            doc["components"][2]["geometry"]["n_elements"].as_integer(),
            Some(3)
        );
        let e = scene_for_all(&base, &[both[0].clone(), pair("friction.law.mu0x", "0.5")])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--param components.1.geometry.n_elements, friction.law.mu0x"),
            "{e}"
        );
    }
}
