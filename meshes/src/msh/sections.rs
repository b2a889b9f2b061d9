//! Section handling shared by the 2.2 and 4.1 readers.

use super::text::Lines;
use super::RawMesh;
use crate::MeshError;

/// The name of a section header line `$Name`.
pub(crate) fn header<'a>(lines: &Lines, l: &'a str) -> Result<&'a str, MeshError> {
    let t = l.trim();
    match t.strip_prefix('$') {
        Some(name) if !name.is_empty() && !name.starts_with("End") => {
            if name == "MeshFormat" {
                Err(lines.err("second `$MeshFormat` section"))
            } else {
                Ok(name)
            }
        }
        _ => Err(lines.err(format!(
            "expected a section header such as `$Nodes`, found `{}`",
            super::text::shorten(t)
        ))),
    }
}

/// Errors when a section appears twice.
pub(crate) fn once(lines: &Lines, name: &str, seen: &mut bool) -> Result<(), MeshError> {
    if *seen {
        return Err(lines.err(format!("second `${name}` section")));
    }
    *seen = true;
    Ok(())
}

/// Errors when `$Nodes` or `$Elements` is missing.
pub(crate) fn require(lines: &Lines, nodes: bool, elements: bool) -> Result<(), MeshError> {
    for (seen, name) in [(nodes, "Nodes"), (elements, "Elements")] {
        if !seen {
            return Err(lines.err(format!("the file has no `${name}` section")));
        }
    }
    Ok(())
}

/// `$PhysicalNames`: a count, then `dim tag "name"` lines (ASCII in binary files too).
pub(crate) fn physical_names(lines: &mut Lines, raw: &mut RawMesh) -> Result<(), MeshError> {
    let n = lines
        .fields("PhysicalNames")?
        .count("number of physical names")?;
    for _ in 0..n {
        let l = lines.entry_line("PhysicalNames")?;
        let line = lines.line;
        let mut f = lines.fields_of(l, line);
        let dim = f.i64("physical dimension")?;
        let tag = f.i64("physical tag")?;
        if !(0..=3).contains(&dim) {
            return Err(lines.err(format!("physical dimension {dim} is not 0..3")));
        }
        let name = match (l.find('"'), l.rfind('"')) {
            (Some(a), Some(b)) if b > a => &l[a + 1..b],
            _ => {
                return Err(lines.err(format!(
                    "physical name of ({dim}, {tag}) is not in double quotes: `{}`",
                    super::text::shorten(l)
                )))
            }
        };
        if name.is_empty() {
            return Err(lines.err(format!("empty physical name for ({dim}, {tag})")));
        }
        raw.names.insert((dim, tag), name.to_string());
    }
    lines.expect_end("PhysicalNames")
}
