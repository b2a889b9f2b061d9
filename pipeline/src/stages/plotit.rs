//! `squeal plotit RUN_DIR --records SPEC ... --out table.csv`: PLOTIT's job — chosen records of
//! the time-history database as a CSV table (time in the first column).
//!
//! A record spec is a column name (`u_1000005_z`, `gap3_contact_force`, see
//! `history_map.json`), or `KIND[:grid=G][:comp=x|y|z][:gap=N]` with KIND one of
//! `displacement`, `velocity`, `acceleration`, `contact_force`, `pressure`, `friction_force`,
//! `friction_coefficient`, `slip_speed`; it selects every column matching all given filters.

use crate::error::PipelineError;
use crate::history::npy::read_npy;
use crate::history::{Column, HistoryMap, RecordKind};
use std::fmt::Write as _;
use std::path::Path;

fn bad(spec: &str, message: String) -> PipelineError {
    PipelineError::Scene {
        field: format!("--records {spec}"),
        message,
    }
}

/// Columns selected by one spec (in map order); an error lists what exists when none match.
pub fn select<'a>(map: &'a HistoryMap, spec: &str) -> Result<Vec<&'a Column>, PipelineError> {
    if let Some(c) = map.columns.iter().find(|c| c.name == spec) {
        return Ok(vec![c]);
    }
    let mut parts = spec.split(':');
    let kind_s = parts.next().unwrap_or("");
    let kind: RecordKind = serde_json::from_value(serde_json::Value::String(kind_s.to_string()))
        .map_err(|_| {
            bad(
                spec,
                format!("`{kind_s}` is neither a column name nor a record kind"),
            )
        })?;
    let (mut grid, mut comp, mut gap) = (None, None, None);
    for p in parts {
        let (k, v) = p
            .split_once('=')
            .ok_or_else(|| bad(spec, format!("`{p}` is not key=value")))?;
        match k {
            "grid" => {
                grid = Some(
                    v.parse::<u64>()
                        .map_err(|_| bad(spec, format!("grid `{v}` is not an id")))?,
                )
            }
            "comp" => comp = Some(v.to_string()),
            "gap" => {
                gap = Some(
                    v.parse::<usize>()
                        .map_err(|_| bad(spec, format!("gap `{v}` is not an index")))?,
                )
            }
            _ => {
                return Err(bad(
                    spec,
                    format!("unknown filter `{k}` (use grid, comp, gap)"),
                ))
            }
        }
    }
    let sel: Vec<&Column> = map
        .columns
        .iter()
        .filter(|c| c.kind == kind)
        .filter(|c| grid.is_none_or(|g| c.grid == Some(g)))
        .filter(|c| {
            comp.as_ref()
                .is_none_or(|x| c.component.as_deref() == Some(x.as_str()))
        })
        .filter(|c| gap.is_none_or(|g| c.gap == Some(g)))
        .collect();
    if sel.is_empty() {
        let names: Vec<&str> = map.columns.iter().map(|c| c.name.as_str()).collect();
        return Err(bad(
            spec,
            format!("matches no column; the history has: {}", names.join(", ")),
        ));
    }
    Ok(sel)
}

/// Writes the CSV table of the selected records of the run in `run_dir`; returns (rows, columns).
pub fn run(run_dir: &Path, specs: &[String], out: &Path) -> Result<(usize, usize), PipelineError> {
    let map = HistoryMap::read(&run_dir.join("history_map.json"))?;
    let (rows, cols, data) = read_npy(&run_dir.join("history.npy"))?;
    if cols != map.n_columns {
        return Err(PipelineError::Input {
            path: run_dir.join("history.npy"),
            message: format!("{cols} columns, the map says {}", map.n_columns),
        });
    }
    let mut chosen: Vec<&Column> = vec![&map.columns[0]];
    let all = specs.is_empty() || specs.iter().any(|s| s == "all");
    if all {
        chosen = map.columns.iter().collect();
    } else {
        for s in specs {
            for c in select(&map, s)? {
                if !chosen.iter().any(|x| x.column == c.column) {
                    chosen.push(c);
                }
            }
        }
    }
    let mut text = String::new();
    let header: Vec<&str> = chosen.iter().map(|c| c.name.as_str()).collect();
    let _ = writeln!(text, "{}", header.join(","));
    for r in 0..rows {
        let line: Vec<String> = chosen
            .iter()
            .map(|c| format!("{:e}", data[r * cols + c.column]))
            .collect();
        let _ = writeln!(text, "{}", line.join(","));
    }
    crate::output::write_atomic(out, text.as_bytes())?;
    Ok((rows, chosen.len()))
}
