//! An advisory lock per cache entry, so that processes sharing a cache folder (a Dask cluster,
//! two `squeal sweep` runs) build each model and each component reduction once.
//!
//! The lock is an exclusive `flock` (std's `File::lock` family) on the file `.lock-<key>`
//! beside the entry; whoever holds it reads the entry, or builds and stores it. A second
//! process asking for the same key waits (polling every 50 ms, so that Ctrl-C still stops it)
//! and then reads what the first stored. The operating system releases the lock when its
//! holder ends, however it ends (a killed builder leaves no stale lock); the lock files
//! themselves are left in place (empty; removing one while another process waits on it would
//! let a third process lock a new file of the same name). Where the file system cannot lock
//! (some network file systems), the cache works unlocked as before (entries are still written
//! atomically and correct; a build may be repeated) and says so in a warning.

use crate::error::PipelineError;
use crate::progress::Progress;
use std::fs::{File, OpenOptions, TryLockError};
use std::path::Path;
use std::time::Duration;

/// How often a waiting process retries the lock (and checks for Ctrl-C).
const POLL: Duration = Duration::from_millis(50);

/// A held lock (released on drop), or the reason none could be taken.
#[derive(Debug)]
pub enum EntryLock {
    Held(#[allow(dead_code)] File),
    /// The file system refused to lock: the caller goes on unlocked (the message says why).
    Unsupported(String),
}

/// Takes the lock of entry `name` in `root` (created if needed), waiting while another
/// process holds it; `what` names the entry in the progress line and the cancellation.
pub fn lock_entry(
    root: &Path,
    name: &str,
    what: &str,
    progress: &Progress,
) -> Result<EntryLock, PipelineError> {
    std::fs::create_dir_all(root).map_err(|source| PipelineError::Io {
        path: root.to_path_buf(),
        source,
    })?;
    let path = root.join(format!(".lock-{name}"));
    let file = match OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&path)
    {
        Ok(f) => f,
        Err(e) => return Ok(EntryLock::Unsupported(format!("{}: {e}", path.display()))),
    };
    let mut waiting = false;
    loop {
        match file.try_lock() {
            Ok(()) => return Ok(EntryLock::Held(file)),
            Err(TryLockError::WouldBlock) => {
                if !waiting {
                    progress.info(format!(
                        "{what}: another process is building it; waiting for its entry"
                    ));
                    waiting = true;
                }
                progress.check(&format!("waiting for the cache entry of {what}"))?;
                std::thread::sleep(POLL);
            }
            Err(TryLockError::Error(e)) => {
                return Ok(EntryLock::Unsupported(format!(
                    "{} could not be locked ({e}): the cache works unlocked, and another \
                     process may build the same entry",
                    path.display()
                )))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A second lock of the same key waits until the first is dropped; another key does not.
    #[test]
    fn a_second_holder_waits_for_the_first() {
        let root = std::env::temp_dir().join(format!("squeal-lock-{}", std::process::id()));
        let q = Progress::quiet();
        let first = lock_entry(&root, "k1", "model k1", &q).unwrap();
        assert!(matches!(first, EntryLock::Held(_)));
        assert!(matches!(
            lock_entry(&root, "k2", "model k2", &q).unwrap(),
            EntryLock::Held(_)
        ));
        let (tx, rx) = std::sync::mpsc::channel();
        let r = root.clone();
        let t = std::thread::spawn(move || {
            let l = lock_entry(&r, "k1", "model k1", &Progress::quiet()).unwrap();
            tx.send(()).unwrap();
            drop(l);
        });
        // Still held: the second caller has not got it after a few polls.
        assert!(rx.recv_timeout(Duration::from_millis(300)).is_err());
        drop(first);
        rx.recv_timeout(Duration::from_secs(10))
            .expect("the lock passes on when dropped");
        t.join().unwrap();
        std::fs::remove_dir_all(&root).ok();
    }
}
