//! Figures (issue 20): the building at snapshot 150 exported with its labels, every text box
//! measured by usvg with the system fonts; long titles shortened; the figure style.

use sonarmap::mapping::Params;
use sonarmap::replay::{Replay, StepView};
use sonarmap::run::Run;
use sonarmap::scene::figure::{figure_svg, Figure};
use sonarmap::scene::{Layer, LayerSet, SceneId, SceneInput};
use std::sync::Arc;

fn building_at(k: usize) -> (Arc<Run>, StepView) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/building.log.json");
    let run = sonarmap::log::load_run(&std::fs::read(path).unwrap(), "building").unwrap();
    let run = Arc::new(run);
    let replay = Replay::new(run.clone(), Params::paper());
    let view = replay.view(k).expect("snapshot replayed");
    (run, view)
}

/// The boxes (x0, y0, x1, y1, text) of the texts inside `<g id="labels">` and
/// `<g id="clusters">`, as usvg lays them out with the system fonts.
fn label_boxes(svg: &str) -> Vec<(f32, f32, f32, f32, String)> {
    let opt = sonarmap::export::svg_options();
    let tree = usvg::Tree::from_str(svg, &opt).expect("the export parses");
    let mut out = Vec::new();
    for id in ["labels", "clusters"] {
        let Some(usvg::Node::Group(g)) = tree.node_by_id(id) else {
            continue;
        };
        for node in g.children() {
            if let usvg::Node::Text(t) = node {
                let b = t.abs_bounding_box();
                let text: String = t.chunks().iter().map(|c| c.text().to_owned()).collect();
                out.push((b.left(), b.top(), b.right(), b.bottom(), text));
            }
        }
    }
    out
}

fn figure(layers: LayerSet, figure_style: bool, title: &str) -> Figure {
    Figure {
        view: None,
        layers,
        size_px: (1000, 700),
        selection: SceneId::None,
        figure_style,
        title: title.to_owned(),
    }
}

#[test]
fn no_two_labels_overlap_in_the_building_export_at_snapshot_150() {
    let (run, view) = building_at(150);
    let layers = LayerSet::all()
        .with(Layer::Beams, false)
        .with(Layer::Discarded, false);
    let svg = figure_svg(
        &SceneInput::from_view(&run, &view),
        &figure(layers, false, "building — snapshot 150"),
        run.units,
    );
    let boxes = label_boxes(&svg);
    assert!(
        boxes.len() >= 15,
        "the building has many labels: {}",
        boxes.len()
    );
    for (i, a) in boxes.iter().enumerate() {
        for b in &boxes[i + 1..] {
            let overlap = a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3;
            assert!(!overlap, "{:?} overlaps {:?}", a, b);
        }
    }
}

#[test]
fn the_figure_style_labels_only_the_decisions_and_lists_only_what_is_drawn() {
    let (run, view) = building_at(150);
    let layers = LayerSet::all()
        .with(Layer::Beams, false)
        .with(Layer::Discarded, false);
    let input = SceneInput::from_view(&run, &view);
    let screen = label_boxes(&figure_svg(&input, &figure(layers, false, "t"), run.units));
    let svg = figure_svg(&input, &figure(layers, true, "t"), run.units);
    let figure_labels = label_boxes(&svg);
    let met: Vec<String> = (view.trace.decisions.iter())
        .flat_map(|d| [d.existing, d.result])
        .flatten()
        .map(|id| format!("s{id}"))
        .collect();
    let map_labels: Vec<&String> = (figure_labels.iter())
        .map(|b| &b.4)
        .filter(|t| t.starts_with('s'))
        .collect();
    assert!(!map_labels.is_empty());
    assert!(
        map_labels.iter().all(|t| met.contains(t)),
        "{map_labels:?} vs {met:?}"
    );
    assert!(figure_labels.len() < screen.len());
    // No grid; a scale bar.
    assert!(!svg.contains("id=\"grid\""));
    assert!(svg.contains("scale"), "a scale bar");
}

#[test]
fn a_long_title_is_shortened_to_the_page() {
    let (run, view) = building_at(20);
    let long = format!(
        "{} — snapshot 20",
        "robond-occupancy-grid-mapping measurement ".repeat(6)
    );
    let svg = figure_svg(
        &SceneInput::from_view(&run, &view),
        &Figure {
            size_px: (600, 400),
            ..figure(LayerSet::all(), false, &long)
        },
        run.units,
    );
    let opt = sonarmap::export::svg_options();
    let tree = usvg::Tree::from_str(&svg, &opt).unwrap();
    let Some(usvg::Node::Text(title)) = tree.node_by_id("title") else {
        panic!("no title");
    };
    let b = title.abs_bounding_box();
    assert!(b.right() <= 600.0, "the title ends at {} of 600", b.right());
    assert!(svg.contains("snapshot 20</text>"), "the snapshot stays");
}
