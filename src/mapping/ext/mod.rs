//! The extensions beyond the paper (docs/algorithm.md §8), each behind its own flag of
//! [`crate::mapping::Params`] and off in the `paper` preset. Each rule is its own module; the
//! mapper calls them through its hooks (`mapper.rs`), and [`ALL`] lists them in run order.

pub mod beam_geometry;
pub mod confirm;
pub mod constant_depth;
pub mod corner_diagonals;
pub mod drift_smoother;
pub mod echo_agreement;
pub mod echo_fit;
pub mod free_space;
pub mod memory_linkage;
pub mod odometry_drift;
pub mod point_features;
pub mod point_memory;
pub mod pose_correction;
pub mod range_gate;
pub mod rectilinear_heading;
pub mod right_angle_break;
pub mod round_reflectors;
pub mod seen_through_ends;
pub mod settled_walls;
pub mod standstill;
mod steps;

/// One extension: the parameter that switches it on, its section of docs/algorithm.md, and
/// where the idea comes from (as docs/algorithm.md §7 and §8 cite it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Extension {
    /// Its parameter (a flag, or a count or a length that is off at 0).
    pub parameter: &'static str,
    /// Its section of docs/algorithm.md.
    pub section: &'static str,
    /// Its source.
    pub source: &'static str,
}

/// Every extension, in the order a step runs them (`steps/mod.rs`).
pub const ALL: &[Extension] = &[
    Extension {
        parameter: "pose_correction",
        section: "8.17",
        source: "Leonard and Durrant-Whyte 1991: EKF localisation on geometric beacons; Crowley 1989: the pose from the segment map",
    },
    Extension {
        parameter: "heading_correction",
        section: "8.17",
        source: "Nguyen, Harati, Martinelli and Siegwart 2006: orthogonal SLAM, indoor walls along two axes; Martinelli, Tomatis and Siegwart 2007: odometry calibrated on line",
    },
    Extension {
        parameter: "calibrate_first",
        section: "8.17",
        source: "Borenstein and Feng 1996 (UMBmark): the odometry's systematic errors measured first, then corrected; Rauch, Tung and Striebel 1965: the heading errors smoothed over the whole run",
    },
    Extension {
        parameter: "revisit_laps",
        section: "8.17",
        source: "Leonard and Durrant-Whyte 1991, Crowley 1989: the pose corrected against the map's walls, on runs that come back to them",
    },
    Extension {
        parameter: "standstill",
        section: "8.19",
        source: "Grisetti, Stachniss and Burgard 2007 (GMapping): a scan is taken once the robot has moved or turned (linearUpdate, angularUpdate)",
    },
    Extension {
        parameter: "echo_agreement",
        section: "8.21",
        source: "Borenstein and Koren 1995 (EERUF): a reading counts when the sensor's next firing agrees",
    },
    Extension {
        parameter: "explain_readings",
        section: "8.5",
        source: "Leonard and Durrant-Whyte 1992: a point target explains its echoes",
    },
    Extension {
        parameter: "settled_walls",
        section: "8.12",
        source: "Kleeman and Kuc: a plane echoes from the foot of the perpendicular",
    },
    Extension {
        parameter: "arc_features",
        section: "8.5",
        source: "Leonard and Durrant-Whyte 1992: regions of constant depth seen by several sensors",
    },
    Extension {
        parameter: "constant_depth",
        section: "8.2",
        source: "Leonard and Durrant-Whyte 1992: regions of constant depth",
    },
    Extension {
        parameter: "min_piece_points",
        section: "8.8",
        source: "beyond the literature (sonarmap): a line needs readings enough to resolve it",
    },
    Extension {
        parameter: "echo_fit",
        section: "8.10",
        source: "Kleeman and Kuc: the plane model, echoes from the foot or the cone's edge",
    },
    Extension {
        parameter: "memory_snapshots",
        section: "8.1",
        source: "beyond the literature (sonarmap): readings of several snapshots fitted as one cluster",
    },
    Extension {
        parameter: "memory_stacks",
        section: "8.15",
        source: "beyond the literature (sonarmap): a place read at changing ranges has no direction",
    },
    Extension {
        parameter: "memory_joints",
        section: "8.16",
        source: "beyond the literature (sonarmap): pieces of one chain share a reading",
    },
    Extension {
        parameter: "wall_windows",
        section: "8.17",
        source: "Kleeman and Kuc: a plane's echo returns from within the beam along its normal, so one wall's echoes from any sensor lie on a line parallel to it; the line observes heading as in Nguyen et al.'s orthogonal SLAM",
    },
    Extension {
        parameter: "open_windows",
        section: "8.17",
        source: "Nguyen et al.'s orthogonal SLAM: a straight run of one sonar's readings beside the robot's motion is a wall whose direction observes heading, confirmed or not; Kleeman and Kuc: a sonar read square-on to a wall ahead returns one place, which draws no line",
    },
    Extension {
        parameter: "right_angle_break",
        section: "8.20",
        source: "Kleeman and Kuc: a plane echoes from within the beam, so sonars a right angle apart never hear one plane on their axes",
    },
    Extension {
        parameter: "plane_gate",
        section: "8.7",
        source: "Kleeman and Kuc: a plane supported by an echo from its foot",
    },
    Extension {
        parameter: "corner_diagonals",
        section: "8.11",
        source: "Kleeman and Kuc: a corner echoes from its vertex at any incidence",
    },
    Extension {
        parameter: "round_reflectors",
        section: "8.14",
        source: "Leonard and Durrant-Whyte 1992: cylinders beside planes, corners and edges",
    },
    Extension {
        parameter: "confirm_segments",
        section: "8.7",
        source: "Kleeman and Kuc: a plane told from a corner from two positions",
    },
    Extension {
        parameter: "off_axis_square_on",
        section: "8.7",
        source: "Kleeman and Kuc: a plane echoes from the foot of the perpendicular; Nguyen, Harati, Martinelli and Siegwart 2006: indoor walls along two axes",
    },
    Extension {
        parameter: "refit_unconfirms",
        section: "8.7",
        source: "beyond the literature (sonarmap): a refit that moves a wall takes back its confirmation",
    },
    Extension {
        parameter: "refit_recounts",
        section: "8.7",
        source: "beyond the literature (sonarmap): support counted for a line is not support for the line a refit turned it into",
    },
    Extension {
        parameter: "baseline_confirm",
        section: "8.7",
        source: "Kleeman and Kuc: two sensors on a baseline",
    },
    Extension {
        parameter: "free_space",
        section: "8.6",
        source: "Kleeman and Kuc's plane model: a segment inside the beam short of the range was seen through",
    },
    Extension {
        parameter: "trim_seen_through",
        section: "8.18",
        source: "Moravec and Elfes 1985: the cone short of the range is empty; Kleeman and Kuc's plane model",
    },
];

#[cfg(test)]
mod tests {
    use super::ALL;
    use crate::mapping::Params;

    #[test]
    fn every_extension_parameter_is_listed_once_and_only_the_paper_rules_options_are_not() {
        let listed: Vec<&str> = ALL.iter().map(|e| e.parameter).collect();
        let mut unique = listed.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), listed.len(), "listed once");
        let options_of_the_papers_rules =
            ["fit", "support_cap", "merge_duplicates", "corner_guard"];
        for p in Params::extension_parameters() {
            let is_option = options_of_the_papers_rules.contains(&p.name);
            assert_eq!(listed.contains(&p.name), !is_option, "{}", p.name);
        }
        let algorithm = include_str!("../../../docs/algorithm.md");
        for e in ALL {
            let heading = format!("\n### {} ", e.section);
            assert!(
                algorithm.contains(&heading),
                "{}: no §{}",
                e.parameter,
                e.section
            );
            assert!(Params::paper_with(e.parameter).is_some(), "{}", e.parameter);
            assert!(
                !Params::paper().is_on(e.parameter),
                "{} off in paper",
                e.parameter
            );
        }
    }
}
