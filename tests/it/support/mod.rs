//! What the integration tests share: the app driven in a harness, the paths of the assets and
//! fixtures, one sensor-layout builder, a snapshot of a robot at the origin, a Pioneer crawl,
//! a whole first pass, and (in `ros2`) ROS 2 recordings built byte by byte.

pub(crate) mod ros2;

use egui_kittest::Harness;
use sonarmap::app::{Command, SonarApp};
use sonarmap::geometry::Pose;
use sonarmap::mapping::{Mapper, Params};
use sonarmap::run::{Run, Snapshot};
use sonarmap::sim::{load_plan, simulate_paced, Model, Pace};
use sonarmap::sonar::{SensorLayout, SensorMount};
use std::collections::HashMap;
use std::path::PathBuf;

/// A file of `tests/fixtures/`.
pub(crate) fn fixture_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

/// A snapshot at time `t` of the robot standing at the origin, heading +x, with `ranges_m`.
pub(crate) fn snapshot_at_origin(t: f64, ranges_m: &[Option<f64>]) -> Snapshot {
    Snapshot {
        t,
        pose: Pose::new(0.0, 0.0, 0.0),
        ranges_m: ranges_m.to_vec(),
        true_pose: None,
        reading_dt_s: Vec::new(),
    }
}

/// A sensor layout of the mounts `(x_m, y_m, heading_rad)`, robot frame.
pub(crate) fn layout_of(mounts: impl IntoIterator<Item = (f64, f64, f64)>) -> SensorLayout {
    SensorLayout {
        mounts: mounts
            .into_iter()
            .map(|(x_m, y_m, heading_rad)| SensorMount {
                x_m,
                y_m,
                heading_rad,
            })
            .collect(),
    }
}

/// A Pioneer's crawl: firing cycles 15 mm and 0.3 s apart, the sonars fired in three groups.
pub(crate) const CRAWL: Pace = Pace {
    cycle_step_m: Some(0.015),
    cycle_s: 0.3,
    firing_groups: 3,
    ..Pace::PLAN
};

/// A mapper stepped over the whole of `run` with `params`: a first pass, whose map and
/// calibration (`second_pass_params`) the tests read.
pub(crate) fn first_pass(run: &Run, params: Params) -> Mapper {
    let mut mapper = Mapper::new(params, run.layout.clone(), run.sensor);
    for snapshot in &run.snapshots {
        mapper.step(snapshot);
    }
    mapper
}

/// The Pioneer corridor stand-in (`assets/pioneer_corridor.plan.json`) simulated at [`CRAWL`]
/// with the specular model and noise seed `seed`, its odometry the truth.
pub(crate) fn pioneer_corridor_crawl(seed: u64) -> Run {
    let path = asset("pioneer_corridor.plan.json");
    let name = path.display().to_string();
    let plan = load_plan(&std::fs::read(&path).unwrap(), &name).unwrap();
    simulate_paced(&plan, Model::Specular, seed, &CRAWL)
}

pub(crate) fn asset(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
}

pub(crate) fn harness(app: SonarApp) -> Harness<'static, SonarApp> {
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_accessibility_check(false)
        .build_ui_state(|ui, app: &mut SonarApp| app.ui(ui), app)
}

/// The app on the built-in run, then `building.log.json` opened through the command path.
pub(crate) fn building() -> Harness<'static, SonarApp> {
    let run = sonarmap::assets::default_run().expect("built-in run loads");
    let mut h = harness(SonarApp::new(run, None));
    h.run();
    h.state_mut()
        .push(Command::Open(asset("building.log.json")));
    h.run();
    assert!(h.state().banner().is_none(), "{:?}", h.state().banner());
    assert!(h.state().len() > 10);
    h
}

#[derive(Default)]
pub(crate) struct MemoryStorage(pub(crate) HashMap<String, String>);

impl eframe::Storage for MemoryStorage {
    fn get_string(&self, key: &str) -> Option<String> {
        self.0.get(key).cloned()
    }
    fn set_string(&mut self, key: &str, value: String) {
        self.0.insert(key.to_owned(), value);
    }
    fn remove_string(&mut self, key: &str) {
        self.0.remove(key);
    }
    fn flush(&mut self) {}
}

/// Steps the harness until no background work is left (re-runs, comparisons), then settles.
/// A frame that ends idle is followed by one more: a finished replay may have queued another
/// (`calibrate_first`'s second pass), started by the next frame.
pub(crate) fn settle(h: &mut Harness<'static, SonarApp>) {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(300);
    loop {
        h.step();
        if !h.state().is_loading() {
            h.step();
            if !h.state().is_loading() {
                break;
            }
        }
        assert!(
            std::time::Instant::now() < deadline,
            "background work never ended"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    h.run();
}
