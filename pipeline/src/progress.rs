//! Progress reporting on stderr (indicatif), silenced by `-q`.

use indicatif::{ProgressBar, ProgressStyle};
use std::time::Duration;

/// Reports stages of a run; quiet reporters print nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Progress {
    pub quiet: bool,
}

impl Progress {
    /// A spinner for a step the user waits on; finish it with [`Step::done`].
    pub fn step(&self, message: impl Into<String>) -> Step {
        if self.quiet {
            return Step { bar: None };
        }
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.set_message(message.into());
        bar.enable_steady_tick(Duration::from_millis(120));
        Step { bar: Some(bar) }
    }

    /// A line of information.
    pub fn info(&self, line: impl AsRef<str>) {
        if !self.quiet {
            eprintln!("{}", line.as_ref());
        }
    }
}

/// One running step.
pub struct Step {
    bar: Option<ProgressBar>,
}

impl Step {
    /// Ends the step with a final message.
    pub fn done(self, message: impl Into<String>) {
        if let Some(bar) = self.bar {
            bar.finish_with_message(message.into());
        }
    }
}
