//! The robot's layer: its path so far (the odometry's, and the corrected and true paths when
//! there are), its previous pose and its body now.

use super::Builder;
use crate::geometry::{unit, Point};
use crate::run::Snapshot;
use crate::scene::declutter::Declutter;
use crate::scene::layer::Layer;
use crate::scene::primitive::{SceneId, Shape};
use crate::scene::style::Role;
use crate::units::inches;

impl Builder<'_, '_> {
    /// The robot's path through `path` as polylines: one, unless the view has a level of
    /// detail. Then a stretch between two poses whose ends fall in the 2-pixel cells of a
    /// stretch drawn already is left out, and the path broken there: a patrol goes over the
    /// same ground lap after lap, and each lap drawn again would only add vertices.
    pub(super) fn path_pieces(
        &self,
        mut positions: impl Iterator<Item = Point>,
    ) -> Vec<Vec<Point>> {
        let mut drawn = Declutter::new(self.options.world_per_px, 2.0, 2.0);
        let mut pieces: Vec<Vec<Point>> = Vec::new();
        let mut open = false;
        let Some(first) = positions.next() else {
            return pieces;
        };
        // Each pose's cell found once (it ends two stretches).
        let at = |drawn: &Declutter, p: Point| (p, drawn.cell(&p));
        let mut from = at(&drawn, first);
        for p in positions {
            let ((a, ca), (b, cb)) = (from, at(&drawn, p));
            from = (b, cb);
            if !drawn.claim_cells(ca, cb) {
                open = false;
                continue;
            }
            if !open {
                pieces.push(vec![a]);
                open = true;
            }
            pieces.last_mut().expect("a piece is open").push(b);
        }
        pieces
    }

    /// A path through `positions` in `role`, decluttered as [`Self::path_pieces`].
    fn path(&mut self, role: Role, positions: impl Iterator<Item = Point>) {
        for points in self.path_pieces(positions) {
            self.push(
                Layer::Robot,
                role,
                SceneId::Robot,
                Shape::Polyline {
                    points,
                    closed: false,
                },
            );
        }
    }

    /// The paths beside the odometry's: the one pose correction made (docs/algorithm.md
    /// §8.17), and the true one when the run keeps it (a simulated run whose odometry drifts).
    fn other_paths(&mut self, path: &[Snapshot]) {
        let corrected = self.input.corrected_path;
        if corrected.len() >= path.len() {
            self.path(
                Role::RobotPathCorrected,
                corrected[..path.len()].iter().map(|p| p.mapped.position()),
            );
        }
        if path.iter().all(|s| s.true_pose.is_some()) {
            self.path(
                Role::RobotPathTrue,
                path.iter()
                    .filter_map(|s| s.true_pose)
                    .map(|p| p.position()),
            );
        }
    }

    /// The robot: its path so far, its previous pose and its body and heading now.
    pub(super) fn robot(&mut self) {
        let run = self.input.run;
        let k = self.input.snapshot;
        let radius_m = run.robot_radius_m.unwrap_or(inches(9.0));
        let path = &run.snapshots[..(k + 1).min(run.snapshots.len())];
        if path.len() >= 2 {
            self.path(Role::RobotPath, path.iter().map(|s| s.pose.position()));
            self.other_paths(path);
            let prev = path[path.len() - 2].pose.position();
            self.push(
                Layer::Robot,
                Role::RobotPrevious,
                SceneId::Robot,
                Shape::Circle {
                    centre: prev,
                    radius_m,
                },
            );
        }
        let Some(pose) = self.pose else { return };
        let centre = pose.position();
        self.push(
            Layer::Robot,
            Role::Robot,
            SceneId::Robot,
            Shape::Circle { centre, radius_m },
        );
        let nose = centre + unit(pose.heading_rad) * radius_m;
        self.push(
            Layer::Robot,
            Role::Robot,
            SceneId::Robot,
            Shape::Segment { a: centre, b: nose },
        );
    }
}
