//! The fuzz driver: proptest's `TestRunner` over a strategy of inputs, with the number of cases
//! (or a time budget) from the environment, a watchdog that fails a case running too long, and
//! failing inputs written to disk for the regression corpus.
//!
//! - `SQUEAL_FUZZ_CASES=N`: cases per target (default: each target's CI count);
//! - `SQUEAL_FUZZ_SECONDS=S`: run each target for S seconds instead (batches of cases with
//!   fresh random seeds until the time is up);
//! - `SQUEAL_FUZZ_SEED=K`: the base seed (default fixed, so CI runs are reproducible);
//! - `SQUEAL_FUZZ_CASE_SECONDS=S`: a case running longer is a hang (default 60): its input is
//!   written beside the reports and the process aborts.
//!
//! A panic in a case fails the test (proptest catches it only to shrink the input first); so
//! does a check's `Err` (an error that does not name its input, or accepted input that breaks
//! a documented guarantee).

use proptest::strategy::Strategy;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestError, TestRng, TestRunner};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, OnceLock};
use std::thread::ThreadId;
use std::time::{Duration, Instant};

/// What a reader did with an input that broke no property.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Read (and, where checked, its result met the reader's guarantees).
    Accepted,
    /// Refused with an error naming the input.
    Rejected,
}

/// Counts of one target's run.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Report {
    pub target: String,
    /// Cases run (shrinking steps of a failure included).
    pub cases: u64,
    pub accepted: u64,
    pub rejected: u64,
    /// Panics, property failures and hangs (a failure also fails the test).
    pub failures: u64,
    pub seconds: f64,
    pub base_seed: u64,
}

struct Running {
    start: Instant,
    target: &'static str,
    bytes: Vec<u8>,
    how: String,
    out: PathBuf,
}

fn running() -> &'static Mutex<HashMap<ThreadId, Running>> {
    static R: OnceLock<Mutex<HashMap<ThreadId, Running>>> = OnceLock::new();
    R.get_or_init(Default::default)
}

fn env_f64(name: &str) -> Option<f64> {
    std::env::var(name).ok().and_then(|v| v.trim().parse().ok())
}

/// Starts (once) the thread that aborts the process when a case runs too long.
fn start_watchdog() {
    static W: OnceLock<()> = OnceLock::new();
    W.get_or_init(|| {
        let limit = Duration::from_secs_f64(env_f64("SQUEAL_FUZZ_CASE_SECONDS").unwrap_or(60.0));
        std::thread::spawn(move || loop {
            std::thread::sleep(Duration::from_millis(200));
            let map = running().lock().unwrap_or_else(|e| e.into_inner());
            if let Some(r) = map.values().find(|r| r.start.elapsed() > limit) {
                let p = r.out.join(format!("hang-{}.bin", r.target));
                let _ = std::fs::create_dir_all(&r.out);
                let _ = std::fs::write(&p, &r.bytes);
                eprintln!(
                    "fuzz {}: a case ran longer than {:?} (a hang): {} — input written to {}",
                    r.target,
                    limit,
                    r.how,
                    p.display()
                );
                std::process::abort();
            }
        });
    });
}

/// 32 seed bytes from the base seed, the target's name and the batch number.
fn seed_bytes(base: u64, name: &str, batch: u64) -> [u8; 32] {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325 ^ base;
    let mut out = [0u8; 32];
    for (k, chunk) in out.chunks_mut(8).enumerate() {
        for b in name.bytes().chain(batch.to_le_bytes()).chain([k as u8]) {
            h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
        chunk.copy_from_slice(&h.to_le_bytes());
    }
    out
}

/// Runs `check` on inputs drawn from `strategy`: `default_cases` of them, or as the
/// environment says (module documentation). `bytes_of` gives the bytes written for a failing
/// or hanging case. Panics (failing the test) on the first failure, after shrinking it.
pub fn fuzz<T, S>(
    name: &'static str,
    out: PathBuf,
    strategy: S,
    default_cases: u32,
    bytes_of: impl Fn(&T) -> Vec<u8>,
    check: impl Fn(&T) -> Result<Outcome, String>,
) -> Report
where
    S: Strategy<Value = T>,
    T: std::fmt::Debug + Clone,
{
    start_watchdog();
    let seconds = env_f64("SQUEAL_FUZZ_SECONDS");
    let cases = std::env::var("SQUEAL_FUZZ_CASES")
        .ok()
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(default_cases);
    let base_seed = std::env::var("SQUEAL_FUZZ_SEED")
        .ok()
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(0x5eed_2024);
    let (accepted, rejected, total) = (AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0));
    let started = Instant::now();
    let me = std::thread::current().id();
    let test = |input: T| -> Result<(), TestCaseError> {
        running().lock().unwrap_or_else(|e| e.into_inner()).insert(
            me,
            Running {
                start: Instant::now(),
                target: name,
                bytes: bytes_of(&input),
                how: format!("{input:?}"),
                out: out.clone(),
            },
        );
        total.fetch_add(1, Ordering::Relaxed);
        let r = check(&input);
        running()
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .remove(&me);
        match r {
            Ok(Outcome::Accepted) => {
                accepted.fetch_add(1, Ordering::Relaxed);
                Ok(())
            }
            Ok(Outcome::Rejected) => {
                rejected.fetch_add(1, Ordering::Relaxed);
                Ok(())
            }
            Err(why) => Err(TestCaseError::fail(why)),
        }
    };
    let mut batch = 0u64;
    loop {
        let n = match seconds {
            Some(_) => 500,
            None => cases,
        };
        let config = Config {
            cases: n,
            failure_persistence: None,
            max_shrink_iters: 1000,
            max_shrink_time: 120_000,
            ..Config::default()
        };
        let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes(base_seed, name, batch));
        let mut runner = TestRunner::new_with_rng(config, rng);
        if let Err(e) = runner.run(&strategy, test) {
            let _ = std::fs::create_dir_all(&out);
            let (why, input) = match &e {
                TestError::Fail(why, input) => (why.to_string(), Some(input)),
                TestError::Abort(why) => (why.to_string(), None),
            };
            let file = input.map(|i| {
                let p = out.join(format!("failure-{name}-seed{base_seed}-batch{batch}.bin"));
                let _ = std::fs::write(&p, bytes_of(i));
                p
            });
            panic!(
                "fuzz {name}: failure after {} cases: {why}\nminimal input: {input:?}\nwritten to: {file:?}",
                total.load(Ordering::Relaxed)
            );
        }
        batch += 1;
        match seconds {
            Some(s) if started.elapsed().as_secs_f64() < s => continue,
            _ => break,
        }
    }
    let report = Report {
        target: name.to_string(),
        cases: total.load(Ordering::Relaxed),
        accepted: accepted.load(Ordering::Relaxed),
        rejected: rejected.load(Ordering::Relaxed),
        failures: 0,
        seconds: started.elapsed().as_secs_f64(),
        base_seed,
    };
    eprintln!(
        "fuzz {name}: {} cases ({} accepted, {} rejected), 0 failures, {:.1} s",
        report.cases, report.accepted, report.rejected, report.seconds
    );
    let _ = std::fs::create_dir_all(&out);
    let _ = std::fs::write(
        out.join(format!("{name}.report.json")),
        serde_json::to_string_pretty(&report).unwrap_or_default(),
    );
    report
}
