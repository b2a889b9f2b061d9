//! A caller's request to stop a long computation (Ctrl-C in the command line or in Python).
//!
//! The library crates know nothing of progress bars or signals: the caller passes an
//! [`Interrupt`] in the options of a long computation — a gmsh run
//! (`GmshOptions::interrupt`: the child is killed), the assembly and the modal solve
//! (`squeal_fe`, which re-exports this type), the Craig–Bampton reduction
//! (`squeal_reduction`) — a callback answering "stop now?", and the computation asks it
//! between units of work (a poll of the child, a chunk of elements, a Lanczos block step).
//! When it answers yes the computation returns its crate's `Interrupted` error with what it
//! was doing; nothing partial is returned.

use std::sync::Arc;

/// A callback asked between units of work; `true` means stop. The default never stops.
///
/// It is not part of the options' value: two options that differ only by their interrupt are
/// equal, and options hold it as a `#[serde(skip)]` field (never serialised; read as "never").
#[derive(Clone, Default)]
pub struct Interrupt(Option<Arc<dyn Fn() -> bool + Send + Sync>>);

impl Interrupt {
    /// An interrupt asking `f` (cheap: it is called often, from several threads).
    pub fn new(f: impl Fn() -> bool + Send + Sync + 'static) -> Self {
        Interrupt(Some(Arc::new(f)))
    }

    /// Never stops.
    pub fn never() -> Self {
        Interrupt(None)
    }

    /// True when the caller asked to stop.
    pub fn is_set(&self) -> bool {
        self.0.as_ref().is_some_and(|f| f())
    }
}

impl std::fmt::Debug for Interrupt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() {
            "Interrupt(callback)"
        } else {
            "Interrupt(never)"
        })
    }
}

impl PartialEq for Interrupt {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};

    #[test]
    fn asks_the_callback_and_is_no_part_of_the_value() {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        let i = Interrupt::new(move || f.load(Ordering::Relaxed));
        assert!(!i.is_set());
        flag.store(true, Ordering::Relaxed);
        assert!(i.is_set() && i.clone().is_set());
        assert!(!Interrupt::never().is_set());
        assert_eq!(i, Interrupt::never());
    }
}
