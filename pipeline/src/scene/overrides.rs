//! `--set dotted.key=value` overrides applied to the scene's TOML before it is typed.

use crate::error::PipelineError;

/// Applies `key=value` to a TOML document. The key is dotted (`modes.n_modes`); a numeric segment
/// indexes an array (`components.0.element`). The value is parsed as a TOML value (`12`, `1e-5`,
/// `true`, `"hex20"`, `[1, 2]`); anything that does not parse is taken as a string.
pub fn apply_override(doc: &mut toml::Value, assignment: &str) -> Result<(), PipelineError> {
    let (key, raw) = assignment
        .split_once('=')
        .ok_or_else(|| PipelineError::Override {
            assignment: assignment.to_string(),
            reason: "expected key=value".into(),
        })?;
    let key = key.trim();
    if key.is_empty() {
        return Err(PipelineError::Override {
            assignment: assignment.to_string(),
            reason: "empty key".into(),
        });
    }
    let value = parse_value(raw.trim());
    let segments: Vec<&str> = key.split('.').collect();
    let mut node = doc;
    for (depth, seg) in segments.iter().enumerate() {
        let last = depth + 1 == segments.len();
        node = match node {
            toml::Value::Table(table) => {
                if last {
                    table.insert((*seg).to_string(), value);
                    return Ok(());
                }
                if !table.contains_key(*seg) && segments[depth + 1].parse::<usize>().is_ok() {
                    // An index into an array the scene does not write (a default): there is
                    // no array to index, and a table `{ "0" = … }` would be a type error.
                    let path = segments[..=depth].join(".");
                    return Err(PipelineError::Override {
                        assignment: assignment.to_string(),
                        reason: format!(
                            "`{path}` is not written in the scene, so `{}` cannot index it; set                              the whole value, e.g. `{path}=[...]`",
                            segments[depth + 1]
                        ),
                    });
                }
                table
                    .entry((*seg).to_string())
                    .or_insert_with(|| toml::Value::Table(Default::default()))
            }
            toml::Value::Array(items) => {
                let index: usize = seg.parse().map_err(|_| PipelineError::Override {
                    assignment: assignment.to_string(),
                    reason: format!("`{seg}` indexes an array and must be a number"),
                })?;
                let len = items.len();
                let item = items
                    .get_mut(index)
                    .ok_or_else(|| PipelineError::Override {
                        assignment: assignment.to_string(),
                        reason: format!(
                            "index {index} is out of range (the array has {len} items)"
                        ),
                    })?;
                if last {
                    *item = value;
                    return Ok(());
                }
                item
            }
            _ => {
                return Err(PipelineError::Override {
                    assignment: assignment.to_string(),
                    reason: format!("`{}` is a value, not a table", segments[..depth].join(".")),
                })
            }
        };
    }
    Ok(())
}

fn parse_value(raw: &str) -> toml::Value {
    let wrapped = format!("v = {raw}");
    match wrapped.parse::<toml::Table>() {
        Ok(mut t) => t
            .remove("v")
            .unwrap_or_else(|| toml::Value::String(raw.to_string())),
        Err(_) => toml::Value::String(raw.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_nested_numbers_strings_and_array_items() {
        let mut doc: toml::Value = toml::from_str(
            "[modes]\nn_modes = 4\n[[components]]\nname = \"a\"\n[[components]]\nname = \"b\"\n",
        )
        .unwrap();
        apply_override(&mut doc, "modes.n_modes=12").unwrap();
        apply_override(&mut doc, "components.1.name=rotor").unwrap();
        apply_override(&mut doc, "modes.max_frequency_hz=1e4").unwrap();
        assert_eq!(doc["modes"]["n_modes"].as_integer(), Some(12));
        assert_eq!(doc["modes"]["max_frequency_hz"].as_float(), Some(1e4));
        assert_eq!(doc["components"][1]["name"].as_str(), Some("rotor"));
    }

    #[test]
    fn index_into_an_unwritten_array_names_it() {
        let mut doc: toml::Value = toml::from_str("[rotor]\nrpm = 1.0\n").unwrap();
        let err = apply_override(&mut doc, "rotor.origin.1=2.0").unwrap_err();
        assert!(
            err.to_string().contains("`rotor.origin` is not written"),
            "{err}"
        );
        apply_override(&mut doc, "rotor.origin=[0.0, 2.0, 0.0]").unwrap();
        assert_eq!(doc["rotor"]["origin"][1].as_float(), Some(2.0));
    }

    #[test]
    fn bad_index_names_the_assignment() {
        let mut doc: toml::Value = toml::from_str("[[components]]\nname = \"a\"\n").unwrap();
        let err = apply_override(&mut doc, "components.3.name=x").unwrap_err();
        assert!(err.to_string().contains("components.3.name=x"), "{err}");
        assert!(err.to_string().contains("out of range"), "{err}");
    }
}
