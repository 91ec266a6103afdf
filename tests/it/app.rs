//! The inspector driven through egui_kittest (no GPU): every test goes through the app's
//! command path or clicks widgets by label.

use super::support::{asset, building, harness, settle, MemoryStorage};
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use sonarmap::app::{
    decision_row_text, snapshot_label, Command, CompareState, Settings, SonarApp, SETTINGS_KEY,
};
use sonarmap::mapping::Params;
use sonarmap::scene::{Layer, SceneId};
use std::path::PathBuf;

fn shows_index(h: &Harness<SonarApp>, k: usize) {
    let label = snapshot_label(k, h.state().len());
    assert!(h.query_by_label(&label).is_some(), "no label {label:?}");
    assert_eq!(h.state().current(), k);
}

#[test]
fn steps_forward_and_back_with_buttons_and_keys() {
    let mut h = building();
    shows_index(&h, 0);
    h.get_by_label(">").click();
    h.run();
    shows_index(&h, 1);
    h.key_press(egui::Key::ArrowRight);
    h.run();
    shows_index(&h, 2);
    h.key_press(egui::Key::ArrowLeft);
    h.run();
    shows_index(&h, 1);
    h.key_press(egui::Key::End);
    h.run();
    let last = h.state().len() - 1;
    shows_index(&h, last);
    h.get_by_label("<").click();
    h.run();
    shows_index(&h, last - 1);
    h.key_press(egui::Key::Home);
    h.run();
    shows_index(&h, 0);
    h.state_mut().push(Command::Seek(usize::MAX));
    h.run();
    shows_index(&h, last);
}

#[test]
fn plays_then_pauses() {
    let mut h = building();
    h.state_mut().push(Command::SetRate(30.0));
    h.run();
    h.get_by_label("Play").click();
    h.run_steps(12);
    assert!(h.state().is_playing());
    let k = h.state().current();
    assert!(k > 0, "playback advanced");
    h.get_by_label("Pause").click();
    h.run_steps(2);
    assert!(!h.state().is_playing());
    let k = h.state().current();
    h.run_steps(8);
    assert_eq!(h.state().current(), k, "paused playback does not move");
}

#[test]
fn jumps_to_the_next_and_previous_mark() {
    let mut h = building();
    let marks: Vec<usize> = h
        .state()
        .marks()
        .iter()
        .copied()
        .filter(|&m| m > 0)
        .collect();
    assert!(marks.len() >= 2, "the building run has notable steps");
    h.get_by_label("Next mark >").click();
    h.run();
    shows_index(&h, marks[0]);
    h.key_press(egui::Key::CloseBracket);
    h.run();
    shows_index(&h, marks[1]);
    h.get_by_label("< Prev mark").click();
    h.run();
    shows_index(&h, marks[0]);
}

/// The first snapshot with a decision that tested candidates, and that decision's index.
fn step_with_candidates(h: &mut Harness<SonarApp>) -> (usize, usize) {
    for k in 0..h.state().len() {
        h.state_mut().apply(Command::Seek(k));
        let view = h.state().step_view().unwrap();
        if let Some(d) = view
            .trace
            .decisions
            .iter()
            .find(|d| !d.mpc_stage.is_empty())
        {
            return (k, d.new_segment);
        }
    }
    panic!("no decision with candidates in the building run");
}

#[test]
fn selecting_a_new_segment_shows_its_candidate_table() {
    let mut h = building();
    let (k, i) = step_with_candidates(&mut h);
    h.state_mut().push(Command::Seek(k));
    h.state_mut().push(Command::Select(SceneId::NewSegment(i)));
    h.run();
    assert!(h
        .query_by_label(&format!("New segment n{i} (snapshot {k})"))
        .is_some());
    assert!(h.query_by_label("Orientation").is_some());
    assert!(h.query_by_label("θ_o").is_some());
    assert!(h.query_by_label("Colinearity d").is_some());
    assert!(h.query_by_label("deciding rule").is_some());
    let before = h.state().map_view().visible_m.unwrap();
    h.key_press(egui::Key::Z);
    h.run();
    let after = h.state().map_view().visible_m.unwrap();
    assert!(
        after.width_m() < before.width_m(),
        "zoomed onto the segment"
    );
    // Orientation and colinearity give a verdict with its margin, the overlap a verdict.
    let verdicts = h.query_all_by_label_contains("pass, margin").count()
        + h.query_all_by_label_contains("FAIL, margin").count();
    assert!(verdicts >= 2, "pass/fail cells with margins for every test");
    let overlap = h.query_all_by_label_contains("pass ").count()
        + h.query_all_by_label_contains("FAIL ").count();
    assert!(overlap >= 1, "an overlap verdict");
}

#[test]
fn clicking_a_decision_row_selects_it() {
    let mut h = building();
    let (k, i) = step_with_candidates(&mut h);
    h.state_mut().push(Command::Seek(k));
    h.state_mut().push(Command::Select(SceneId::None));
    h.run();
    let d = h
        .state()
        .step_view()
        .unwrap()
        .trace
        .decisions
        .iter()
        .find(|d| d.new_segment == i)
        .unwrap()
        .clone();
    h.get_by_label(&decision_row_text(&d)).click();
    h.run();
    assert_eq!(h.state().selection(), SceneId::NewSegment(i));
    assert!(h.query_by_label("Orientation").is_some());
}

#[test]
fn compare_with_runs_the_three_tests() {
    let mut h = building();
    h.key_press(egui::Key::End);
    h.run();
    let ids: Vec<_> = h
        .state()
        .step_view()
        .unwrap()
        .map_after
        .segments
        .iter()
        .map(|s| s.id)
        .take(2)
        .collect();
    assert_eq!(ids.len(), 2);
    h.state_mut()
        .push(Command::Select(SceneId::MapSegment(ids[0])));
    h.run();
    // The inspector is narrow by default: the button may be below its fold.
    h.get_by_label("Compare with…").scroll_to_me();
    h.run();
    h.get_by_label("Compare with…").click();
    h.run();
    assert_eq!(*h.state_compare(), CompareState::Armed(ids[0]));
    h.state_mut()
        .push(Command::Select(SceneId::MapSegment(ids[1])));
    h.run();
    assert!(
        matches!(h.state_compare(), CompareState::Done { existing, .. } if *existing == ids[0])
    );
    assert!(h.query_by_label("Containment").is_some());
    assert!(h.query_by_label("Orientation").is_some());
}

trait CompareOf {
    fn state_compare(&self) -> &CompareState;
}

impl CompareOf for Harness<'_, SonarApp> {
    fn state_compare(&self) -> &CompareState {
        self.state().compare()
    }
}

#[test]
fn switching_a_layer_off_removes_it_from_the_scene() {
    let mut h = building();
    h.state_mut().push(Command::Seek(5));
    h.run();
    assert!(h
        .state()
        .scene()
        .unwrap()
        .layers_present()
        .contains(Layer::Map));
    h.get_by_label("Layers").click();
    h.run();
    h.get_by_label(Layer::Map.label()).click();
    h.run();
    assert!(!h.state().layers().contains(Layer::Map));
    assert!(!h
        .state()
        .scene()
        .unwrap()
        .layers_present()
        .contains(Layer::Map));
    h.state_mut().push(Command::ToggleLayer(Layer::Map));
    h.run();
    assert!(h
        .state()
        .scene()
        .unwrap()
        .layers_present()
        .contains(Layer::Map));
}

#[test]
fn exports_the_view_as_svg() {
    let mut h = building();
    h.state_mut().push(Command::Seek(3));
    h.run();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("view.svg");
    h.state_mut().push(Command::ExportSvg(path.clone()));
    h.run();
    assert!(h.state().banner().is_none(), "{:?}", h.state().banner());
    let text = std::fs::read_to_string(&path).unwrap();
    let tree = usvg::Tree::from_str(&text, &usvg::Options::default()).expect("the export parses");
    assert!(tree.size().width() > 100.0);
    assert!(text.contains("snapshot 3"));
    assert!(text.contains("id=\"map\""));
    // A write error goes to the banner, not a panic.
    h.state_mut().push(Command::ExportSvg(
        dir.path().join("missing-dir").join("x.svg"),
    ));
    h.run();
    assert!(h.state().banner().unwrap().contains("Could not write"));
}

#[test]
fn a_broken_log_shows_a_banner_and_keeps_the_run() {
    let mut h = building();
    h.state_mut().push(Command::Seek(4));
    h.run();
    let name = h.state().run().name.clone();
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.json");
    std::fs::write(
        &bad,
        br#"{"format": "sonarmap-log", "version": 1, "units": "furlong"}"#,
    )
    .unwrap();
    h.state_mut().push(Command::Open(bad));
    h.run();
    let banner = h.state().banner().expect("banner").to_owned();
    assert!(banner.contains("broken.json"), "{banner}");
    assert!(h.query_by_label_contains("Could not open").is_some());
    assert_eq!(h.state().run().name, name);
    shows_index(&h, 4);
    h.get_by_label("Dismiss").click();
    h.run();
    assert!(h.state().banner().is_none());
    h.state_mut()
        .push(Command::Open(dir.path().join("does-not-exist.json")));
    h.run();
    assert!(h.state().banner().unwrap().contains("does-not-exist.json"));
    assert_eq!(h.state().run().name, name);
}

#[test]
fn settings_persist_and_corrupt_values_are_ignored() {
    let run = sonarmap::assets::default_run().unwrap();
    let mut app = SonarApp::new(run.clone(), None);
    app.apply(Command::ToggleLayer(Layer::Balls));
    app.apply(Command::Open(asset("tight_room.log.json")));
    let mut storage = MemoryStorage::default();
    eframe::App::save(&mut app, &mut storage);
    let again = SonarApp::new(run.clone(), Some(&storage));
    assert!(!again.layers().contains(Layer::Balls));
    assert_eq!(again.settings().recent, vec![asset("tight_room.log.json")]);

    let mut corrupt = MemoryStorage::default();
    corrupt
        .0
        .insert(SETTINGS_KEY.to_owned(), "{not json".to_owned());
    assert_eq!(
        *SonarApp::new(run.clone(), Some(&corrupt)).settings(),
        Settings::default()
    );
    corrupt.0.insert(
        SETTINGS_KEY.to_owned(),
        r#"{"rate": -3, "recent": []}"#.to_owned(),
    );
    let app = SonarApp::new(run, Some(&corrupt));
    assert!(app.settings().rate > 0.0);
}

/// The building asset's log driven back and forth for 3,000 snapshots (seconds to replay in
/// a test build: a replay of it is still running after the next frames).
fn long_building_log() -> String {
    let lap = sonarmap::log::load_run(
        &std::fs::read(asset("building.log.json")).unwrap(),
        "building.log.json",
    )
    .unwrap();
    sonarmap::log::save_run(&sonarmap::bench::back_and_forth(&lap, 3000))
}

/// The building's harness, then [`long_building_log`] opened as a large run: its preview
/// shown, the whole replay running.
fn previewing_long_building() -> Harness<'static, SonarApp> {
    let mut h = building();
    h.state_mut().set_background_threshold(100);
    open_long_building(&mut h);
    assert_eq!(h.state().len(), 256);
    h
}

/// Opens [`long_building_log`] as "big.json", one frame.
fn open_long_building(h: &mut Harness<'static, SonarApp>) {
    h.state_mut().push(Command::OpenBytes {
        name: "big.json".to_owned(),
        bytes: long_building_log().into_bytes(),
    });
    h.step();
}

#[test]
fn a_large_run_shows_its_first_snapshots_at_once_and_the_rest_once_replayed() {
    let mut h = building();
    h.state_mut().set_background_threshold(100);
    // Stepped on from the old run's first snapshot: the new one opens at its own first.
    h.key_press(egui::Key::ArrowRight);
    h.step();
    assert_eq!(h.state().current(), 1);
    open_long_building(&mut h);
    assert!(h.state().is_loading());
    assert_eq!(
        *h.state().source(),
        sonarmap::app::Source::Bytes("big.json".to_owned()),
        "the new run is shown at once"
    );
    assert_eq!(
        h.state().len(),
        256,
        "its first snapshots, while the rest replays"
    );
    assert_eq!(h.state().current(), 0);
    h.step();
    h.get_by_label_contains("(the first 256 while replaying)");
    // The status bar's progress: the share, the count, the rate and the time left.
    h.get_by_label_contains("snapshots/s ·");
    h.key_press(egui::Key::ArrowRight);
    h.key_press(egui::Key::ArrowRight);
    h.step();
    assert_eq!(h.state().current(), 2, "and usable");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(300);
    while h.state().is_loading() && std::time::Instant::now() < deadline {
        std::thread::sleep(std::time::Duration::from_millis(20));
        h.step();
    }
    assert!(h.state().banner().is_none(), "{:?}", h.state().banner());
    assert!(!h.state().is_loading());
    assert_eq!(
        *h.state().source(),
        sonarmap::app::Source::Bytes("big.json".to_owned())
    );
    assert_eq!(h.state().len(), 3000, "the whole run");
    assert_eq!(h.state().current(), 2, "where the preview was left");
    // The same maps as the run opened in one go.
    let whole = sonarmap::replay::Replay::new(h.state().run().clone(), h.state().params().clone());
    h.state_mut().push(Command::Seek(2900));
    h.step();
    assert_eq!(h.state().step_view().unwrap().map_after, whole.map_at(2900));
}

#[test]
fn a_baseline_is_pinned_on_the_whole_run_not_on_its_preview() {
    let mut h = previewing_long_building();
    h.state_mut().push(Command::PinBaseline);
    h.step();
    assert!(
        !h.state().is_pinned(),
        "refused while the whole run replays"
    );
    assert!(
        h.state().message().contains("still replaying"),
        "{}",
        h.state().message()
    );
    settle(&mut h);
    h.state_mut().push(Command::PinBaseline);
    settle(&mut h);
    assert!(h.state().is_pinned());
}

#[test]
fn a_reload_of_a_large_run_returns_to_its_snapshot_even_through_new_parameters() {
    let mut h = building();
    h.state_mut().set_background_threshold(100);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long.log.json");
    std::fs::write(&path, long_building_log()).unwrap();
    h.state_mut().push(Command::Open(path));
    settle(&mut h);
    h.state_mut().push(Command::Seek(2000));
    h.step();
    h.state_mut().push(Command::Reload);
    h.step();
    assert_eq!(h.state().len(), 256, "the preview");
    assert_eq!(h.state().current(), 255, "as far as it goes");
    // New parameters during the reload's preview: the re-run goes back to 2,000 too.
    h.state_mut()
        .push(Command::SetParams(sonarmap::mapping::Params::extended()));
    settle(&mut h);
    assert_eq!(h.state().len(), 3000);
    assert_eq!(h.state().current(), 2000);
}

#[test]
fn new_parameters_while_a_large_run_opens_rerun_the_whole_run() {
    let mut h = previewing_long_building();
    let extended = sonarmap::mapping::Params::extended();
    h.state_mut().push(Command::SetParams(extended.clone()));
    settle(&mut h);
    assert_eq!(h.state().len(), 3000, "the whole run, not the preview");
    assert_eq!(h.state().params(), &extended);
}

// ---- Live parameters, A/B comparison, bookmarks (issue 6) ----

/// Replaces the text of the parameter field labelled `label` and presses Enter.
fn set_field(h: &mut Harness<'static, SonarApp>, label: &str, text: &str) {
    h.get_by_label(label).focus();
    h.run();
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::A);
    h.run();
    h.get_by_label(label).type_text(text);
    h.run();
    h.key_press(egui::Key::Enter);
    h.step();
    settle(h);
}

/// The decision rows of every snapshot of the building run under `params`.
fn rows(params: &sonarmap::mapping::Params) -> Vec<Vec<String>> {
    let run = sonarmap::log::load_run(
        &std::fs::read(asset("building.log.json")).unwrap(),
        "building",
    )
    .unwrap();
    let mut mapper = sonarmap::mapping::Mapper::new(params.clone(), run.layout.clone(), run.sensor);
    run.snapshots
        .iter()
        .map(|s| {
            mapper
                .step(s)
                .decisions
                .iter()
                .map(decision_row_text)
                .collect()
        })
        .collect()
}

#[test]
fn changing_t_gap_in_the_panel_changes_the_decisions_list() {
    let mut h = building();
    let paper = sonarmap::mapping::Params::paper();
    let before = rows(&paper);
    // The first of these t_gap values (inches) that changes a decision row, and a row that
    // exists under one value only (it appears or disappears with the change).
    let (t_gap_in, small, k, row, appears) = [5.0, 12.0, 24.0, 80.0, 200.0]
        .into_iter()
        .find_map(|t_gap_in: f64| {
            let mut small = paper.clone();
            small.t_gap_m = sonarmap::units::inches(t_gap_in);
            let after = rows(&small);
            (0..before.len()).find_map(|k| {
                let new = after[k].iter().find(|r| !before[k].contains(r));
                let gone = before[k].iter().find(|r| !after[k].contains(r));
                new.map(|r| (r.clone(), true))
                    .or(gone.map(|r| (r.clone(), false)))
                    .map(|(r, appears)| (t_gap_in, small.clone(), k, r, appears))
            })
        })
        .expect("some t_gap changes a decision");
    h.state_mut().push(Command::Seek(k));
    h.run();
    assert_eq!(h.query_by_label(&row).is_some(), !appears, "{row:?} before");
    set_field(&mut h, "t_gap", &t_gap_in.to_string());
    assert_eq!(h.state().current(), k, "the snapshot is kept");
    assert!(
        (h.state().shown_params().t_gap_m - small.t_gap_m).abs() < 1e-12,
        "t_gap applied in inches"
    );
    assert_eq!(h.query_by_label(&row).is_some(), appears, "{row:?} after");
    assert!(h.state().last_rerun_s().is_some());

    // An invalid value is refused in the field with the reason; nothing changes.
    set_field(&mut h, "t_gap", "-3");
    let reason = h.state().params_error("t_gap").expect("refused");
    assert!(reason.contains("t_gap"), "{reason}");
    assert!(h.query_by_label_contains("refused:").is_some());
    assert!((h.state().params().t_gap_m - small.t_gap_m).abs() < 1e-12);
    set_field(&mut h, "θ_o (°)", "95");
    assert!(h.state().params_error("orientation_deg").is_some());
    assert_eq!(h.state().params().orientation_rad, paper.orientation_rad);

    h.get_by_label("Reset to the paper's defaults").click();
    h.step();
    settle(&mut h);
    assert_eq!(*h.state().shown_params(), paper);
    assert_eq!(h.query_by_label(&row).is_some(), !appears);
}

#[test]
fn pinning_a_baseline_then_changing_theta_marks_the_differing_decisions() {
    let mut h = building();
    h.get_by_label("Pin as baseline").click();
    h.step();
    settle(&mut h);
    assert!(h.state().is_pinned());
    assert_eq!(
        h.state().baseline_diff().map(|d| d.snapshots.len()),
        Some(0)
    );
    set_field(&mut h, "θ_o (°)", "3");
    let diff = h
        .state()
        .baseline_diff()
        .expect("comparison computed")
        .clone();
    assert!(!diff.snapshots.is_empty(), "θ_o = 3° changes some decision");
    // The timeline marks only the snapshots with a direct difference (the parameter change
    // itself), fewer than those that differ at all.
    assert!(diff.direct > 0 && diff.direct_snapshots.len() < diff.snapshots.len());
    let label = format!(
        "≠ baseline: {} snapshots with a direct difference",
        diff.direct_snapshots.len()
    );
    assert!(
        h.query_by_label(&label).is_some(),
        "timeline shows {label:?}"
    );

    // "First difference" seeks to the first direct difference.
    let k = diff.direct_snapshots[0];
    assert_eq!(diff.first_difference, Some(k));
    // The button sits low in the parameters panel: scrolled into view before the click.
    h.get_by_label("First difference").scroll_to_me();
    h.run();
    h.get_by_label("First difference").click();
    h.run();
    assert_eq!(h.state().current(), k);
    let here = h.state().differences_here();
    assert!(!here.is_empty());
    assert!(
        h.query_all_by_label_contains("≠ baseline").next().is_some(),
        "a decision row is marked"
    );
    // The inspector shows the baseline's tests beside the current ones.
    if let Some(b) = here.iter().find_map(|d| d.b) {
        h.state_mut()
            .push(Command::Select(SceneId::NewSegment(b.new_segment)));
        h.run();
        assert!(h.query_by_label("Against the baseline").is_some());
    }
    h.get_by_label("Unpin baseline").click();
    h.run();
    assert!(!h.state().is_pinned());
    assert!(h.query_all_by_label_contains("≠ baseline").next().is_none());
}

#[test]
fn a_parameter_set_saves_and_loads_in_the_params_format() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tuned.json");
    let mut h = building();
    set_field(&mut h, "t_gap", "20");
    set_field(&mut h, "ξ accuracy (%)", "4.5");
    let tuned = h.state().params().clone();
    h.state_mut().push(Command::SaveParams(path.clone()));
    h.run();
    let text = std::fs::read_to_string(&path).unwrap();
    let file: sonarmap::mapping::ParamsFile = serde_json::from_str(&text).unwrap();
    assert_eq!(file.t_gap, Some(20.0), "{text}");
    assert_eq!(file.units.as_deref(), Some("in"));
    h.get_by_label("Paper").click();
    h.step();
    settle(&mut h);
    assert_eq!(*h.state().params(), sonarmap::mapping::Params::paper());
    h.state_mut().push(Command::LoadParams(path.clone()));
    h.step();
    settle(&mut h);
    let loaded = h.state().shown_params();
    assert!((loaded.t_gap_m - tuned.t_gap_m).abs() < 1e-12);
    assert_eq!(loaded.accuracy_pct, 4.5);
    // A broken file is refused with a banner; the parameters stay.
    std::fs::write(&path, r#"{"t_gap": -1}"#).unwrap();
    h.state_mut().push(Command::LoadParams(path.clone()));
    h.run();
    assert!(h.state().banner().unwrap().contains("t_gap"));
    assert!((h.state().params().t_gap_m - tuned.t_gap_m).abs() < 1e-12);
    // The last parameters persist.
    let mut storage = MemoryStorage::default();
    eframe::App::save(h.state_mut(), &mut storage);
    let run = sonarmap::assets::default_run().unwrap();
    let again = SonarApp::new(run, Some(&storage));
    assert_eq!(again.params().t_gap_m, tuned.t_gap_m);
}

#[test]
fn a_parameter_set_saved_before_a_parameter_existed_takes_its_presets_value_for_it() {
    let run = sonarmap::assets::default_run().unwrap();
    // An extended set as an older version saved it: no `standstill_m`, no `revisit_laps`, and
    // one edited value.
    let mut saved = serde_json::to_value(Params::extended()).unwrap();
    let fields = saved.as_object_mut().unwrap();
    fields.remove("standstill_m");
    fields.remove("revisit_laps");
    fields.insert("t_gap_m".to_owned(), serde_json::json!(0.5));
    for (preset, expected) in [("extended", Params::extended()), ("paper", Params::paper())] {
        let mut storage = MemoryStorage::default();
        let settings = serde_json::json!({ "preset": preset, "params": saved });
        storage
            .0
            .insert(SETTINGS_KEY.to_owned(), settings.to_string());
        let app = SonarApp::new(run.clone(), Some(&storage));
        assert_eq!(app.params().standstill_m, expected.standstill_m, "{preset}");
        assert_eq!(app.params().revisit_laps, expected.revisit_laps, "{preset}");
        assert_eq!(app.params().t_gap_m, 0.5, "{preset}: the saved value stays");
    }
    assert_ne!(
        Params::extended().standstill_m,
        Params::paper().standstill_m
    );
    assert_ne!(
        Params::extended().revisit_laps,
        Params::paper().revisit_laps
    );
}

#[test]
fn a_corrupt_settings_value_is_ignored_with_a_notice() {
    let run = sonarmap::assets::default_run().unwrap();
    let mut storage = MemoryStorage::default();
    storage.0.insert(
        SETTINGS_KEY.to_owned(),
        r#"{"rate": "fast", "hidden_layers": 7, "recent": ["/tmp/a.json"], "params": {"t_gap_m": "far"}}"#
            .to_owned(),
    );
    let mut h = harness(SonarApp::new(run.clone(), Some(&storage)));
    h.run();
    let message = h.state().message().to_owned();
    for bad in ["rate", "hidden_layers", "params"] {
        assert!(message.contains(bad), "{message}");
    }
    assert!(h.query_by_label(&message).is_some(), "status bar shows it");
    assert_eq!(
        h.state().settings().recent,
        vec![PathBuf::from("/tmp/a.json")],
        "good values kept"
    );
    assert_eq!(h.state().settings().rate, Settings::default().rate);
    storage
        .0
        .insert(SETTINGS_KEY.to_owned(), "{not json".to_owned());
    let app = SonarApp::new(run, Some(&storage));
    assert!(
        app.message().contains("settings ignored"),
        "{}",
        app.message()
    );
}

#[test]
fn bookmarks_are_added_jumped_to_and_saved_beside_the_log() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("building.log.json");
    std::fs::copy(asset("building.log.json"), &log).unwrap();
    let run = sonarmap::assets::default_run().unwrap();
    let mut h = harness(SonarApp::new(run.clone(), None));
    h.run();
    h.state_mut().push(Command::Open(log.clone()));
    h.state_mut().push(Command::Seek(7));
    h.run();
    h.get_by_label("Bookmarks").click();
    h.run();
    h.get_by_label("Add bookmark").click();
    h.run();
    assert_eq!(h.state().bookmarks().len(), 1);
    let side = sonarmap::app::bookmarks_path(&log);
    assert_eq!(side, dir.path().join("building.log.json.bookmarks.json"));
    let text = std::fs::read_to_string(&side).expect("sidecar written");
    assert!(text.contains("\"snapshot\": 7"), "{text}");
    h.key_press(egui::Key::Home);
    h.run();
    assert_eq!(h.state().current(), 0);
    h.get_by_label("snapshot 7 (7)").click();
    h.run();
    assert_eq!(h.state().current(), 7);
    // A colleague opening the same log sees them.
    let mut other = SonarApp::new(run, None);
    other.apply(Command::Open(log));
    assert_eq!(other.bookmarks(), h.state().bookmarks());
}

#[test]
fn the_truth_layer_and_status_bar_show_evals_verdicts_on_the_map_shown() {
    use sonarmap::eval::{segment_verdict, truth_figures};
    use sonarmap::scene::{Layer, Role};
    let mut h = building();
    let last = h.state().len() - 1;
    h.state_mut().push(Command::Seek(last));
    h.run();
    // The same figures as `eval` on the map after the last step.
    let run = h.state().run().clone();
    let plan = run
        .floor_plan
        .clone()
        .expect("the building has a floor plan");
    let params = h.state().shown_params().clone();
    let map = h.state().step_view().expect("a view").map_after.clone();
    let verdicts = sonarmap::eval::map_verdicts(&map, &plan, &params);
    let (spurious, coverage) = truth_figures(&map, &plan, &verdicts);
    let truth = h.state().truth().expect("truth with a floor plan");
    assert_eq!(
        (truth.spurious_fraction, truth.coverage),
        (spurious, coverage)
    );
    assert!(
        h.query_by_label(&truth.summary()).is_some(),
        "status bar shows {:?}",
        truth.summary()
    );
    // Off by default; on, one primitive a fitted segment, coloured by its verdict.
    assert!(!h.state().layers().contains(Layer::Truth));
    h.state_mut().push(Command::ToggleLayer(Layer::Truth));
    h.run();
    let scene = h.state().scene().expect("a scene");
    let drawn: Vec<_> = scene.layer(Layer::Truth).collect();
    let fitted: Vec<_> = map
        .segments
        .iter()
        .filter(|s| s.kind == sonarmap::mapping::SegmentKind::Fitted)
        .collect();
    assert_eq!(drawn.len(), fitted.len());
    for (p, s) in drawn.iter().zip(&fitted) {
        let expected = if segment_verdict(s, &plan, &params).is_true() {
            Role::TruthTrue
        } else {
            Role::TruthSpurious
        };
        assert_eq!(p.role, expected);
    }
    assert!(drawn.iter().any(|p| p.role == Role::TruthSpurious));
    assert!(drawn.iter().any(|p| p.role == Role::TruthTrue));
}

#[test]
fn a_segments_lineage_leads_to_the_decision_that_made_it() {
    use sonarmap::lineage::LineageEvent;
    let mut h = building();
    let last = h.state().len() - 1;
    h.state_mut().push(Command::Seek(last));
    h.run();
    // A segment of the final map that was updated after it was made.
    let view = h.state().step_view().expect("a view").clone();
    let seg = view
        .map_after
        .segments
        .iter()
        .find(|s| s.created > 0 && !s.updated.is_empty())
        .expect("an updated segment")
        .clone();
    h.state_mut()
        .push(Command::Select(SceneId::MapSegment(seg.id)));
    h.run();
    assert!(h.query_by_label_contains("Lineage (").is_some());
    // Its supporting readings are drawn where they were read, whatever their snapshot.
    let scene = h.state().scene().expect("a scene");
    let rings: Vec<_> = scene
        .primitives
        .iter()
        .filter(|p| p.role == sonarmap::scene::Role::SupportPoint)
        .collect();
    assert_eq!(rings.len(), seg.points.len());
    for (p, q) in rings.iter().zip(seg.points.iter()) {
        assert_eq!(
            p.id,
            SceneId::Reading {
                snapshot: q.reading.snapshot(),
                sensor: q.reading.sensor()
            }
        );
    }
    // The first event names the decision; its button goes there and selects it.
    let replay =
        sonarmap::replay::Replay::new(h.state().run().clone(), h.state().shown_params().clone());
    let Some(&LineageEvent::Created {
        snapshot,
        new_segment,
    }) = replay.lineage().of(seg.id, last).first()
    else {
        panic!("segment #{} was made by a decision", seg.id);
    };
    assert_eq!(snapshot, seg.created);
    // Its updates are listed too, each a button.
    let updates = replay
        .lineage()
        .of(seg.id, last)
        .iter()
        .filter(|e| matches!(e, LineageEvent::Updated { .. }))
        .count();
    assert!(updates >= 1);
    assert!(
        h.query_all_by_label_contains(" by n").count() >= updates,
        "an update row for each update"
    );
    h.get_by_label(&format!(
        "snapshot {snapshot}: made by n{new_segment} (new face)"
    ))
    .click();
    h.run();
    assert_eq!(h.state().current(), seg.created);
    assert_eq!(
        h.state().selection(),
        SceneId::Decision {
            new_segment,
            existing: None
        }
    );
}

#[test]
fn spurious_creations_are_marked_and_their_decisions_can_be_filtered() {
    use sonarmap::app::DecisionFilter;
    let mut h = building();
    assert!(
        h.query_by_label_contains("with a spurious new segment")
            .is_some(),
        "the timeline counts the snapshots with a spurious creation"
    );
    // The first such snapshot: its spurious filter keeps exactly the decisions whose segment
    // eval calls spurious, at least one new face among them.
    let summaries = h.state().step_summaries().to_vec();
    let k = summaries
        .iter()
        .position(|s| s.spurious_new_faces > 0)
        .expect("the building makes spurious segments");
    h.state_mut().push(Command::Seek(k));
    h.run();
    let truth = h.state().truth().expect("a floor plan").clone();
    let view = h.state().step_view().unwrap().clone();
    let spurious: Vec<usize> = view
        .trace
        .decisions
        .iter()
        .filter(|d| {
            d.result
                .and_then(|id| truth.verdict(id))
                .is_some_and(|v| !v.is_true())
        })
        .map(|d| d.new_segment)
        .collect();
    assert!(!spurious.is_empty());
    h.state_mut()
        .push(Command::FilterDecisions(DecisionFilter::Spurious));
    h.run();
    for d in &view.trace.decisions {
        let row = sonarmap::app::decision_row_text(d);
        assert_eq!(
            h.query_by_label(&row).is_some(),
            spurious.contains(&d.new_segment),
            "{row}"
        );
    }
}

#[test]
fn the_run_plots_open_under_the_timeline_and_switch_curves() {
    let mut h = building();
    assert!(h.query_by_label("Readings").is_none(), "closed by default");
    h.get_by_label("Plots").click();
    h.run();
    assert!(h.state().settings().show_plots);
    for name in ["Segments", "Decisions", "Readings", "Spurious new faces"] {
        assert!(h.query_by_label(name).is_some(), "{name} choice");
    }
    h.get_by_label("Decisions").click();
    h.run();
    assert_eq!(
        h.state().settings().run_plot,
        sonarmap::app::RunPlot::Decisions
    );
    // A click in the plot, halfway along, goes to the snapshot under it.
    assert_eq!(h.state().current(), 0);
    let choices = h.get_by_label("Segments").rect();
    let at = egui::pos2(700.0, choices.bottom() + 60.0);
    h.hover_at(at);
    h.run();
    h.drag_at(at);
    h.drop_at(at);
    h.run();
    let k = h.state().current();
    let len = h.state().len();
    assert!(
        k > len / 4 && k < 3 * len / 4,
        "a click halfway along the plot went to snapshot {k} of {len}"
    );
}

#[test]
fn a_decision_shows_its_margins_and_where_its_tests_would_flip() {
    let mut h = building();
    // The first decision that tested a candidate.
    let (k, d) = (0..h.state().len())
        .find_map(|k| {
            h.state_mut().push(Command::Seek(k));
            h.run();
            let view = h.state().step_view()?;
            view.trace
                .decisions
                .iter()
                .find(|d| !d.mpc_stage.is_empty())
                .map(|d| (k, d.clone()))
        })
        .expect("a decision with candidates");
    assert_eq!(h.state().current(), k);
    h.state_mut()
        .push(Command::Select(SceneId::NewSegment(d.new_segment)));
    h.run();
    assert!(h
        .query_by_label("Flip points (this test alone, the map as it is)")
        .is_some());
    let c = &d.mpc_stage[0].evaluation;
    let theta = format!("{:.2}°", c.orientation.value.to_degrees());
    assert!(
        h.query_all_by_label(&theta).next().is_some(),
        "θ_o flip {theta}"
    );
    assert!(
        h.query_all_by_label_contains("margin").next().is_some(),
        "test cells show their margin"
    );
}

#[test]
fn the_mark_filter_changes_the_marks_and_prev_next_follow_it() {
    use sonarmap::app::MarkKind;
    let mut h = building();
    let all = h.state().marks();
    let counts = h.state().mark_counts();
    let dismissals = counts
        .iter()
        .find(|(k, _, _)| *k == MarkKind::Dismissals)
        .map(|c| c.1)
        .unwrap();
    assert!(dismissals > 0 && dismissals < all.len());
    // Keep only the dismissals: the marks are exactly the dismissal snapshots.
    for (kind, _, _) in counts {
        if kind != MarkKind::Dismissals {
            h.state_mut().push(Command::ToggleMarkKind(kind));
        }
    }
    h.run();
    let only = h.state().marks();
    assert_eq!(only.len(), dismissals);
    assert!(only.iter().all(|m| all.contains(m)));
    assert!(h.query_by_label(&format!("{dismissals} marks")).is_some());
    // Next mark goes to the first dismissal.
    h.state_mut().push(Command::Seek(0));
    h.run();
    let first = *only.iter().find(|&&m| m > 0).unwrap();
    h.state_mut().push(Command::NextMark);
    h.run();
    assert_eq!(h.state().current(), first);
    let summary = &h.state().step_summaries()[first];
    assert!(summary.dismissals > 0);
}

#[test]
fn frames_that_change_nothing_reuse_the_map_scene_and_a_step_builds_it_again() {
    let mut h = building();
    h.run();
    let built = h.state().scene_builds();
    // Frames with nothing new (the pointer moving over the map, say) draw the same scene.
    for _ in 0..5 {
        h.step();
    }
    assert_eq!(h.state().scene_builds(), built);
    h.key_press(egui::Key::ArrowRight);
    h.run();
    assert!(h.state().scene_builds() > built, "a new step, a new scene");
    let after_step = h.state().scene_builds();
    h.state_mut().push(Command::ToggleLayer(Layer::Balls));
    h.run();
    assert!(
        h.state().scene_builds() > after_step,
        "a layer switched, a new scene"
    );
}

#[test]
fn a_log_opened_while_new_parameters_replay_the_old_run_stays_open() {
    // New parameters start a replay of the open run (the built-in Blue Room) on a thread; a
    // small log opened meanwhile is installed at once, and the replay of the old run must not
    // land on top of it when it ends.
    let run = sonarmap::assets::default_run().expect("built-in run loads");
    let mut h = harness(SonarApp::new(run, None));
    h.run();
    h.state_mut()
        .push(Command::SetPreset(sonarmap::mapping::Preset::Extended));
    h.state_mut()
        .push(Command::Open(asset("tight_room.log.json")));
    settle(&mut h);
    h.run();
    let tight = sonarmap::log::load_run(
        &std::fs::read(asset("tight_room.log.json")).unwrap(),
        "tight",
    )
    .unwrap();
    assert_eq!(h.state().run().name, tight.name);
    assert_eq!(h.state().len(), tight.snapshots.len());
    assert!(
        h.state().params().merge_duplicates,
        "under the extended preset"
    );
}

/// The building asset in `extended`, shown at the first snapshot whose step (found by running
/// the engine alone) gives `found` something, with the snapshot and that something.
fn building_extended_at_first<T>(
    mut found: impl FnMut(&sonarmap::mapping::StepTrace) -> Option<T>,
) -> (Harness<'static, SonarApp>, usize, T) {
    let mut h = building();
    h.state_mut()
        .push(Command::SetPreset(sonarmap::mapping::Preset::Extended));
    settle(&mut h);
    let run = h.state().run().clone();
    let mut mapper = sonarmap::mapping::Mapper::new(
        sonarmap::mapping::Params::extended(),
        run.layout.clone(),
        run.sensor,
    );
    let (k, thing) = run
        .snapshots
        .iter()
        .enumerate()
        .find_map(|(k, s)| found(&mapper.step(s)).map(|t| (k, t)))
        .expect("the building's extended run has such a step");
    h.state_mut().push(Command::Seek(k));
    h.run();
    (h, k, thing)
}

/// Asserts that the inspector at snapshot `k` shows a label containing each of `texts` (the
/// `what` line).
fn assert_labels_shown(h: &Harness<'static, SonarApp>, k: usize, what: &str, texts: &[&str]) {
    for text in texts {
        assert!(
            h.query_all_by_label_contains(text).next().is_some(),
            "snapshot {k}: no {what} line with {text:?} (of {texts:?})"
        );
    }
}

#[test]
fn the_inspector_explains_an_echo_placement_with_its_numbers() {
    // The first snapshot whose step moved a piece's readings to their echo points names it in
    // "Extensions this step", with how many readings moved to a foot and to a cone edge.
    let (h, k, fit) = building_extended_at_first(|trace| trace.echo_fits.first().cloned());
    let text = format!(
        "reading(s) moved to the foot of the perpendicular, {} to",
        fit.at_cone_edge
    );
    assert_labels_shown(&h, k, "echo placement", &["echo placement: ", &text]);
}

#[test]
fn the_inspector_explains_a_corner_diagonal_with_its_numbers() {
    // The first snapshot whose step removed a segment as the diagonal of a corner names it in
    // "Extensions this step", with the corner's two walls and the angle between them.
    let (h, k, d) = building_extended_at_first(|trace| trace.diagonals.first().cloned());
    let text = format!("corner diagonal: s{} (", d.segment);
    let walls = format!(
        "of s{} and s{} ({:.1} deg apart",
        d.walls[0],
        d.walls[1],
        d.corner_angle_rad.to_degrees()
    );
    assert_labels_shown(&h, k, "corner diagonal", &[&text, &walls]);
}

#[test]
fn the_inspector_explains_a_settled_reading_with_its_wall() {
    // The first snapshot whose step kept a reading out of the clusters because a confirmed wall
    // explains it names the reading and the wall in "Extensions this step".
    let (h, k, s) = building_extended_at_first(|trace| trace.settled.first().cloned());
    let text = format!("settled: sensor {} read ", s.sensor);
    let wall = format!("confirmed wall s{} predicts", s.segment);
    let kept_out = "kept out of the clusters, point memory and the free-space sweep";
    assert_labels_shown(&h, k, "settled", &[&text, &wall, kept_out]);
}

#[test]
fn the_inspector_explains_a_stack_with_its_readings_and_ranges() {
    // The first snapshot whose step let a stack go from point memory (§8.15) names its
    // readings and says why they make no segment.
    let (h, k, first) =
        building_extended_at_first(|trace| trace.memory.as_ref()?.stacked.first().copied());
    let text = format!("stack: readings {}/{}", first.snapshot(), first.sensor());
    let why = "the sonar moved along its beam, so their line has no direction";
    assert_labels_shown(&h, k, "stack", &[&text, why]);
}

#[test]
fn the_inspector_explains_a_joint_kept_in_point_memory() {
    // The first snapshot whose step kept a piece's newest end in point memory as its joint
    // (§8.16) names the reading and says what it is kept for.
    let (h, k, joint) =
        building_extended_at_first(|trace| trace.memory.as_ref()?.joints.first().copied());
    let text = format!("joint: reading {}/{}", joint.snapshot(), joint.sensor());
    let why = "the next piece along the chain shares it";
    assert_labels_shown(&h, k, "joint", &[&text, why]);
}

#[test]
fn a_flag_switched_on_without_its_prerequisite_is_warned_about_in_the_panel() {
    let run = sonarmap::assets::default_run().unwrap();
    let mut h = harness(SonarApp::new(run, None));
    h.run();
    let warning = "parameter `settled_walls` acts only with `confirm_segments`";
    assert!(h.query_by_label_contains(warning).is_none());
    let alone = sonarmap::mapping::Params {
        settled_walls: true,
        ..sonarmap::mapping::Params::paper()
    };
    h.state_mut().push(Command::SetParams(alone));
    settle(&mut h);
    assert!(h.query_by_label_contains(warning).is_some());
    let with_it = sonarmap::mapping::Params::paper_with("settled_walls").unwrap();
    h.state_mut().push(Command::SetParams(with_it));
    settle(&mut h);
    assert!(h.query_by_label_contains(warning).is_none());
}
