//! One frame of the window: the queued and new commands applied, playback advanced, and the
//! panels laid out (menu bar, error banner, status bar, timeline, the left pages, the inspector
//! with the decision list, the map view). Panels only draw and return [`Command`]s. The eframe
//! glue (a frame, saving the settings) is here too.

use super::app::SonarApp;
use super::bookmarks_panel::bookmarks_ui;
use super::command::Command;
use super::decisions::decisions_ui;
use super::in_app_dialog::InAppAnswer;
use super::inspector::{hover_text, inspector_ui, InspectCtx};
use super::jobs::JobKind;
use super::layers::layers_ui;
use super::layout_picker::layout_picker_ui;
use super::map_view::ViewRequest;
use super::map_view::{map_toolbar_ui, map_view_ui, MapPlot};
use super::marks::MarkKind;
use super::menu::{handle_shortcuts, menu_bar_ui, shortcuts_window_ui};
use super::params_panel::{params_panel_ui, BaselineSummary, ParamsPanelInfo};
use super::run_plots::{run_plots_ui, RunCurves};
use super::settings::{InspectorDock, LeftTab, PanelLayout, RightTab, SETTINGS_KEY};
use super::timeline::{timeline_ui, TimelineInfo};
use crate::geometry::Point;
use crate::scene::svg::default_view;
use crate::scene::{format_length, Scene, SceneId, ViewRect};

impl SonarApp {
    /// One frame of the whole window: applies queued commands, then lays out the panels.
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        for command in std::mem::take(&mut self.pending) {
            self.apply(command);
        }
        self.poll_background(&ctx);
        self.advance_playback(&ctx);
        let mut commands = handle_shortcuts(&ctx);
        commands.extend(Self::dropped_files(&ctx));
        let title = self.window_title();
        if title != self.shown_title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.shown_title = title;
        }
        if let Some(rect) = ctx.input(|i| i.viewport().inner_rect) {
            self.settings.window_size = Some([rect.width(), rect.height()]);
        }

        egui::Panel::top("menu_bar").show(ui, |ui| {
            commands.extend(menu_bar_ui(
                ui,
                &self.settings.recent,
                self.baseline.is_some(),
                &self.settings,
            ));
        });
        self.banner_ui(ui, &mut commands);
        egui::Panel::bottom("status_bar").show(ui, |ui| self.status_bar_ui(ui));
        self.timeline_panel_ui(ui, &mut commands);
        let scene = self.frame_scene();
        self.left_panel_ui(ui, &scene, &mut commands);
        self.inspector_panel_ui(ui, &mut commands);
        self.map_panel_ui(ui, &scene, &mut commands);
        self.dialogs_ui(&ctx, &mut commands);
        if self.show_shortcuts {
            let mut open = true;
            shortcuts_window_ui(&ctx, &mut open);
            if !open {
                commands.push(Command::ToggleShortcuts);
            }
        }
        for command in commands {
            self.apply(command);
        }
    }

    fn banner_ui(&self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        if let Some(text) = &self.banner {
            let frame = egui::Frame::new()
                .fill(egui::Color32::from_rgb(0x7a, 0x1e, 0x1e))
                .inner_margin(6.0);
            egui::Panel::top("error_banner")
                .frame(frame)
                .show(ui, |ui| {
                    ui.horizontal(|ui| {
                        if ui.button("Dismiss").clicked() {
                            commands.push(Command::DismissError);
                        }
                        ui.add(
                            egui::Label::new(egui::RichText::new(text).color(egui::Color32::WHITE))
                                .wrap(),
                        );
                    });
                });
        }
    }

    fn timeline_panel_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        egui::Panel::bottom("timeline").show(ui, |ui| {
            let marks = self.marks();
            let counts = self.mark_counts();
            let shown = |kind: MarkKind, marks: &'_ [usize]| -> Vec<usize> {
                if self.settings.hidden_marks.contains(&kind) {
                    Vec::new()
                } else {
                    marks.to_vec()
                }
            };
            let spurious = shown(
                MarkKind::SpuriousCreations,
                self.loaded.marks.of_kind(MarkKind::SpuriousCreations),
            );
            let direct = shown(MarkKind::DirectDifferences, self.direct_difference_marks());
            let info = TimelineInfo {
                len: self.len(),
                current: self.current(),
                t_s: self.view.as_ref().map_or(0.0, |v| v.trace.t),
                marks: &marks,
                mark_counts: &counts,
                baseline_marks: self.baseline.as_ref().map(|_| direct.as_slice()),
                spurious_marks: &spurious,
                show_plots: self.settings.show_plots,
                playing: self.playing,
                rate: self.settings.rate,
            };
            commands.extend(timeline_ui(ui, &info, &mut self.jump_text));
        });
        if self.settings.show_plots {
            egui::Panel::bottom("run_plots")
                .resizable(true)
                .default_size(170.0)
                .show(ui, |ui| {
                    let baseline = self
                        .baseline
                        .as_ref()
                        .filter(|b| b.diff.is_some())
                        .map(|b| b.replay.summaries());
                    let current = self.current();
                    let replay = &self.loaded.replay;
                    let curves = RunCurves {
                        summaries: replay.summaries(),
                        truth: replay.truth_curve(),
                        poses: replay.step_poses(),
                    };
                    commands.extend(run_plots_ui(
                        ui,
                        &mut self.settings.run_plot,
                        curves,
                        baseline,
                        current,
                    ));
                });
        }
    }

    /// The left panel: the tabs and the page shown.
    fn left_panel_ui(&mut self, ui: &mut egui::Ui, scene: &Scene, commands: &mut Vec<Command>) {
        if !self.settings.panels.shows_left() {
            return;
        }
        let shown = egui::Panel::left("layers")
            .resizable(true)
            .min_size(160.0)
            .default_size(self.settings.panels.left_px)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    for tab in LeftTab::ALL {
                        if ui
                            .selectable_label(self.settings.left_tab == tab, tab.label())
                            .clicked()
                        {
                            commands.push(Command::ShowTab(tab));
                        }
                    }
                });
                ui.separator();
                egui::ScrollArea::vertical().show(ui, |ui| match self.settings.left_tab {
                    LeftTab::Parameters => self.params_page_ui(ui, commands),
                    LeftTab::Bookmarks => {
                        commands.extend(bookmarks_ui(
                            ui,
                            &self.bookmarks,
                            self.current(),
                            &mut self.bookmark_text,
                        ));
                    }
                    LeftTab::Layers => {
                        commands.extend(layers_ui(ui, self.settings.layers(), &scene.legend()));
                    }
                });
            });
        self.settings.panels.left_px = shown.response.rect.width();
    }

    /// The parameters page, and the baseline ghost switch while pinned.
    fn params_page_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        let info = ParamsPanelInfo {
            params: &self.params,
            units: self.loaded.replay.run().units,
            rerun_progress: self
                .background
                .as_ref()
                .and_then(|j| matches!(j.kind, JobKind::Rerun { .. }).then(|| j.task.fraction())),
            pinned: self.baseline.is_some(),
            diff_progress: self
                .baseline
                .as_ref()
                .and_then(|b| b.job.as_ref().map(|j| j.fraction())),
            differing: self
                .baseline
                .as_ref()
                .and_then(|b| b.diff.as_ref())
                .map(BaselineSummary::of),
            preset: self.settings.preset,
        };
        commands.extend(params_panel_ui(ui, &mut self.params_panel, &info));
        if self.baseline.is_some() {
            let mut ghost = self.settings.baseline_ghost;
            if ui.checkbox(&mut ghost, "Baseline map (ghosted)").changed() {
                commands.push(Command::ToggleBaselineGhost);
            }
        }
    }

    /// The right panel: the decision list, and the inspector below it or in a tab.
    fn inspector_panel_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        if !self.settings.panels.shows_right() {
            return;
        }
        let differences = self.differences_here();
        let panels = self.settings.panels.clone();
        let shown = egui::Panel::right("inspector")
            .resizable(true)
            .min_size(200.0)
            .default_size(panels.right_px)
            .show(ui, |ui| {
                right_panel_header_ui(ui, &panels, commands);
                let Some(view) = &self.view else {
                    return;
                };
                let ictx = InspectCtx {
                    run: self.loaded.replay.run(),
                    view,
                    params: self.loaded.replay.params(),
                    baseline: self
                        .baseline
                        .as_ref()
                        .and_then(|b| b.view.as_ref().map(|v| (&b.params, v))),
                    truth: self.truth.as_ref(),
                    lineage: self.loaded.replay.lineage(),
                };
                let decisions = |ui: &mut egui::Ui, commands: &mut Vec<Command>| {
                    commands.extend(decisions_ui(
                        ui,
                        &ictx,
                        self.decision_filter,
                        self.selection,
                        self.baseline.as_ref().map(|_| differences.as_slice()),
                    ));
                };
                let inspector = |ui: &mut egui::Ui, commands: &mut Vec<Command>| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        commands.extend(inspector_ui(ui, &ictx, self.selection, &self.compare));
                    });
                };
                match (panels.inspector_dock, panels.right_tab) {
                    (InspectorDock::Below, _) => {
                        egui::Panel::top("decisions")
                            .resizable(true)
                            .default_size(190.0)
                            .show(ui, |ui| decisions(ui, commands));
                        egui::CentralPanel::default().show(ui, |ui| inspector(ui, commands));
                    }
                    (InspectorDock::Tab, RightTab::Decisions) => {
                        egui::CentralPanel::default().show(ui, |ui| decisions(ui, commands));
                    }
                    (InspectorDock::Tab, RightTab::Inspector) => {
                        egui::CentralPanel::default().show(ui, |ui| inspector(ui, commands));
                    }
                }
            });
        self.settings.panels.right_px = shown.response.rect.width();
    }

    /// The map view in the central panel: its tool bar, then one plot, or the baseline (A)
    /// and the current map (B) side by side with linked pan and zoom.
    fn map_panel_ui(&mut self, ui: &mut egui::Ui, scene: &Scene, commands: &mut Vec<Command>) {
        let split_scene = self
            .is_split()
            .then(|| self.frame_baseline_scene())
            .flatten();
        egui::CentralPanel::default().show(ui, |ui| {
            let units = self.run().units;
            commands.extend(map_toolbar_ui(
                ui,
                &mut self.map_view,
                units,
                &self.settings.panels,
                self.baseline.is_some(),
            ));
            if let Some(a_scene) = &split_scene {
                self.share_request(a_scene, scene);
            }
            let describe = |id: SceneId| {
                self.view.as_ref().and_then(|view| {
                    hover_text(
                        &InspectCtx {
                            run: self.loaded.replay.run(),
                            view,
                            params: self.loaded.replay.params(),
                            baseline: None,
                            truth: self.truth.as_ref(),
                            lineage: self.loaded.replay.lineage(),
                        },
                        id,
                    )
                })
            };
            let Some(a_scene) = split_scene else {
                commands.extend(map_view_ui(
                    ui,
                    MapPlot::MAIN,
                    scene,
                    units,
                    &mut self.map_view,
                    self.selection,
                    &describe,
                    self.baseline
                        .as_ref()
                        .filter(|_| self.settings.baseline_ghost)
                        .and_then(|b| b.view.as_ref())
                        .map(|v| &v.map_after),
                ));
                return;
            };
            let no_hover = |_: SceneId| None;
            ui.columns(2, |columns| {
                commands.extend(map_view_ui(
                    &mut columns[0],
                    MapPlot::SPLIT_A,
                    &a_scene,
                    units,
                    &mut self.split_view,
                    self.selection,
                    &no_hover,
                    None,
                ));
                commands.extend(map_view_ui(
                    &mut columns[1],
                    MapPlot::SPLIT_B,
                    scene,
                    units,
                    &mut self.map_view,
                    self.selection,
                    &describe,
                    None,
                ));
            });
        });
    }

    /// Both plots of the A | B split frame the same request (Fit: both maps), then stay
    /// linked.
    fn share_request(&mut self, a_scene: &Scene, scene: &Scene) {
        if self.map_view.request == Some(ViewRequest::Fit) {
            let (a, b) = (default_view(a_scene), default_view(scene));
            let both = ViewRect::new(
                Point::new(a.min.x.min(b.min.x), a.min.y.min(b.min.y)),
                Point::new(a.max.x.max(b.max.x), a.max.y.max(b.max.y)),
            );
            self.map_view.request = Some(ViewRequest::Frame(both));
        }
        self.split_view.request = self.map_view.request;
    }

    /// The in-app file dialog and the layout picker, when open.
    fn dialogs_ui(&mut self, ctx: &egui::Context, commands: &mut Vec<Command>) {
        if let Some(dialog) = &mut self.file_dialog {
            match dialog.show(ctx) {
                InAppAnswer::Open => {}
                InAppAnswer::Chosen(path) => {
                    let purpose = dialog.purpose;
                    self.file_dialog = None;
                    self.path_chosen(purpose, path);
                }
                InAppAnswer::Cancelled => self.file_dialog = None,
            }
        }
        if let Some(picker) = &mut self.layout_picker {
            commands.extend(layout_picker_ui(ctx, picker));
        }
    }

    fn status_bar_ui(&self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.label(self.loaded.source.display_name());
            ui.separator();
            if let Some(job) = &self.background {
                ui.spinner();
                let (done, total) = (job.task.done(), job.task.total());
                let elapsed_s = job.started.elapsed().as_secs_f64();
                // The share first: a long label is cut at the bar's end.
                ui.add(
                    egui::ProgressBar::new(job.task.fraction())
                        .desired_width(420.0)
                        .text(super::jobs::progress_text(
                            done, total, elapsed_s, &job.label,
                        )),
                );
                ui.separator();
            }
            ui.label(format!(
                "snapshot {} / {}",
                self.current(),
                self.len().saturating_sub(1)
            ));
            if self.loaded.is_preview() {
                ui.label(format!("(the first {} while replaying)", self.len()))
                    .on_hover_text(format!(
                        "The run has {} snapshots; its first ones are shown while the whole run \
                         replays, and the rest join the timeline when it is done.",
                        self.loaded.run.snapshots.len()
                    ));
            }
            ui.separator();
            let units = self.run().units;
            match self.map_view.cursor_m {
                Some(p) => ui.label(format!(
                    "x {}  y {}",
                    format_length(p.x, units),
                    format_length(p.y, units)
                )),
                None => ui.label("x -  y -"),
            };
            if let Some(r) = self.map_view.ruler_text(units) {
                ui.separator();
                ui.label(format!("ruler {r}"));
            }
            if let Some(truth) = &self.truth {
                ui.separator();
                ui.label(truth.summary()).on_hover_text(
                    "The map shown against the floor plan, as `sonarmap eval` scores it: \
                     the share of fitted segments on no wall, and the share of wall length \
                     covered. The Truth layer colours each segment.",
                );
            }
            let changed = self.changed_params();
            if !changed.is_empty() {
                ui.separator();
                ui.label(
                    egui::RichText::new(format!(
                        "parameters ≠ {}",
                        super::params_panel::preset_name(self.settings.preset)
                    ))
                    .color(egui::Color32::from_rgb(0xe0, 0x90, 0x30)),
                )
                .on_hover_text(format!("changed: {}", changed.join(", ")));
            }
            ui.separator();
            ui.label(&self.message);
        });
    }

    fn advance_playback(&mut self, ctx: &egui::Context) {
        if !self.playing {
            return;
        }
        let dt = f64::from(ctx.input(|i| i.stable_dt)).clamp(0.0, 0.5);
        self.play_clock_s += dt;
        let period = 1.0 / f64::from(self.settings.rate.max(0.25));
        while self.play_clock_s >= period {
            self.play_clock_s -= period;
            if self.current() + 1 >= self.len() {
                self.playing = false;
                self.message = "reached the last snapshot".to_owned();
                break;
            }
            self.seek(self.current() + 1);
        }
        ctx.request_repaint();
    }

    fn dropped_files(ctx: &egui::Context) -> Vec<Command> {
        ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .take(1)
                .map(|f| {
                    let path = f.path();
                    if path.exists() {
                        Command::Open(path.to_path_buf())
                    } else {
                        let name = path.display().to_string();
                        match f.bytes() {
                            Ok(bytes) => Command::OpenBytes { name, bytes },
                            Err(_) => Command::Open(path.to_path_buf()),
                        }
                    }
                })
                .collect()
        })
    }
}

impl eframe::App for SonarApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        SonarApp::ui(self, ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        if let Ok(text) = serde_json::to_string(&self.settings) {
            storage.set_string(SETTINGS_KEY, text);
        }
    }
}

/// The right panel's header: the Decisions and Inspector tabs (when docked in a tab) and the
/// dock switch.
fn right_panel_header_ui(ui: &mut egui::Ui, panels: &PanelLayout, commands: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        let tab = panels.inspector_dock == InspectorDock::Tab;
        if tab {
            for (page, label) in [
                (RightTab::Decisions, "Decisions"),
                (RightTab::Inspector, "Inspector"),
            ] {
                if ui
                    .selectable_label(panels.right_tab == page, label)
                    .clicked()
                {
                    commands.push(Command::ShowRightTab(page));
                }
            }
        }
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            let (dock, text, hover) = if tab {
                (
                    InspectorDock::Below,
                    "Dock below",
                    "Show the inspector below the decision list",
                )
            } else {
                (
                    InspectorDock::Tab,
                    "Dock in a tab",
                    "Show the inspector in a tab beside the decision list",
                )
            };
            if ui.small_button(text).on_hover_text(hover).clicked() {
                commands.push(Command::DockInspector(dock));
            }
        });
    });
}
