//! `study.toml`: the base scene and the table of cases of `squeal reproduce`.

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_contact::FrictionLaw;
use std::path::{Path, PathBuf};

use squeal_solver::Real;

/// A study: one base scene, the cases that change it, and the comparison figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    /// Base scene, relative to the study file (required).
    pub base: PathBuf,
    /// Scene settings applied to the base before every case, as `--set` writes them
    /// (`"contact.0.normal_stiffness=1e6"`; default: none). A study of a variant of a shipped
    /// scene says here what differs, and its report prints them. The command line's `--set`
    /// comes after these.
    #[serde(default)]
    pub set: Vec<String>,
    /// A run stops after `step_cap × TF / h_max` steps when the base scene sets `h_max`
    /// (default: 1.6).
    #[serde(default = "default_step_cap")]
    pub step_cap: Real,
    /// Run `squeal cea` at every case's steady sliding state (default: true).
    #[serde(default = "yes")]
    pub cea: bool,
    /// Amplitude of the squealing root (the verdict's deciding root, norm over the output
    /// velocity DOFs) that marks the squeal onset time (default: 0.1, model units of velocity).
    #[serde(default = "default_onset")]
    pub onset_level: Real,
    /// Complex eigenvalues of the base scene over a range of constant μ (default: none): which
    /// mode pairs couple at which critical μ, reported with a root locus.
    pub cea_sweep: Option<MuRange>,
    /// Markdown put into the report under "The model" (default: none): what the base scene is
    /// and why its design is what it is.
    pub notes: Option<String>,
    /// The cases (required, at least one).
    pub cases: Vec<CaseSpec>,
    /// Comparison figures (default: none).
    #[serde(default)]
    pub figures: Vec<FigureSpec>,
    /// Folder of the study file (not read from the file).
    #[serde(skip)]
    pub base_dir: PathBuf,
}

fn default_step_cap() -> Real {
    1.6
}
fn yes() -> bool {
    true
}
fn default_onset() -> Real {
    0.1
}

/// A range of friction coefficients: `count` values from `first` to `last`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MuRange {
    pub first: Real,
    pub last: Real,
    pub count: usize,
}

/// One row of the paper's table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    /// Case number (required, unique).
    pub case: u32,
    /// RTOL1 (default: the base scene's).
    pub rtol1: Option<Real>,
    /// TLOAD (default: the base scene's).
    pub tload: Option<Real>,
    /// Friction law μ (default: the base scene's).
    pub friction: Option<FrictionLaw>,
    /// Overall structural damping G (default: the base scene's).
    pub g: Option<Real>,
    /// W3 (default: the base scene's).
    pub w3: Option<Real>,
    /// Preload P0 of every contact pair (default: the base scene's).
    pub p0: Option<Real>,
    /// TF, the final time (default: the base scene's).
    pub tf: Option<Real>,
    /// Further `key=value` overrides of this case (default: none).
    #[serde(default)]
    pub set: Vec<String>,
}

/// A figure comparing the response of several cases.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FigureSpec {
    /// File stem (required).
    pub name: String,
    /// Caption (required).
    pub title: String,
    /// Cases drawn (required).
    pub cases: Vec<u32>,
    /// Zoom on the last this many seconds of the shortest run (default: none = whole run).
    pub last: Option<Real>,
}

fn bad(field: &str, message: String) -> PipelineError {
    PipelineError::Scene {
        field: format!("study.{field}"),
        message,
    }
}

impl StudySpec {
    /// Reads and validates a study file.
    pub fn load(path: &Path) -> Result<Self, PipelineError> {
        let text = std::fs::read_to_string(path).map_err(|source| PipelineError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut s: StudySpec = toml::from_str(&text).map_err(|e| PipelineError::SceneParse {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        s.base_dir = path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from("."));
        s.validate()?;
        Ok(s)
    }

    /// Checks the cases are unique and the values in range; errors name the case.
    pub fn validate(&self) -> Result<(), PipelineError> {
        if self.cases.is_empty() {
            return Err(bad("cases", "no case".into()));
        }
        if !(self.step_cap.is_finite() && self.step_cap >= 1.0) {
            return Err(bad("step_cap", format!("{} must be >= 1", self.step_cap)));
        }
        if let Some(r) = &self.cea_sweep {
            if !(r.first.is_finite() && r.last.is_finite() && r.first >= 0.0 && r.last > r.first)
                || r.count < 2
            {
                return Err(bad(
                    "cea_sweep",
                    format!(
                        "first = {}, last = {}, count = {}: need 0 <= first < last and count >= 2",
                        r.first, r.last, r.count
                    ),
                ));
            }
        }
        let mut seen = std::collections::BTreeSet::new();
        for c in &self.cases {
            if !seen.insert(c.case) {
                return Err(bad("cases", format!("case {} is listed twice", c.case)));
            }
        }
        for f in &self.figures {
            if let Some(c) = f.cases.iter().find(|c| !seen.contains(c)) {
                return Err(bad(
                    &format!("figures[{}].cases", f.name),
                    format!("no case {c}"),
                ));
            }
        }
        Ok(())
    }

    /// The base scene's path.
    pub fn base_path(&self) -> PathBuf {
        if self.base.is_absolute() {
            self.base.clone()
        } else {
            self.base_dir.join(&self.base)
        }
    }
}

impl CaseSpec {
    /// The `key=value` overrides that turn the base scene into this case (`n_contact` pairs).
    pub fn overrides(&self, n_contact: usize) -> Result<Vec<String>, PipelineError> {
        let mut out = Vec::new();
        let mut num = |k: &str, v: Option<Real>| {
            if let Some(v) = v {
                out.push(format!("{k}={v:e}"));
            }
        };
        num("transient.rtol1", self.rtol1);
        num("loads.tload", self.tload);
        num("damping.g", self.g);
        num("damping.w3", self.w3);
        num("transient.tfinal", self.tf);
        for i in 0..n_contact {
            num(&format!("contact.{i}.p0"), self.p0);
        }
        if let Some(law) = &self.friction {
            let v = toml::Value::try_from(law).map_err(|e| {
                bad(
                    &format!("cases[case = {}].friction", self.case),
                    e.to_string(),
                )
            })?;
            out.push(format!("friction.law={v}"));
        }
        out.extend(self.set.iter().cloned());
        Ok(out)
    }
}

/// μ as the paper's table writes it: `0.7`, `0.7-0.0005V`.
pub fn mu_label(law: &FrictionLaw) -> String {
    match law {
        FrictionLaw::Constant { mu } => format!("{mu}"),
        FrictionLaw::LinearSpeed { mu0, slope } if *slope < 0.0 => format!("{mu0}-{}V", -slope),
        FrictionLaw::LinearSpeed { mu0, slope } => format!("{mu0}+{slope}V"),
        other => serde_json::to_string(other).unwrap_or_else(|_| "?".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's table (section 3) parses and its case 2 turns into the expected overrides.
    #[test]
    fn example_study_parses_and_case_overrides_apply() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/sample-brake/study.toml");
        let s = StudySpec::load(&path).unwrap();
        assert_eq!(s.cases.len(), 8);
        let c2 = &s.cases[1];
        let o = c2.overrides(2).unwrap();
        assert!(o.contains(&"transient.rtol1=1e-4".to_string()), "{o:?}");
        let scene = crate::Scene::load(&s.base_path(), &o).unwrap();
        assert_eq!(scene.transient.as_ref().unwrap().rtol1, 1e-4);
        assert_eq!(
            mu_label(&scene.friction.as_ref().unwrap().law),
            "0.7-0.0005V"
        );
        let c8 = s.cases[7].overrides(2).unwrap();
        let scene8 = crate::Scene::load(&s.base_path(), &c8).unwrap();
        assert_eq!(scene8.contact[1].p0, 0.01);
        assert_eq!(scene8.damping.as_ref().unwrap().w3, 100.0);
    }
}
