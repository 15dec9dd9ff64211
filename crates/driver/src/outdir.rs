//! Output directories written as a whole: one command's files appear together or not at all.
//!
//! A command (`solve`, `compare`, `sweep`) writes a *set* of files into one directory:
//! `result.json`, `solution.vtu`, `deformed.svg` and (with contact rows) `pressure.svg`; `compare.json` and `compare.csv`;
//! `sweep.csv` and its plots (with `--shard`, also `shard.json`; with `--vtu`, `solutions.pvd`, the
//! files in `solutions/` and, per shard, `displacements/` being sets of their own, each with its
//! own lock).  Writing each file atomically is not enough: a failure between two files, or two
//! runs into the same directory, would leave files of different runs side by side.  So:
//!
//! 1. [`DirLock::acquire`] takes an advisory, exclusive, non-blocking lock on the directory
//!    (created if missing) for the whole write.  A second run that finds it held refuses at once
//!    with [`OutputError::Locked`], naming the directory.  On Unix the lock is `flock(2)` on the
//!    directory itself (no lock file is left behind); elsewhere it is a file `.signorini.lock`
//!    inside it.  The lock is released when the [`DirLock`] is dropped (or the process ends,
//!    even by a crash).
//! 2. [`OutputSet::new`] creates a staging directory `.signorini-stage-XXXXXX` inside the target
//!    directory (so on the same file system), and [`OutputSet::write`] writes every file there.
//! 3. [`OutputSet::commit`] moves the staged files into place, the *primary* file (the one
//!    readers look at first: `result.json`, `compare.json`, `sweep.csv`) last, and removes the
//!    set's other *members* that this run did not write (a stale plot of an earlier sweep, say).
//!    Each replaced file is first hard-linked into the staging directory (or, where hard links
//!    are not supported, moved there), so if any step fails every file already moved is put back
//!    and the previous set is left as it was.
//!
//! If anything fails before the commit (a writer's error, a full disk), the staging directory is
//! deleted when the [`OutputSet`] is dropped and the directory's previous content is untouched.
//! Staging directories left by a killed process are removed by the next [`DirLock::acquire`]
//! (which owns the directory by then).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::output::OutputError;

/// Prefix of the staging directories inside an output directory.
const STAGE_PREFIX: &str = ".signorini-stage-";

/// An exclusive advisory lock on an output directory, held until dropped.
#[derive(Debug)]
pub struct DirLock {
    dir: PathBuf,
    /// The locked file: the directory itself on Unix, `.signorini.lock` elsewhere.
    file: File,
    /// Whether [`DirLock::acquire`] created the directory (it is removed again, if still empty,
    /// when the lock is dropped: a refused or failed run leaves no empty directory behind).
    created: bool,
}

fn io_error(path: &Path) -> impl Fn(io::Error) -> OutputError + '_ {
    move |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

impl DirLock {
    /// Creates `dir` if missing and locks it.  Refuses with [`OutputError::Locked`] if another
    /// process (or another [`DirLock`] of this one) holds the lock; never waits.  Removes
    /// staging directories that a killed run left behind.
    pub fn acquire(dir: &Path) -> Result<Self, OutputError> {
        let created = !dir.is_dir();
        std::fs::create_dir_all(dir).map_err(io_error(dir))?;
        #[cfg(unix)]
        let file = File::open(dir).map_err(io_error(dir))?;
        #[cfg(not(unix))]
        let file = {
            let path = dir.join(".signorini.lock");
            std::fs::OpenOptions::new()
                .create(true)
                .truncate(false)
                .write(true)
                .open(&path)
                .map_err(io_error(&path))?
        };
        match file.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                return Err(OutputError::Locked {
                    dir: dir.to_path_buf(),
                })
            }
            Err(std::fs::TryLockError::Error(source)) => {
                return Err(OutputError::Io {
                    path: dir.to_path_buf(),
                    source,
                })
            }
        }
        let lock = DirLock {
            dir: dir.to_path_buf(),
            file,
            created,
        };
        lock.remove_stale_staging();
        Ok(lock)
    }

    /// The locked directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Best effort: staging directories of earlier runs are garbage once we hold the lock.
    fn remove_stale_staging(&self) {
        let Ok(entries) = std::fs::read_dir(&self.dir) else {
            return;
        };
        for entry in entries.flatten() {
            let stale = entry
                .file_name()
                .to_string_lossy()
                .starts_with(STAGE_PREFIX)
                && entry.file_type().is_ok_and(|t| t.is_dir());
            if stale {
                let _ = std::fs::remove_dir_all(entry.path());
            }
        }
    }
}

impl Drop for DirLock {
    fn drop(&mut self) {
        // Unlock explicitly rather than by closing: a child process forked by another thread
        // at this moment holds a copy of the descriptor until it execs, and with it the lock.
        let _ = self.file.unlock();
        if self.created {
            // Fails (harmlessly) unless the directory is still empty.
            let _ = std::fs::remove_dir(&self.dir);
        }
    }
}

/// The files of one command, staged beside their targets and moved into place together.
/// See the [module docs](self).
#[derive(Debug)]
pub struct OutputSet<'a> {
    lock: &'a DirLock,
    staging: tempfile::TempDir,
    primary: Option<String>,
    members: Vec<String>,
    staged: Vec<String>,
    /// Fault injection for tests: fail the commit before its n-th move into place.
    #[cfg(test)]
    pub(crate) fail_commit_at: Option<usize>,
}

/// One completed step of a commit, for the rollback.
enum Step {
    /// `name` was replaced; its old content is at the backup path.
    Replaced(String, PathBuf),
    /// `name` did not exist before and was created.
    Created(String),
    /// `name` (not rewritten) was moved to the backup path.
    Removed(String, PathBuf),
}

impl<'a> OutputSet<'a> {
    /// Starts a set in the directory `lock` holds.  `primary` (if any) is moved into place last;
    /// `members` are every file name the set may hold: those not written by this set are
    /// removed from the directory on [`commit`](Self::commit).  Files of the directory that are
    /// not members are never touched.
    pub fn new(
        lock: &'a DirLock,
        primary: Option<&str>,
        members: &[&str],
    ) -> Result<Self, OutputError> {
        let staging = tempfile::Builder::new()
            .prefix(STAGE_PREFIX)
            .tempdir_in(&lock.dir)
            .map_err(io_error(&lock.dir))?;
        let mut members: Vec<String> = members.iter().map(|m| m.to_string()).collect();
        if let Some(p) = primary {
            if !members.iter().any(|m| m == p) {
                members.push(p.to_string());
            }
        }
        for m in &members {
            check_name(m)?;
        }
        Ok(OutputSet {
            lock,
            staging,
            primary: primary.map(str::to_string),
            members,
            staged: Vec::new(),
            #[cfg(test)]
            fail_commit_at: None,
        })
    }

    /// The path `name` will have once the set is committed.
    pub fn target(&self, name: &str) -> PathBuf {
        self.lock.dir.join(name)
    }

    /// Stages the file `name` (a plain file name, no directories): `write` fills it through a
    /// buffered writer.  Writing a name twice replaces the first version.  Returns the path the
    /// file will have once committed.  On error nothing outside the staging directory changes.
    pub fn write(
        &mut self,
        name: &str,
        write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> Result<PathBuf, OutputError> {
        check_name(name)?;
        let target = self.target(name);
        let io_err = io_error(&target);
        let path = self.staging.path().join(name);
        let file = File::create(&path).map_err(&io_err)?;
        let mut out = BufWriter::new(file);
        write(&mut out).map_err(&io_err)?;
        let file = out.into_inner().map_err(|e| io_err(e.into_error()))?;
        file.sync_all().map_err(&io_err)?;
        if !self.staged.iter().any(|s| s == name) {
            self.staged.push(name.to_string());
        }
        if !self.members.iter().any(|m| m == name) {
            self.members.push(name.to_string());
        }
        Ok(self.target(name))
    }

    /// Moves the staged files into place (the primary last) and removes the members not
    /// written.  Returns the paths written, in the order they were staged.  On error every
    /// file already moved is restored, and the directory holds the previous set.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, OutputError> {
        let written: Vec<PathBuf> = self.staged.iter().map(|n| self.target(n)).collect();
        let mut steps = Vec::new();
        match self.move_into_place(&mut steps) {
            Ok(()) => Ok(written),
            Err(e) => {
                self.roll_back(steps);
                Err(e)
            }
        }
        // Dropping `self.staging` deletes the backups.
    }

    fn move_into_place(&mut self, steps: &mut Vec<Step>) -> Result<(), OutputError> {
        let backup_dir = self.staging.path().join(".previous");
        std::fs::create_dir(&backup_dir).map_err(io_error(&self.lock.dir))?;
        // Stale members first, then the new files, the primary last.
        let stale: Vec<String> = self
            .members
            .iter()
            .filter(|m| !self.staged.contains(m))
            .cloned()
            .collect();
        for name in stale {
            let target = self.target(&name);
            if std::fs::symlink_metadata(&target).is_err() {
                continue;
            }
            let backup = backup_dir.join(&name);
            std::fs::rename(&target, &backup).map_err(io_error(&target))?;
            steps.push(Step::Removed(name, backup));
        }
        let mut order: Vec<String> = self
            .staged
            .iter()
            .filter(|n| Some(*n) != self.primary.as_ref())
            .cloned()
            .collect();
        if let Some(p) = &self.primary {
            if self.staged.contains(p) {
                order.push(p.clone());
            }
        }
        for (i, name) in order.into_iter().enumerate() {
            #[cfg(test)]
            if self.fail_commit_at == Some(i) {
                return Err(OutputError::Io {
                    path: self.target(&name),
                    source: io::Error::other("injected failure"),
                });
            }
            #[cfg(not(test))]
            let _ = i;
            let target = self.target(&name);
            let staged = self.staging.path().join(&name);
            let io_err = io_error(&target);
            if std::fs::symlink_metadata(&target).is_ok() {
                let backup = backup_dir.join(&name);
                // A hard link keeps the old file in place until the rename replaces it
                // atomically; without hard links, move it aside first.
                if std::fs::hard_link(&target, &backup).is_err() {
                    std::fs::rename(&target, &backup).map_err(&io_err)?;
                }
                steps.push(Step::Replaced(name.clone(), backup));
            } else {
                steps.push(Step::Created(name.clone()));
            }
            std::fs::rename(&staged, &target).map_err(&io_err)?;
        }
        sync_dir(&self.lock.dir);
        Ok(())
    }

    /// Undoes `steps`, newest first (best effort: the first error is already being reported).
    fn roll_back(&self, steps: Vec<Step>) {
        for step in steps.into_iter().rev() {
            match step {
                Step::Replaced(name, backup) | Step::Removed(name, backup) => {
                    let _ = std::fs::rename(&backup, self.target(&name));
                }
                Step::Created(name) => {
                    // Only if the rename happened (the step is recorded just before it).
                    let staged = self.staging.path().join(&name);
                    if !staged.exists() {
                        let _ = std::fs::remove_file(self.target(&name));
                    }
                }
            }
        }
    }
}

/// Flushes the directory entry changes to disk (best effort; Unix only).
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

/// A member of a set is a plain file name.
fn check_name(name: &str) -> Result<(), OutputError> {
    let plain = !name.is_empty()
        && name != "."
        && name != ".."
        && !name.contains(['/', '\\'])
        && !name.starts_with(STAGE_PREFIX);
    if plain {
        Ok(())
    } else {
        Err(OutputError::Mismatch(format!(
            "\"{name}\" is not a plain file name for an output set"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every entry of `dir` with its bytes (directories marked), sorted.
    fn snapshot(dir: &Path) -> Vec<(String, Option<Vec<u8>>)> {
        let mut v: Vec<(String, Option<Vec<u8>>)> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| {
                let e = e.unwrap();
                let name = e.file_name().to_string_lossy().into_owned();
                let bytes = e
                    .file_type()
                    .unwrap()
                    .is_file()
                    .then(|| std::fs::read(e.path()).unwrap());
                (name, bytes)
            })
            .collect();
        v.sort();
        v
    }

    fn write_set(dir: &Path, files: &[(&str, &str)], members: &[&str]) -> Vec<PathBuf> {
        let lock = DirLock::acquire(dir).unwrap();
        let mut set = OutputSet::new(&lock, Some("main.json"), members).unwrap();
        for (name, text) in files {
            set.write(name, |w| w.write_all(text.as_bytes())).unwrap();
        }
        set.commit().unwrap()
    }

    const MEMBERS: [&str; 3] = ["main.json", "a.vtu", "b.svg"];

    #[test]
    fn a_set_replaces_the_previous_one_and_removes_stale_members() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let first = write_set(
            &dir,
            &[("main.json", "1"), ("a.vtu", "a1"), ("b.svg", "b1")],
            &MEMBERS,
        );
        assert_eq!(
            first,
            [dir.join("main.json"), dir.join("a.vtu"), dir.join("b.svg")]
        );
        std::fs::write(dir.join("notes.txt"), "mine").unwrap();
        // The second run writes no b.svg: the stale one of the first run goes.
        write_set(&dir, &[("a.vtu", "a2"), ("main.json", "2")], &MEMBERS);
        let got = snapshot(&dir);
        let want = [
            ("a.vtu", "a2"),
            ("main.json", "2"),
            ("notes.txt", "mine"), // not a member: never touched
        ]
        .map(|(n, t)| (n.to_string(), Some(t.as_bytes().to_vec())));
        assert_eq!(got, want);
    }

    #[test]
    fn a_failing_writer_leaves_the_previous_set_byte_identical() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        write_set(
            dir,
            &[("main.json", "old"), ("a.vtu", "a-old"), ("b.svg", "b-old")],
            &MEMBERS,
        );
        let before = snapshot(dir);
        {
            let lock = DirLock::acquire(dir).unwrap();
            let mut set = OutputSet::new(&lock, Some("main.json"), &MEMBERS).unwrap();
            set.write("main.json", |w| w.write_all(b"new")).unwrap();
            let err = set
                .write("a.vtu", |w| {
                    w.write_all(b"half")?;
                    Err(io::Error::other("injected"))
                })
                .unwrap_err();
            assert!(err.to_string().contains("a.vtu"), "{err}");
            // The set is dropped here without a commit.
        }
        assert_eq!(snapshot(dir), before);
    }

    #[test]
    fn a_failed_commit_is_rolled_back() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        write_set(
            dir,
            &[("main.json", "old"), ("a.vtu", "a-old"), ("b.svg", "b-old")],
            &MEMBERS,
        );
        let before = snapshot(dir);
        // Fail at each move: after 0, 1 and 2 files were moved into place (main.json is the
        // third and last), with b.svg (stale) already moved aside and a new c.txt created.
        for at in 0..3 {
            let lock = DirLock::acquire(dir).unwrap();
            let mut set = OutputSet::new(&lock, Some("main.json"), &MEMBERS).unwrap();
            set.write("main.json", |w| w.write_all(b"new")).unwrap();
            set.write("a.vtu", |w| w.write_all(b"a-new")).unwrap();
            set.write("c.txt", |w| w.write_all(b"c-new")).unwrap();
            set.fail_commit_at = Some(at);
            let err = set.commit().unwrap_err();
            assert!(err.to_string().starts_with("cannot write"), "{err}");
            drop(lock);
            assert_eq!(snapshot(dir), before, "failure at move {at}");
        }
        // Without the fault the same set goes through.
        write_set(dir, &[("main.json", "new"), ("c.txt", "c")], &MEMBERS);
        let names: Vec<String> = snapshot(dir).into_iter().map(|e| e.0).collect();
        assert_eq!(names, ["c.txt", "main.json"]);
    }

    #[test]
    fn a_held_lock_refuses_a_second_writer_naming_the_directory() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("busy");
        let first = DirLock::acquire(&dir).unwrap();
        let err = DirLock::acquire(&dir).unwrap_err();
        assert!(matches!(err, OutputError::Locked { .. }), "{err:?}");
        assert!(
            err.to_string().contains(&dir.display().to_string()),
            "{err}"
        );
        drop(first);
        DirLock::acquire(&dir).unwrap();
    }

    #[test]
    fn stale_staging_is_removed_and_an_unused_new_directory_too() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        std::fs::create_dir_all(dir.join(".signorini-stage-killed/.previous")).unwrap();
        std::fs::write(dir.join(".signorini-stage-killed/main.json"), "x").unwrap();
        std::fs::write(dir.join(".signorini-stage-file"), "not a directory: kept").unwrap();
        drop(DirLock::acquire(&dir).unwrap());
        let names: Vec<String> = snapshot(&dir).into_iter().map(|e| e.0).collect();
        assert_eq!(names, [".signorini-stage-file"]);

        // A directory the lock created is removed again if nothing was written into it.
        let fresh = tmp.path().join("fresh");
        let lock = DirLock::acquire(&fresh).unwrap();
        assert!(fresh.is_dir());
        let set = OutputSet::new(&lock, Some("main.json"), &MEMBERS).unwrap();
        drop(set);
        drop(lock);
        assert!(!fresh.exists());
    }

    #[test]
    fn names_must_be_plain() {
        let tmp = tempfile::tempdir().unwrap();
        let lock = DirLock::acquire(tmp.path()).unwrap();
        for bad in ["", "..", "a/b", ".signorini-stage-x"] {
            assert!(OutputSet::new(&lock, Some(bad), &[]).is_err(), "{bad:?}");
        }
        let mut set = OutputSet::new(&lock, None, &[]).unwrap();
        assert!(set.write("../escape", |w| w.write_all(b"x")).is_err());
        assert!(!tmp.path().parent().unwrap().join("escape").exists());
    }
}
