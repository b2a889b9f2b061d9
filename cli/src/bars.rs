//! The command line's progress: the library's events drawn as indicatif spinners and bars on
//! stderr, and information lines printed above them.

use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use squeal_pipeline::progress::{Event, ProgressSink};
use std::collections::HashMap;
use std::sync::Mutex;
use std::time::Duration;

/// Draws every task as a spinner (steps) or a bar (fractions).
#[derive(Default)]
pub struct Bars {
    multi: MultiProgress,
    live: Mutex<HashMap<u64, ProgressBar>>,
}

impl ProgressSink for Bars {
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
                let _ = self.multi.println(line);
            }
        }
    }
}
