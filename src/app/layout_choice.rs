//! Where a log's sensor layout comes from, as the layout picker offers it and a command
//! carries it.

use std::path::PathBuf;

/// Where the layout comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum LayoutChoice {
    /// A shipped layout, by name.
    Shipped(String),
    /// A `sonarmap-layout` file.
    File(PathBuf),
}
