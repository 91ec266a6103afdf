//! Writing results: files (atomically, the error naming the file) and lines on stdout, one
//! per log, with failed logs reported on stderr.

use super::interrupt::{self, Interrupted};
use anyhow::{bail, Context, Result};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes `contents` to `path` atomically ([`sonarmap::atomic_write`]).
pub fn write_atomic(path: &Path, contents: impl AsRef<[u8]>) -> Result<()> {
    write_atomic_with(path, |f| f.write_all(contents.as_ref()))
}

/// [`write_atomic`] with the content written by `write` (through a buffer), for output too
/// large to hold as one string first. After Ctrl-C the file is not renamed into place: the
/// temporary file is removed and the error is [`Interrupted`].
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<()> {
    write_unless(path, write, &interrupt::interrupted)
}

/// [`write_atomic_with`], stopped (no file, [`Interrupted`]) when `stop()` says so before the
/// rename.
fn write_unless(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
    stop: &dyn Fn() -> bool,
) -> Result<()> {
    if path.file_name().is_none() {
        bail!("{} is not a file name", path.display());
    }
    if stop() {
        return Err(Interrupted.into());
    }
    let written = sonarmap::atomic_write::write_atomic_with(path, |f| {
        write(f)?;
        if stop() {
            return Err(std::io::Error::other(Interrupted));
        }
        Ok(())
    });
    if stop() {
        return Err(Interrupted.into());
    }
    written.with_context(|| format!("cannot write {}", path.display()))
}

/// Prints a line on stdout; a closed pipe (`| head`) is not an error.
pub fn emit(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}").and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

/// Prints each log's line on stdout, or its error on stderr, in order; fails (exit 2) when
/// any log failed, after all were reported; stops at once on Ctrl-C.
pub fn emit_each<'a>(results: impl Iterator<Item = (&'a Path, Result<String>)>) -> Result<()> {
    let (mut total, mut failed) = (0, 0);
    for (path, result) in results {
        total += 1;
        match result {
            Ok(line) => emit(&line)?,
            Err(e) if interrupt::is_interruption(&e) => return Err(e),
            Err(e) => {
                failed += 1;
                report_failure(path, &e);
            }
        }
    }
    if failed > 0 {
        bail!("{failed} of {total} logs failed");
    }
    Ok(())
}

/// Prints a failed log's error on stderr, naming the log unless the error already does.
fn report_failure(path: &Path, e: &anyhow::Error) {
    let message = sonarmap::import::sane::escape(&format!("{e:#}"));
    let name = path.display().to_string();
    if message.contains(&name) {
        eprintln!("{message}");
    } else {
        eprintln!("{name}: {message}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_write_stopped_by_ctrl_c_leaves_no_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("map.json");
        let pressed = std::cell::Cell::new(false);
        let e = write_unless(
            &path,
            |f| {
                f.write_all(b"the whole map")?;
                pressed.set(true);
                Ok(())
            },
            &|| pressed.get(),
        )
        .unwrap_err();
        assert!(interrupt::is_interruption(&e), "{e:#}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
