//! Reading files: bytes, and recorded runs of any supported format (the importers themselves
//! are pure, in `sonarmap::import`).

use super::interrupt;
use super::progress::Progress;
use anyhow::{Context, Result};
use sonarmap::import::{import_any, Format, ImportOptions, Imported};
use sonarmap::run::Run;
use std::io::Read;
use std::path::Path;

/// The bytes of `path`; the error names the file.
pub fn read(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
}

/// [`read`], the bytes read shown on a progress bar (for a recording that may be large).
fn read_showing(path: &Path) -> Result<Vec<u8>> {
    let cannot = || format!("cannot read {}", path.display());
    let file = std::fs::File::open(path).with_context(cannot)?;
    let size = file.metadata().with_context(cannot)?.len() as usize;
    let progress = Progress::bytes(&format!("reading {}", path.display()), size);
    let mut bytes = Vec::with_capacity(size);
    let mut reader = file;
    let mut chunk = vec![0; 1 << 20];
    loop {
        let n = reader.read(&mut chunk).with_context(cannot)?;
        if n == 0 {
            return Ok(bytes);
        }
        bytes.extend_from_slice(&chunk[..n]);
        progress.set(bytes.len())?;
    }
}

/// Reads and imports a run of any supported format with `options`, showing its progress
/// (the bytes read, then the time spent importing).
pub fn import_file(path: &Path, options: &ImportOptions) -> Result<Imported> {
    let name = path.display().to_string();
    let bytes = read_showing(path)?;
    let importing = Progress::spinner(&format!("importing {name}"));
    let imported = import_any(&bytes, &name, options)?;
    drop(importing);
    interrupt::check()?;
    Ok(imported)
}

/// Reads a run log or any recording the importers read (content decides), with no import
/// options; says on stderr what an import (not a plain run log) did.
pub fn read_run(path: &Path) -> Result<Run> {
    let imported = import_file(path, &ImportOptions::default())?;
    if imported.format != Format::SonarmapLog {
        eprintln!(
            "{}: imported as a {}: {}",
            path.display(),
            imported.format.name(),
            imported.summary
        );
    }
    Ok(imported.run)
}
