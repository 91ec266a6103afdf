//! Reading files: bytes, and recorded runs of any supported format (the importers themselves
//! are pure, in `sonarmap::import`).

use anyhow::{Context, Result};
use sonarmap::import::{import_any, Format, ImportOptions, Imported};
use sonarmap::run::Run;
use std::path::Path;

/// The bytes of `path`; the error names the file.
pub fn read(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
}

/// Reads and imports a run of any supported format with `options`.
pub fn import_file(path: &Path, options: &ImportOptions) -> Result<Imported> {
    let name = path.display().to_string();
    let imported = import_any(&read(path)?, &name, options)?;
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
