//! Progress and cancellation from Python: the pipeline's [`ProgressSink`] calling a Python
//! callable with one dict per event, and answering `cancelled()` from Ctrl-C
//! (`Python::check_signals`, effective on the main thread) or a callback that raised.

use crate::errors;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use squeal_pipeline::progress::{Event, Progress, ProgressSink};
use squeal_pipeline::PipelineError;
use std::sync::{Arc, Mutex};

/// Calls `callback({"kind", "task", "label", "message", "fraction", "bar"})` for every event;
/// remembers the first Python exception (from the callback or a signal handler) and then asks
/// the computation to stop.
pub struct PySink {
    callback: Option<Py<PyAny>>,
    error: Mutex<Option<PyErr>>,
}

impl PySink {
    fn keep(&self, e: PyErr) {
        let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
        if slot.is_none() {
            *slot = Some(e);
        }
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
        if self.failed() {
            return true;
        }
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => false,
            Err(e) => {
                self.keep(e);
                true
            }
        }
    }
}

/// The progress handle of one call and its sink (to fetch what stopped it).
pub struct Hook {
    sink: Arc<PySink>,
    pub progress: Progress,
}

impl Hook {
    pub fn new(callback: Option<Py<PyAny>>) -> Hook {
        let sink = Arc::new(PySink {
            callback,
            error: Mutex::new(None),
        });
        Hook {
            progress: Progress::new(sink.clone()),
            sink,
        }
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
