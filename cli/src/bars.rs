//! The command line's progress: the library's events drawn as indicatif spinners and bars on
//! stderr when it is a terminal, information lines printed above them (or plainly on stderr
//! when it is not: a pipe, a file, a batch job), and Ctrl-C turned into a cancellation.

use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use squeal_pipeline::progress::{Event, ProgressSink};
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// Set by the first Ctrl-C (SIGINT): the running computation stops at its next check and the
/// command exits with [`EXIT_CANCELLED`].
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Exit status of a run stopped by Ctrl-C (128 + SIGINT, as a shell reports it).
pub const EXIT_CANCELLED: u8 = 130;

/// Installs the Ctrl-C handler: the first SIGINT asks the computation to stop (it checks
/// inside its long loops, kills gmsh, and returns `Cancelled` without writing a partial
/// result); a second one exits at once with [`EXIT_CANCELLED`].
pub fn handle_ctrl_c() {
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            std::process::exit(EXIT_CANCELLED as i32);
        }
    });
}

/// Prints nothing; answers the cancellation (`-q`).
pub struct Quiet;

impl ProgressSink for Quiet {
    fn event(&self, _: u64, _: Event<'_>) {}
    fn cancelled(&self) -> bool {
        INTERRUPTED.load(Ordering::Relaxed)
    }
}

/// Draws every task as a spinner (steps) or a bar (fractions).
#[derive(Default)]
pub struct Bars {
    multi: MultiProgress,
    live: Mutex<HashMap<u64, ProgressBar>>,
}

impl ProgressSink for Bars {
    fn cancelled(&self) -> bool {
        INTERRUPTED.load(Ordering::Relaxed)
    }

    fn event(&self, task: u64, event: Event<'_>) {
        let mut live = self.live.lock().unwrap_or_else(|e| e.into_inner());
        match event {
            Event::Begin { label, bar } => {
                let b = if bar {
                    let b = ProgressBar::new(1000);
                    b.set_style(
                        ProgressStyle::with_template("{bar:40} {msg} [{elapsed}]")
                            .unwrap_or_else(|_| ProgressStyle::default_bar()),
                    );
                    b
                } else {
                    let b = ProgressBar::new_spinner();
                    b.set_style(
                        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
                            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
                    );
                    b.enable_steady_tick(Duration::from_millis(120));
                    b
                };
                b.set_message(label.to_string());
                live.insert(task, self.multi.add(b));
            }
            Event::Update { fraction, message } => {
                if let Some(b) = live.get(&task) {
                    if let Some(f) = fraction {
                        b.set_position((1000.0 * f) as u64);
                    }
                    b.set_message(message.to_string());
                }
            }
            Event::End { message } => {
                if let Some(b) = live.remove(&task) {
                    b.finish_with_message(message.to_string());
                }
            }
            Event::Info { line } => {
                // `MultiProgress::println` prints nothing when stderr is not a terminal.
                if self.multi.is_hidden() {
                    eprintln!("{line}");
                } else {
                    let _ = self.multi.println(line);
                }
            }
        }
    }
}
