//! ROS 2 recordings in MCAP files (read with the `mcap` crate; CDR decoded by hand, see
//! [`super::cdr`]).
//!
//! # Accepted
//! Messages with CDR encoding whose schema is
//! - `sensor_msgs/msg/Range`: one sonar reading (one topic or one `frame_id` per sonar);
//! - `nav_msgs/msg/Odometry`: the robot pose (x, y and the yaw of the quaternion);
//! - `tf2_msgs/msg/TFMessage` on `/tf_static`: the sonar mounts (chains of static transforms
//!   from the robot's frame, the odometry's `child_frame_id`, else `base_link`, to each
//!   sonar's `frame_id`; x, y and yaw are kept).
//!
//! Everything else is left out (counted in the summary). Times are the header stamps (the log
//! time when a stamp is zero).
//!
//! # Rules
//! - Sensors: with `--layout`, its `frames` map (frame id, else topic → index) decides; a layout
//!   without `frames` takes the distinct frame ids (or topics, for empty frame ids) in natural
//!   order (`sonar_2` before `sonar_10`) as sensors 0, 1, ...; without `--layout` the sonars
//!   are those frame ids in natural order and their mounts come from `/tf_static`. With
//!   neither, the import is refused and the error names `--layout`.
//! - A reading outside `[min_range, max_range]` of its message, or ±inf or NaN, is no echo
//!   (REP 117), as is one at or beyond `--max-range` (default: the layout's, else the largest
//!   `max_range` of the messages).
//! - Snapshots: the readings, sorted by time, are cut into firing cycles of the ring. A cycle
//!   starts at a reading and takes the following ones until a sensor repeats or a reading comes
//!   more than the window (`--window`, default 0.1 s) after the cycle's first; then the next
//!   cycle starts (`crate::import::cycles`, shared with one-reading-a-line tables). The
//!   snapshot's time is the mean of its readings' times, its pose interpolated there, and each
//!   reading keeps its own moment as an offset (`reading_dt_s`); a sensor silent in a cycle is
//!   no echo (counted in a warning).
//! - A reading or odometry message earlier than the previous one of the same sensor or odometry
//!   topic is skipped with a warning. No odometry: refused unless a fixed pose is given.
//!
//! # Refused (with the file, the message index, topic and field or byte offset, and what was expected)
//! - Bytes that are not MCAP; a record whose declared length (or that of a string, map or
//!   byte array inside it) runs past the bytes present, at the top level or in a chunk (the
//!   error gives the record's byte offset; checked before the `mcap` crate sees the file, and
//!   a panic inside the crate is contained as an error); a compressed chunk (this build reads
//!   uncompressed recordings); a record the `mcap` crate cannot read (the error says after
//!   which message).
//! - A Range/Odometry/TFMessage that is not CDR of its type (too short, a string running past
//!   the end, an unknown encapsulation).
//! - Values no robot produces: a Range's field of view outside 0..π, a negative or non-finite
//!   `min_range` or `max_range`, `min_range ≥ max_range`, a negative finite `range`; an
//!   odometry or /tf_static position that is not finite or beyond 10 km, a quaternion that is
//!
//! # Code
//! `collect` reads the messages (`messages` decodes and checks each type), `sensors` names
//! the sonars and finds their layout (`tf`: the `/tf_static` chains) and `assembly` cuts the
//! readings into firing cycles and puts the run together; `contain` keeps a panic
//! in the `mcap` crate from escaping.

mod assembly;
mod collect;
mod contain;
mod messages;
mod sensors;
mod tf;

use super::error::{at, ImportError};
use super::mcap_check;
use super::options::ImportOptions;
use super::summary::{ImportSummary, Imported};

/// The first bytes of every MCAP file.
pub const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// Imports a ROS 2 MCAP recording. `file` names it in errors. Pure.
pub fn import_mcap(
    bytes: &[u8],
    file: &str,
    options: &ImportOptions,
) -> Result<Imported, ImportError> {
    if !bytes.starts_with(MCAP_MAGIC) {
        return Err(at(
            file,
            "byte 0",
            "expected the MCAP magic bytes 89 4D 43 41 50 30 0D 0A",
        ));
    }
    options.check()?;
    mcap_check::check(bytes, file)?;
    let mut summary = ImportSummary::default();
    let collected = contain::contain_panic(file, || collect::collect(bytes, file, &mut summary))?;
    assembly::assemble_mcap(collected, file, options, summary)
}
