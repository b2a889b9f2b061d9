//! Progress and cancellation: one hook shared by the command line and the Python package.
//!
//! A long computation reports what it is doing through a [`Progress`] handle: spinner steps
//! ([`Progress::step`]), bars with a known fraction ([`Progress::bar`], the transient), and lines
//! of information ([`Progress::info`]). The handle forwards them as [`Event`]s to a
//! [`ProgressSink`] — the CLI's indicatif bars, a Python callback (tqdm) — or drops them when
//! quiet. The same sink is asked, between units of work (transient chunks, sweep values, study
//! cases), whether the caller wants to stop ([`Progress::check`]): a cancelled run ends with
//! [`PipelineError::Cancelled`] after flushing what it had written.

use crate::error::PipelineError;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// What happened to one task.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Event<'a> {
    /// A task starts. `bar`: it reports fractions (else it is a spinner).
    Begin { label: &'a str, bar: bool },
    /// A task moved: `fraction` of it is done (bars), `message` says where it is.
    Update {
        fraction: Option<f64>,
        message: &'a str,
    },
    /// A task ended with a final message.
    End { message: &'a str },
    /// A line of information (not tied to a task).
    Info { line: &'a str },
}

/// Receives progress events and answers whether to stop. Implemented by the CLI (indicatif)
/// and the Python package (a callback); must be shareable between threads (a study runs cases
/// in parallel).
pub trait ProgressSink: Send + Sync {
    /// One event of task `task` (ids are unique within a process; `Info` events carry 0).
    fn event(&self, task: u64, event: Event<'_>);
    /// True when the caller asks the computation to stop (default: never).
    fn cancelled(&self) -> bool {
        false
    }
}

/// A cheap, cloneable handle on a [`ProgressSink`]; [`Progress::quiet`] reports nothing and
/// never cancels.
#[derive(Clone, Default)]
pub struct Progress {
    sink: Option<Arc<dyn ProgressSink>>,
    /// Pass events on (false: only cancellation is forwarded; parallel cases run quiet).
    verbose: bool,
}

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Progress")
            .field("sink", &self.sink.is_some())
            .field("verbose", &self.verbose)
            .finish()
    }
}

static NEXT_TASK: AtomicU64 = AtomicU64::new(1);

impl Progress {
    /// Reports nothing, never cancels.
    pub fn quiet() -> Self {
        Self::default()
    }

    /// Reports to `sink`.
    pub fn new(sink: Arc<dyn ProgressSink>) -> Self {
        Self {
            sink: Some(sink),
            verbose: true,
        }
    }

    /// The same cancellation, no events (for work done in parallel, whose bars would mix).
    pub fn silenced(&self) -> Self {
        Self {
            sink: self.sink.clone(),
            verbose: false,
        }
    }

    fn emit(&self, task: u64, e: Event<'_>) {
        if let (true, Some(s)) = (self.verbose, &self.sink) {
            s.event(task, e);
        }
    }

    fn begin(&self, label: &str, bar: bool) -> u64 {
        let id = NEXT_TASK.fetch_add(1, Ordering::Relaxed);
        self.emit(id, Event::Begin { label, bar });
        id
    }

    /// A step the user waits on (a spinner); finish it with [`Step::done`].
    pub fn step(&self, message: impl Into<String>) -> Step {
        let message = message.into();
        Step {
            id: self.begin(&message, false),
            progress: self.clone(),
        }
    }

    /// A task with a known fraction done (0 → 1); move it with [`Bar::set`].
    pub fn bar(&self, label: impl AsRef<str>) -> Bar {
        Bar {
            id: self.begin(label.as_ref(), true),
            progress: self.clone(),
        }
    }

    /// A line of information.
    pub fn info(&self, line: impl AsRef<str>) {
        self.emit(
            0,
            Event::Info {
                line: line.as_ref(),
            },
        );
    }

    /// True when the caller asked to stop.
    pub fn is_cancelled(&self) -> bool {
        self.sink.as_ref().is_some_and(|s| s.cancelled())
    }

    /// The same cancellation as the library crates ask it inside their long loops (assembly,
    /// Craig–Bampton, Lanczos): a callback asking the sink; never, without a sink.
    pub fn interrupt(&self) -> squeal_fe::Interrupt {
        match &self.sink {
            Some(_) => {
                let p = self.silenced();
                squeal_fe::Interrupt::new(move || p.is_cancelled())
            }
            None => squeal_fe::Interrupt::never(),
        }
    }

    /// [`Progress::interrupt`] for `squeal_solver` (CEA Lanczos, refinement, sweeps).
    pub fn solver_interrupt(&self) -> squeal_solver::Interrupt {
        match &self.sink {
            Some(_) => {
                let p = self.silenced();
                squeal_solver::Interrupt::new(move || p.is_cancelled())
            }
            None => squeal_solver::Interrupt::never(),
        }
    }

    /// `Err(PipelineError::Cancelled)` when the caller asked to stop; `what` says where.
    pub fn check(&self, what: &str) -> Result<(), PipelineError> {
        if self.is_cancelled() {
            Err(PipelineError::Cancelled { what: what.into() })
        } else {
            Ok(())
        }
    }
}

/// One running spinner step.
pub struct Step {
    id: u64,
    progress: Progress,
}

impl Step {
    /// Ends the step with a final message.
    pub fn done(self, message: impl AsRef<str>) {
        self.progress.emit(
            self.id,
            Event::End {
                message: message.as_ref(),
            },
        );
    }
}

/// One running bar.
pub struct Bar {
    id: u64,
    progress: Progress,
}

impl Bar {
    /// Moves the bar to `fraction` (clamped to 0..1) and shows `message()` (not evaluated when
    /// nobody listens).
    pub fn set(&self, fraction: f64, message: impl FnOnce() -> String) {
        if self.progress.verbose && self.progress.sink.is_some() {
            let m = message();
            self.progress.emit(
                self.id,
                Event::Update {
                    fraction: Some(fraction.clamp(0.0, 1.0)),
                    message: &m,
                },
            );
        }
    }

    /// Ends the bar.
    pub fn finish(self, message: impl AsRef<str>) {
        self.progress.emit(
            self.id,
            Event::End {
                message: message.as_ref(),
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    #[derive(Default)]
    struct Log {
        events: Mutex<Vec<String>>,
        stop: std::sync::atomic::AtomicBool,
    }
    impl ProgressSink for Log {
        fn event(&self, task: u64, e: Event<'_>) {
            self.events.lock().unwrap().push(format!("{task}:{e:?}"));
        }
        fn cancelled(&self) -> bool {
            self.stop.load(Ordering::Relaxed)
        }
    }

    /// Events reach the sink in order with one id per task; silenced handles forward only the
    /// cancellation; `check` turns it into the pipeline's error.
    #[test]
    fn events_and_cancellation() {
        let log = Arc::new(Log::default());
        let p = Progress::new(log.clone());
        let s = p.step("meshing");
        s.done("meshed");
        let b = p.bar("transient");
        b.set(2.0, || "t = 1".into());
        b.finish("done");
        p.silenced().info("hidden");
        let ev = log.events.lock().unwrap().clone();
        assert_eq!(ev.len(), 5, "{ev:?}");
        assert!(
            ev[0].contains("Begin") && ev[0].contains("meshing"),
            "{ev:?}"
        );
        assert!(ev[3].contains("fraction: Some(1.0)"), "{ev:?}");
        let id = |s: &str| s.split(':').next().unwrap().to_string();
        assert_eq!(id(&ev[0]), id(&ev[1]));
        assert_ne!(id(&ev[0]), id(&ev[2]));
        assert!(p.check("x").is_ok());
        log.stop.store(true, Ordering::Relaxed);
        assert!(p.silenced().is_cancelled());
        let e = p.check("transient").unwrap_err();
        assert!(e.to_string().contains("transient"), "{e}");
        assert!(!Progress::quiet().is_cancelled());
    }
}
