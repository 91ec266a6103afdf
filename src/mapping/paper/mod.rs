//! The paper's rules (Cahut, Valavanis and Deliç; docs/algorithm.md §1–§6), one rule a file:
//! [`readings`] §1, [`cluster`] §2, [`fit`] §3, [`matching`] and its faster equal
//! [`fast_path`] §4, [`update`] §5 (with [`merge`], its `merge_duplicates` option), and
//! [`correlate`] §6. [`flip`] answers, for the inspector, where a test of §4 would flip.
//!
//! Options that change a rule of the paper itself (`support_cap`, `merge_duplicates`,
//! `corner_guard`, the least-squares fit) stay options of that rule here. Nothing here imports
//! [`crate::mapping::ext`].

pub mod candidates;
pub mod cluster;
pub mod correlate;
pub mod fast_path;
pub mod fit;
pub mod flip;
pub mod matching;
pub mod merge;
pub mod reading_poses;
pub mod readings;
pub mod support_points;
pub mod update;
pub mod update_geometry;
