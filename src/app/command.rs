//! What the panels ask the app to do. Every panel returns `Command`s; the app applies them in
//! one place per frame ([`super::SonarApp::apply`]), so keyboard, buttons and tests drive the
//! same path.

use super::settings::LeftTab;
use crate::geometry::Point;
use crate::mapping::{Params, SegmentId};
use crate::scene::{Layer, SceneId};
use std::path::PathBuf;

/// One request from the UI.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Load the run log at this path (the current run stays open if it fails).
    Open(PathBuf),
    /// Load a run log from bytes (a file dropped without a path); the name is for errors.
    OpenBytes {
        /// Name shown in errors and the status bar.
        name: String,
        /// The file's contents.
        bytes: Vec<u8>,
    },
    /// Ask for a file (system or in-app dialog), then [`Command::Open`] it.
    OpenDialog,
    /// Load the current file again from disk.
    Reload,
    /// Show snapshot `k` (clamped to the run).
    Seek(usize),
    /// Move by this many snapshots (negative is back).
    Step(i64),
    /// Show the first snapshot.
    First,
    /// Show the last snapshot.
    Last,
    /// Start or pause playback.
    TogglePlay,
    /// Playback rate, snapshots per second.
    SetRate(f32),
    /// Seek to the next notable snapshot.
    NextMark,
    /// Seek to the previous notable snapshot.
    PrevMark,
    /// Select what the scene shows under this id (`SceneId::None` clears the selection).
    Select(SceneId),
    /// The next selected segment is compared with this map segment ("compare with…").
    CompareWith(SegmentId),
    /// Stop comparing.
    CancelCompare,
    /// Switch a layer on or off.
    ToggleLayer(Layer),
    /// Show or hide the run plots under the timeline.
    TogglePlots,
    /// Show or hide one kind of timeline mark.
    ToggleMarkKind(super::marks::MarkKind),
    /// Show only decisions with this outcome (`None`: all).
    FilterDecisions(super::decision_filter::DecisionFilter),
    /// Fit the map view to the scene.
    FitView,
    /// Zoom the map view onto the selected segment.
    ZoomToSelection,
    /// Centre the map view on a world point (metres).
    CenterOn(Point),
    /// Ask for a path (system or in-app dialog), then export the figure to it (SVG, or PNG by
    /// the extension).
    ExportDialog,
    /// Write what the map view shows to this path: SVG, or PNG when it ends in `.png`.
    ExportSvg(PathBuf),
    /// Exports in the figure style (labels for the selection and the decisions only) or not.
    ToggleFigureStyle,
    /// PNG exports are this many times the map view's size (1 to 4).
    SetPngScale(u32),
    /// Hide the error banner.
    DismissError,
    /// Show or hide the keyboard shortcut help.
    ToggleShortcuts,
    /// Re-run the run with these parameters (refused if they do not validate).
    SetParams(Params),
    /// Make this preset the one compared with, and apply its values.
    SetPreset(crate::mapping::Preset),
    /// Ask for a parameter file (system or in-app dialog), then [`Command::LoadParams`] it.
    LoadParamsDialog,
    /// Ask for a path (system or in-app dialog), then [`Command::SaveParams`] to it.
    SaveParamsDialog,
    /// Load a `--params` file (docs/formats.md §6) on top of the paper's values and re-run.
    LoadParams(PathBuf),
    /// Write the current parameters as a `--params` file in the run's units (atomically).
    SaveParams(PathBuf),
    /// Keep the current parameters and their replay as the baseline of an A/B comparison.
    PinBaseline,
    /// Stop comparing with the baseline.
    Unpin,
    /// Show this page of the left panel.
    ShowTab(LeftTab),
    /// Show or hide the baseline's map ghosted under the current one.
    ToggleBaselineGhost,
    /// Bookmark the current snapshot under this name.
    AddBookmark(String),
    /// Remove the bookmark at this position of the list.
    RemoveBookmark(usize),
    /// Use this file dialog from now on.
    SetFileDialog(super::file_dialog::DialogBackend),
    /// Show or hide a side panel, every side panel, or the A | B split.
    TogglePanel(PanelToggle),
    /// Dock the inspector below the decision list or in a tab.
    DockInspector(super::settings::InspectorDock),
    /// Open the log waiting in the layout picker with this layout.
    OpenWithLayout(super::layout_choice::LayoutChoice),
    /// Ask for a layout file (system or in-app dialog) for the log in the layout picker.
    ChooseLayoutFile,
    /// Ask for the poses table (system or in-app dialog) of the table in the layout picker.
    ChoosePosesFile,
    /// Read the poses of the table in the layout picker from this file.
    SetPosesFile(PathBuf),
    /// Close the layout picker; the run that was open stays.
    CancelLayoutPicker,
    /// Show this page of the right panel (inspector docked in a tab).
    ShowRightTab(super::settings::RightTab),
}

/// What [`Command::TogglePanel`] switches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PanelToggle {
    /// The left panel (key L).
    Left,
    /// The right panel: decisions and inspector (key I).
    Right,
    /// Map only: every side panel hidden (key M).
    MapOnly,
    /// The baseline and the current map side by side (key S, while pinned).
    Split,
}
