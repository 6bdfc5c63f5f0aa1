//! Scratch folders for the files a test or a tool writes (ELFs, QEMU's output,
//! images).

use std::ops::Deref;
use std::path::{Path, PathBuf};

/// An empty folder `NAME-PID` under the system's temporary folder, where one
/// test puts its files.
///
/// It is emptied when made, in case an earlier run of the same process id left
/// it, and removed when dropped, so that passing tests leave nothing behind. A
/// test that fails while the folder is alive keeps it for inspection: when the
/// folder is dropped while the thread panics, it stays and its path is printed
/// on standard error. A failure after the drop finds the folder gone.
///
/// It dereferences to its [`Path`], so `dir.join("firmware.elf")` names a file
/// in it. Keep the `ScratchDir` itself alive while the files are used.
#[derive(Debug)]
pub struct ScratchDir {
    path: PathBuf,
}

impl ScratchDir {
    /// Makes the empty folder `NAME-PID`.
    ///
    /// # Panics
    ///
    /// When the folder cannot be made, with its path and the system's error
    /// (see [`ScratchDir::try_new`]).
    pub fn new(name: &str) -> Self {
        Self::try_new(name).unwrap_or_else(|e| panic!("{e}"))
    }

    /// Makes the empty folder `NAME-PID`, or says which folder could not be
    /// made and why.
    pub fn try_new(name: &str) -> Result<Self, String> {
        let path = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        match std::fs::create_dir_all(&path) {
            Ok(()) => Ok(Self { path }),
            Err(e) => Err(format!(
                "cannot make the scratch folder {}: {e}",
                path.display()
            )),
        }
    }

    /// The folder's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Deref for ScratchDir {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for ScratchDir {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!(
                "the failing test's files are kept in {}",
                self.path.display()
            );
        } else {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ScratchDir;

    #[test]
    fn a_passing_test_leaves_no_folder() {
        let dir = ScratchDir::new("abuffer-scratch-pass");
        let path = dir.to_path_buf();
        std::fs::write(dir.join("a.txt"), "a").unwrap();
        assert!(path.join("a.txt").is_file());
        drop(dir);
        assert!(!path.exists());
    }

    #[test]
    fn a_failing_test_keeps_its_folder() {
        let path =
            std::env::temp_dir().join(format!("abuffer-scratch-fail-{}", std::process::id()));
        let kept = std::thread::spawn(|| {
            let dir = ScratchDir::new("abuffer-scratch-fail");
            std::fs::write(dir.join("b.txt"), "b").unwrap();
            panic!("the test fails");
        })
        .join();
        assert!(kept.is_err());
        assert!(path.join("b.txt").is_file());
        std::fs::remove_dir_all(&path).unwrap();
    }

    #[test]
    fn a_new_folder_starts_empty() {
        let first = ScratchDir::new("abuffer-scratch-empty");
        std::fs::write(first.join("c.txt"), "c").unwrap();
        std::mem::forget(first);
        let again = ScratchDir::new("abuffer-scratch-empty");
        assert_eq!(std::fs::read_dir(&*again).unwrap().count(), 0);
    }
}
