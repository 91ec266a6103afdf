//! The inspector's layout and views (issue 20): Fit frames the visible map, the map's share of
//! the window, collapsible and remembered panels, the inspector's dock, the A | B split with
//! linked zoom, the in-app file dialog, the layout picker, parameters that are not the preset's.

use super::support::{asset, building, fixture_path, harness, settle, MemoryStorage};
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use sonarmap::app::{Command, DialogBackend, FilePurpose, SonarApp};
use sonarmap::geometry::Point;

/// The part of the map plot visible on screen, points.
fn visible_plot(h: &Harness<SonarApp>) -> egui::Rect {
    h.state().map_view().visible_px.expect("the map was drawn")
}

/// Every end-point of the map shown, world metres.
fn map_end_points(h: &Harness<SonarApp>) -> Vec<Point> {
    let view = h.state().step_view().expect("a step is shown");
    view.map_after
        .segments
        .iter()
        .flat_map(|s| [s.a.point, s.b.point])
        .collect()
}

#[test]
fn after_fit_every_segment_end_point_lies_inside_the_visible_map() {
    let mut h = building();
    h.state_mut().push(Command::Last);
    h.state_mut().push(Command::FitView);
    h.run();
    let visible = visible_plot(&h);
    let points = map_end_points(&h);
    assert!(points.len() > 20, "the building's last map has segments");
    for p in points {
        let at = h.state().map_view().screen_of(p).unwrap();
        assert!(
            visible.contains(at),
            "{p:?} drawn at {at:?}, outside {visible:?}"
        );
    }
    // The visible map is left of the right panel, not under it.
    let dock = h.get_by_label("Dock in a tab").rect();
    assert!(
        visible.right() <= dock.left(),
        "{visible:?} runs under {dock:?}"
    );
}

#[test]
fn the_default_layout_gives_the_map_at_least_55_percent_of_the_width() {
    let h = building();
    let width = visible_plot(&h).width();
    assert!(width >= 0.55 * 1400.0, "the map is {width} of 1400 points");
}

#[test]
fn side_panels_collapse_with_keys_map_only_hides_both_and_the_layout_is_remembered() {
    let mut h = building();
    let both = visible_plot(&h).width();
    h.key_press(egui::Key::L);
    h.run();
    assert!(
        h.query_by_label("Bookmarks").is_none(),
        "the left panel is hidden"
    );
    let without_left = visible_plot(&h).width();
    assert!(without_left > both + 100.0, "{without_left} vs {both}");
    h.key_press(egui::Key::L);
    h.key_press(egui::Key::I);
    h.run();
    assert!(h.query_by_label("Bookmarks").is_some());
    assert!(
        h.query_by_label("Dock in a tab").is_none(),
        "the right panel is hidden"
    );
    h.key_press(egui::Key::I);
    h.key_press(egui::Key::M);
    h.run();
    assert!(h.query_by_label("Bookmarks").is_none());
    assert!(h.query_by_label("Dock in a tab").is_none());
    let map_only = visible_plot(&h).width();
    assert!(map_only > 1300.0, "map only: {map_only}");

    let mut storage = MemoryStorage::default();
    eframe::App::save(h.state_mut(), &mut storage);
    let run = sonarmap::assets::default_run().unwrap();
    let again = SonarApp::new(run, Some(&storage));
    assert!(again.settings().panels.map_only);
    assert_eq!(again.settings().panels, h.state().settings().panels);
    h.key_press(egui::Key::M);
    h.run();
    assert!(h.query_by_label("Bookmarks").is_some() && h.query_by_label("Dock in a tab").is_some());
}

#[test]
fn the_inspector_docks_in_a_tab_beside_the_decisions() {
    let mut h = building();
    assert!(h
        .query_by_label_contains("Click something in the map")
        .is_some());
    h.get_by_label("Dock in a tab").click();
    h.run();
    // The decisions page: the inspector is in the other tab.
    assert!(h
        .query_by_label_contains("Click something in the map")
        .is_none());
    assert!(h.query_all_by_label_contains("New face").count() > 0);
    h.get_by_label("Inspector").click();
    h.run();
    assert!(h
        .query_by_label_contains("Click something in the map")
        .is_some());
    assert!(h.query_by_label("Dock below").is_some());
}

#[test]
fn the_split_view_shows_the_baseline_beside_the_current_map_with_linked_zoom() {
    let mut h = building();
    h.state_mut().push(Command::Seek(150));
    h.state_mut().push(Command::PinBaseline);
    let mut theta = h.state().params().clone();
    theta.orientation_rad = 5f64.to_radians();
    h.state_mut().push(Command::SetParams(theta));
    settle(&mut h);
    h.key_press(egui::Key::S);
    h.run();
    assert!(h.state().is_split());
    let a = h.state().split_view().unwrap().visible_px.unwrap();
    let b = visible_plot(&h);
    assert!(a.right() <= b.left() + 1.0, "A {a:?} left of B {b:?}");
    let a_m = h.state().split_view().unwrap().visible_m.unwrap();
    let b_m = h.state().map_view().visible_m.unwrap();
    // Zoom in over B only (pinch / ctrl+scroll): A follows.
    h.hover_at(b.center());
    h.event(egui::Event::Zoom(2.0));
    h.run();
    let a_zoomed = h.state().split_view().unwrap().visible_m.unwrap();
    let b_zoomed = h.state().map_view().visible_m.unwrap();
    assert!(
        b_zoomed.width_m() < 0.75 * b_m.width_m(),
        "B zoomed: {} then {}",
        b_m.width_m(),
        b_zoomed.width_m()
    );
    assert!(
        (a_zoomed.width_m() - b_zoomed.width_m()).abs() < 1e-6 * b_zoomed.width_m(),
        "A {} follows B {}",
        a_zoomed.width_m(),
        b_zoomed.width_m()
    );
    assert!((a_m.width_m() - b_m.width_m()).abs() < 1e-6 * b_m.width_m());
    // Same snapshot on both sides.
    assert_eq!(h.state().current(), 150);
}

#[test]
fn with_the_portal_absent_the_in_app_dialog_opens_a_log() {
    let mut h = building();
    h.state_mut()
        .push(Command::SetFileDialog(DialogBackend::InApp));
    h.state_mut().push(Command::OpenDialog);
    h.run();
    let (purpose, folder) = h.state().file_dialog().expect("the in-app dialog is open");
    assert_eq!(purpose, FilePurpose::OpenLog);
    // It starts in the folder of the most recent file.
    assert_eq!(folder, asset("building.log.json").parent().unwrap());
    assert!(h.query_by_label_contains("Open a run log").is_some());
    h.get_by_label("tight_room.log.json").click();
    h.run();
    h.get_by_label("Open").click();
    h.run();
    assert!(h.state().file_dialog().is_none());
    assert!(h.state().banner().is_none(), "{:?}", h.state().banner());
    assert!(h.state().source().display_name().contains("tight_room"));
}

#[test]
fn a_parameter_file_chosen_in_the_in_app_dialog_that_does_not_parse_goes_to_the_banner() {
    let mut h = building();
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("room.log.json");
    std::fs::copy(asset("tight_room.log.json"), &log).unwrap();
    std::fs::write(dir.path().join("bad.params.json"), "{ nope").unwrap();
    h.state_mut().push(Command::Open(log));
    h.state_mut()
        .push(Command::SetFileDialog(DialogBackend::InApp));
    h.state_mut().push(Command::LoadParamsDialog);
    h.run();
    let (purpose, folder) = h.state().file_dialog().expect("the in-app dialog is open");
    assert_eq!((purpose, folder), (FilePurpose::LoadParams, dir.path()));
    h.get_by_label("bad.params.json").click();
    h.run();
    h.get_by_label("Open").click();
    h.run();
    let banner = h.state().banner().expect("the error is in the banner");
    assert!(banner.contains("bad.params.json"), "{banner}");
}

#[test]
fn a_table_opens_through_the_layout_picker() {
    let run = sonarmap::assets::default_run().unwrap();
    let mut h = harness(SonarApp::new(run, None));
    h.run();
    let table = fixture_path("nomad_tiny.table.csv");
    h.state_mut().push(Command::Open(table));
    h.run();
    assert!(h.state().banner().is_none(), "{:?}", h.state().banner());
    assert!(h.state().layout_picker().is_some(), "the picker waits");
    assert!(h.query_by_label("This log needs a sensor layout").is_some());
    h.get_by_label("in").click();
    h.get_by_label("nomad_200").click();
    h.run();
    assert!(h.state().layout_picker().is_none());
    assert!(h.state().banner().is_none(), "{:?}", h.state().banner());
    assert_eq!(h.state().len(), 2);
    assert_eq!(h.state().run().units, sonarmap::units::Units::Inches);

    // Cancelling keeps the run that was open.
    let table = fixture_path("nomad_tiny.table.csv");
    h.state_mut()
        .push(Command::Open(asset("tight_room.log.json")));
    h.run();
    let name = h.state().run().name.clone();
    h.state_mut().push(Command::Open(table));
    h.run();
    h.get_by_label("Cancel").click();
    h.run();
    assert!(h.state().layout_picker().is_none());
    assert_eq!(h.state().run().name, name);

    // A table of ranges only takes its poses from a second file.
    let dir = tempfile::tempdir().unwrap();
    let ranges = dir.path().join("ranges.txt");
    let poses = dir.path().join("poses.txt");
    std::fs::write(
        &ranges,
        "0.0 48.2 51 - 110.4 230 97.3 77 75.1 74.9 76 80.2 99 - 60 52.3 49.9\n",
    )
    .unwrap();
    std::fs::write(&poses, "-1 120 77 0\n1 130 77 90\n").unwrap();
    h.state_mut().push(Command::Open(ranges));
    h.run();
    assert!(h.query_by_label("Poses table: none").is_some());
    h.state_mut().push(Command::SetPosesFile(poses.clone()));
    h.run();
    assert!(h
        .query_by_label(&format!("Poses table: {}", poses.display()))
        .is_some());
    h.get_by_label("in").click();
    h.get_by_label("nomad_200").click();
    h.run();
    assert!(h.state().banner().is_none(), "{:?}", h.state().banner());
    assert_eq!(h.state().len(), 1);
    let pose = h.state().run().snapshots[0].pose;
    assert!(
        (pose.x - sonarmap::units::inches(125.0)).abs() < 1e-9,
        "{pose:?}"
    );
}

#[test]
fn parameters_that_differ_from_the_preset_are_named_in_the_title_and_status_bar() {
    let mut h = building();
    assert!(!h.state().window_title().contains('≠'));
    assert!(h.query_by_label("parameters ≠ paper").is_none());
    let mut p = h.state().params().clone();
    p.t_gap_m *= 2.0;
    h.state_mut().push(Command::SetParams(p));
    settle(&mut h);
    assert_eq!(h.state().changed_params(), vec!["t_gap"]);
    assert!(h
        .state()
        .window_title()
        .contains("parameters ≠ paper (t_gap)"));
    assert!(h.query_by_label("parameters ≠ paper").is_some());
    // The preset's value beside the field, marked; an unchanged field is not.
    assert!(h.query_by_label("≠ 42 in").is_some(), "t_gap is marked");
    assert!(h.query_by_label("≠ 255 in").is_none(), "d_max is not");
    // The extended preset: its own values are not a difference.
    h.state_mut()
        .push(Command::SetPreset(sonarmap::mapping::Preset::Extended));
    settle(&mut h);
    assert!(h.state().changed_params().is_empty());
    assert!(h.query_by_label_contains("parameters ≠").is_none());
}

#[test]
fn the_export_is_what_the_screen_shows_and_a_png_name_writes_a_png() {
    let mut h = building();
    h.state_mut().push(Command::Seek(150));
    h.run();
    let id = h.state().step_view().unwrap().map_after.segments[0].id;
    h.state_mut()
        .push(Command::Select(sonarmap::scene::SceneId::MapSegment(id)));
    h.state_mut().push(Command::ZoomToSelection);
    h.state_mut()
        .push(Command::ToggleLayer(sonarmap::scene::Layer::Balls));
    h.run();
    let dir = tempfile::tempdir().unwrap();
    let svg_path = dir.path().join("view.svg");
    h.state_mut().push(Command::ExportSvg(svg_path.clone()));
    h.run();
    assert!(h.state().banner().is_none(), "{:?}", h.state().banner());
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    assert!(
        !svg.contains("<g id=\"balls\""),
        "a layer switched off is not exported"
    );
    assert!(svg.contains("#ffb020"), "the selection has its halo");
    // The visible region, not the whole map: far fewer map labels than the full figure has.
    let labels = |svg: &str| svg.matches(">s").count();
    let full = sonarmap::scene::figure::figure_svg(
        &sonarmap::scene::SceneInput::from_view(h.state().run(), h.state().step_view().unwrap()),
        &sonarmap::scene::figure::Figure {
            view: None,
            layers: h.state().layers(),
            size_px: (1600, 1200),
            selection: sonarmap::scene::SceneId::None,
            figure_style: false,
            title: String::new(),
        },
        h.state().run().units,
    );
    assert!(
        labels(&svg) < labels(&full),
        "{} vs {}",
        labels(&svg),
        labels(&full)
    );
    let png_path = dir.path().join("view.png");
    h.state_mut().push(Command::ExportSvg(png_path.clone()));
    h.run();
    let png = std::fs::read(&png_path).expect("the PNG is written");
    assert_eq!(&png[1..4], b"PNG");
}

/// A crawl's support from the last view's place is traced and the inspector says why it did
/// not count (docs/algorithm.md §8.7, `confirm_spacing`).
#[test]
fn the_inspector_says_when_a_plane_support_was_the_same_view() {
    use sonarmap::mapping::{Mapper, Params};
    let mut run = super::support::pioneer_corridor_crawl(2);
    run.snapshots.truncate(40);
    let mut mapper = Mapper::new(Params::extended(), run.layout.clone(), run.sensor);
    let same_view = run
        .snapshots
        .iter()
        .map(|s| mapper.step(s))
        .find(|t| {
            t.plane_support
                .iter()
                .any(|p| p.same_view_moved_m.is_some())
        })
        .expect("a crawl reads its first wall again from the same place")
        .snapshot;
    let mut h = harness(SonarApp::new(run, None));
    settle(&mut h);
    h.state_mut().push(Command::SetParams(Params::extended()));
    settle(&mut h);
    h.state_mut().push(Command::Seek(same_view));
    h.run();
    assert!(h
        .query_by_label_contains("plane support not counted")
        .is_some());
}

/// A step that stood still says so in the decisions and the inspector (docs/algorithm.md
/// §8.19, `standstill`).
#[test]
fn the_inspector_says_when_the_robot_stood_still() {
    use sonarmap::mapping::Params;
    let mut run = super::support::pioneer_corridor_crawl(2);
    run.snapshots.truncate(30);
    // Snapshot 20 read again five times from the same pose: snapshots 21–25 stand still.
    let standing = run.snapshots[20].clone();
    let later: Vec<_> = run.snapshots.split_off(21);
    for k in 1..=5 {
        run.snapshots.push(sonarmap::run::Snapshot {
            t: standing.t + 0.3 * k as f64,
            ..standing.clone()
        });
    }
    run.snapshots.extend(
        later
            .into_iter()
            .map(|s| sonarmap::run::Snapshot { t: s.t + 1.5, ..s }),
    );
    let mut h = harness(SonarApp::new(run, None));
    settle(&mut h);
    h.state_mut().push(Command::SetParams(Params::extended()));
    settle(&mut h);
    h.state_mut().push(Command::Seek(23));
    h.run();
    assert!(h
        .query_by_label_contains("stood still since snapshot 20")
        .is_some());
    assert!(h
        .query_by_label_contains("the robot stood still: this snapshot's readings were set aside")
        .is_some());
    h.state_mut().push(Command::Seek(27));
    h.run();
    assert!(h.query_by_label_contains("stood still since").is_none());
}

/// A step whose cluster link was broken across a right angle says so in the inspector, once
/// for the pair (docs/algorithm.md §8.20, `right_angle_break`).
#[test]
fn the_inspector_names_a_link_broken_across_a_right_angle() {
    use sonarmap::geometry::Pose;
    use sonarmap::mapping::Params;
    // Four sonars at the centre (front, left, back, right); each snapshot reads 0.3 m ahead and
    // 0.4 m to the left, 0.5 m apart, within t_gap.
    let mut run = super::support::pioneer_corridor_crawl(2);
    run.layout = super::support::layout_of(
        [0.0f64, 90.0, 180.0, -90.0].map(|deg| (0.0, 0.0, deg.to_radians())),
    );
    run.sensor.min_range_m = 0.02;
    run.snapshots = (0..3)
        .map(|k| sonarmap::run::Snapshot {
            t: k as f64,
            pose: Pose::new(0.01 * k as f64, 0.0, 0.0),
            ranges_m: vec![Some(0.3), Some(0.4), None, None],
            true_pose: None,
            reading_dt_s: Vec::new(),
        })
        .collect();
    let params = Params {
        min_range_m: 0.02,
        ..Params::extended()
    };
    let mut h = harness(SonarApp::new(run, None));
    settle(&mut h);
    h.state_mut().push(Command::SetParams(params));
    settle(&mut h);
    h.state_mut().push(Command::Seek(1));
    h.run();
    let lines = h.query_all_by_label_contains("right-angle break").count();
    assert_eq!(lines, 1, "one line for the pair of sensors 0 and 1");
    assert!(h
        .query_by_label_contains("sensors 0 and 1, axes 90° apart")
        .is_some());
}

/// A step where point memory cut a bent group before its fit says so in the inspector, with
/// the group's size and the widest gap (docs/algorithm.md §8.1).
#[test]
fn the_inspector_says_where_point_memory_cut_a_group() {
    use sonarmap::mapping::{Mapper, Params};
    let mut run = super::support::pioneer_corridor_crawl(2);
    run.snapshots.truncate(400);
    let mut mapper = Mapper::new(Params::extended(), run.layout.clone(), run.sensor);
    let cut = run
        .snapshots
        .iter()
        .map(|s| mapper.step(s))
        .find(|t| {
            t.memory
                .as_ref()
                .is_some_and(|m| m.groups.iter().any(|g| !g.cuts.is_empty()))
        })
        .expect("the crawl's point memory cuts a group at the corridor's corners")
        .snapshot;
    let mut h = harness(SonarApp::new(run, None));
    settle(&mut h);
    h.state_mut().push(Command::SetParams(Params::extended()));
    settle(&mut h);
    h.state_mut().push(Command::Seek(cut));
    h.run();
    assert!(h
        .query_by_label_contains("point memory cut: a group of")
        .is_some());
}

/// `echo_agreement` (docs/algorithm.md §8.21): a crosstalk echo among a wall's readings, on the
/// Pioneer stand-in's crawl, is set aside, and the inspector gives its status and the numbers
/// of the refusal (the sensor's last echo, how much shorter, the tolerance).
#[test]
fn the_inspector_gives_a_refused_short_readings_last_echo() {
    use sonarmap::app::Command;
    use sonarmap::mapping::model::trace::DiscardReason;
    use sonarmap::mapping::{Mapper, Params};
    use sonarmap::scene::SceneId;
    let mut run = super::support::pioneer_corridor_crawl(1);
    let (snapshot, sensor) = (1..run.snapshots.len())
        .flat_map(|k| (0..8).map(move |s| (k, s)))
        .find(|&(k, s)| {
            let echo = |j: usize| run.snapshots[j].ranges_m[s].filter(|d| *d > 1.5 && *d < 4.0);
            echo(k - 1).is_some() && echo(k).is_some()
        })
        .expect("a sensor reading a wall twice");
    run.snapshots[snapshot].ranges_m[sensor] = Some(0.5);
    let params = Params {
        echo_agreement: true,
        ..Params::extended()
    };
    let mut mapper = Mapper::new(params.clone(), run.layout.clone(), run.sensor);
    let trace = run
        .snapshots
        .iter()
        .take(snapshot + 1)
        .map(|s| mapper.step(s))
        .last()
        .unwrap();
    assert_eq!(
        trace.readings[sensor].discarded,
        Some(DiscardReason::ShorterThanLast)
    );
    let mut h = super::support::harness(sonarmap::app::SonarApp::new(run, None));
    super::support::settle(&mut h);
    h.state_mut().push(Command::SetParams(params));
    super::support::settle(&mut h);
    h.state_mut().push(Command::Seek(snapshot));
    h.run();
    // The step's extensions list the refusal too.
    let listed = format!("echo agreement: sensor {sensor} read 0.500 m after");
    assert!(h.query_by_label_contains(&listed).is_some(), "{listed}");
    h.state_mut()
        .push(Command::Select(SceneId::Reading { snapshot, sensor }));
    h.run();
    assert!(h
        .query_by_label_contains("much shorter than the sensor's last echo")
        .is_some());
    assert!(h.query_by_label("sensor's last echo").is_some());
    let last_m = trace.readings[sensor]
        .shorter_than_last
        .expect("the refusal's numbers")
        .last_m;
    let row = format!("{last_m:.3} m: {:.3} m shorter", last_m - 0.5);
    assert!(h.query_by_label_contains(&row).is_some(), "{row}");
}
