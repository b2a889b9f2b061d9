//! Progress and cancellation from Python: the pipeline's [`ProgressSink`] calling a Python
//! callable with one dict per event, and answering `cancelled()` from a flag. The computation
//! runs on a thread of its own while the calling thread waits and polls ([`Hook::poll`]):
//! `Python::check_signals` (Ctrl-C: effective when the caller is the main thread) every
//! 20 ms, and the caller's `cancel()` callable (a sweep's task) every 100 ms. A signal
//! handler's exception, a `cancel()` returning true, or a progress callback that raised sets
//! the flag; the library asks it inside its long loops (assembly, Craig–Bampton, Lanczos,
//! CEA sweeps, gmsh), so the run stops within a fraction of a second.

use crate::errors;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use squeal_pipeline::progress::{Event, Progress, ProgressSink};
use squeal_pipeline::PipelineError;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// Calls `callback({"kind", "task", "label", "message", "fraction", "bar"})` for every event;
/// remembers the first Python exception (from the callback or a signal handler) and then asks
/// the computation to stop.
pub struct PySink {
    callback: Option<Py<PyAny>>,
    /// `cancel()`: true asks the run to stop (polled by [`Hook::poll`]).
    cancel: Option<Py<PyAny>>,
    error: Mutex<Option<PyErr>>,
    stop: AtomicBool,
}

impl PySink {
    fn keep(&self, e: PyErr) {
        let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
        if slot.is_none() {
            *slot = Some(e);
        }
        self.stop.store(true, Ordering::SeqCst);
    }

    fn failed(&self) -> bool {
        self.error
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .is_some()
    }
}

impl ProgressSink for PySink {
    fn event(&self, task: u64, event: Event<'_>) {
        let Some(cb) = &self.callback else { return };
        if self.failed() {
            return;
        }
        let r = Python::attach(|py| -> PyResult<()> {
            let d = PyDict::new(py);
            d.set_item("task", task)?;
            let (kind, label, message, fraction, bar) = match event {
                Event::Begin { label, bar } => ("begin", label, "", None, bar),
                Event::Update { fraction, message } => ("update", "", message, fraction, false),
                Event::End { message } => ("end", "", message, None, false),
                Event::Info { line } => ("info", "", line, None, false),
            };
            d.set_item("kind", kind)?;
            d.set_item("label", label)?;
            d.set_item("message", message)?;
            d.set_item("fraction", fraction)?;
            d.set_item("bar", bar)?;
            cb.call1(py, (d,))?;
            Ok(())
        });
        if let Err(e) = r {
            self.keep(e);
        }
    }

    fn cancelled(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// The progress handle of one call and its sink (to fetch what stopped it).
pub struct Hook {
    sink: Arc<PySink>,
    pub progress: Progress,
}

impl Hook {
    pub fn new(callback: Option<Py<PyAny>>) -> Hook {
        Hook::with_cancel(callback, None)
    }

    /// A hook whose run also stops when `cancel()` returns true.
    pub fn with_cancel(callback: Option<Py<PyAny>>, cancel: Option<Py<PyAny>>) -> Hook {
        let sink = Arc::new(PySink {
            callback,
            cancel,
            error: Mutex::new(None),
            stop: AtomicBool::new(false),
        });
        Hook {
            progress: Progress::new(sink.clone()),
            sink,
        }
    }

    /// Runs Python's signal handlers (a KeyboardInterrupt stops the run) and, with
    /// `ask_cancel`, the `cancel()` callable; called by the waiting thread.
    pub fn poll(&self, ask_cancel: bool) {
        if self.sink.stop.load(Ordering::Relaxed) {
            return;
        }
        Python::attach(|py| {
            if let Err(e) = py.check_signals() {
                self.sink.keep(e);
                return;
            }
            if let (true, Some(c)) = (ask_cancel, &self.sink.cancel) {
                match c.call0(py).and_then(|v| v.is_truthy(py)) {
                    Ok(true) => self.sink.stop.store(true, Ordering::SeqCst),
                    Ok(false) => {}
                    Err(e) => self.sink.keep(e),
                }
            }
        });
    }

    /// The Python exception of a failed computation: the callback's or the signal handler's
    /// (KeyboardInterrupt) when one stopped it, else the pipeline error's.
    pub fn error(&self, e: &PipelineError) -> PyErr {
        let kept = self
            .sink
            .error
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take();
        match (e, kept) {
            (PipelineError::Cancelled { .. }, Some(py_err)) => py_err,
            _ => errors::to_py(e),
        }
    }

    /// A computation that succeeded may still have seen a callback raise (after its last
    /// cancellation check): raise it then.
    pub fn finish(&self) -> PyResult<()> {
        match self
            .sink
            .error
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take()
        {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}
