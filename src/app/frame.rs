//! One frame of the window: the queued and new commands applied, playback advanced, and the
//! panels laid out (menu bar, error banner, status bar, timeline, the left pages, the inspector
//! with the decision list, the map view). Panels only draw and return [`Command`]s. The eframe
//! glue (a frame, saving the settings) is here too.

use super::app::SonarApp;
use super::bookmarks_panel::bookmarks_ui;
use super::command::Command;
use super::decisions::decisions_ui;
use super::inspector::{hover_text, inspector_ui, InspectCtx};
use super::jobs::JobKind;
use super::layers::layers_ui;
use super::map_view::map_view_ui;
use super::marks::MarkKind;
use super::menu::{handle_shortcuts, menu_bar_ui, shortcuts_window_ui};
use super::params_panel::{params_panel_ui, BaselineSummary, ParamsPanelInfo};
use super::run_plots::run_plots_ui;
use super::settings::{LeftTab, SETTINGS_KEY};
use super::timeline::{timeline_ui, TimelineInfo};
use crate::scene::{format_length, Scene, SceneId};

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
        if let Some(rect) = ctx.input(|i| i.viewport().inner_rect) {
            self.settings.window_size = Some([rect.width(), rect.height()]);
        }

        egui::Panel::top("menu_bar").show(ui, |ui| {
            commands.extend(menu_bar_ui(
                ui,
                &self.settings.recent,
                self.baseline.is_some(),
            ));
        });
        self.banner_ui(ui, &mut commands);
        egui::Panel::bottom("status_bar").show(ui, |ui| self.status_bar_ui(ui));
        self.timeline_panel_ui(ui, &mut commands);
        let scene = self.frame_scene();
        self.left_panel_ui(ui, &scene, &mut commands);
        self.inspector_panel_ui(ui, &mut commands);
        self.map_panel_ui(ui, &scene, &mut commands);
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
                    commands.extend(run_plots_ui(
                        ui,
                        &mut self.settings.run_plot,
                        self.loaded.replay.summaries(),
                        self.loaded.replay.truth_curve(),
                        baseline,
                        current,
                    ));
                });
        }
    }

    /// The left panel: the tabs and the page shown.
    fn left_panel_ui(&mut self, ui: &mut egui::Ui, scene: &Scene, commands: &mut Vec<Command>) {
        egui::Panel::left("layers")
            .resizable(true)
            .default_size(290.0)
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
    }

    /// The parameters page, and the baseline ghost switch while pinned.
    fn params_page_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        let info = ParamsPanelInfo {
            params: &self.params,
            units: self.loaded.replay.run().units,
            rerun_progress: self
                .background
                .as_ref()
                .and_then(|j| matches!(j.kind, JobKind::Rerun).then(|| j.task.fraction())),
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
        };
        commands.extend(params_panel_ui(ui, &mut self.params_panel, &info));
        if self.baseline.is_some() {
            let mut ghost = self.settings.baseline_ghost;
            if ui.checkbox(&mut ghost, "Baseline map (ghosted)").changed() {
                commands.push(Command::ToggleBaselineGhost);
            }
        }
    }

    /// The right panel: the decision list above the inspector.
    fn inspector_panel_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        let differences = self.differences_here();
        egui::Panel::right("inspector")
            .resizable(true)
            .default_size(580.0)
            .show(ui, |ui| {
                if let Some(view) = &self.view {
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
                    egui::Panel::top("decisions")
                        .resizable(true)
                        .default_size(190.0)
                        .show(ui, |ui| {
                            commands.extend(decisions_ui(
                                ui,
                                &ictx,
                                self.decision_filter,
                                self.selection,
                                self.baseline.as_ref().map(|_| differences.as_slice()),
                            ));
                        });
                    egui::CentralPanel::default().show(ui, |ui| {
                        egui::ScrollArea::both().show(ui, |ui| {
                            commands.extend(inspector_ui(ui, &ictx, self.selection, &self.compare));
                        });
                    });
                }
            });
    }

    /// The map view in the central panel.
    fn map_panel_ui(&mut self, ui: &mut egui::Ui, scene: &Scene, commands: &mut Vec<Command>) {
        egui::CentralPanel::default().show(ui, |ui| {
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
            commands.extend(map_view_ui(
                ui,
                scene,
                self.run().units,
                &mut self.map_view,
                self.selection,
                &describe,
                self.baseline
                    .as_ref()
                    .filter(|_| self.settings.baseline_ghost)
                    .and_then(|b| b.view.as_ref())
                    .map(|v| &v.map_after),
            ));
        });
    }

    fn status_bar_ui(&self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.label(self.loaded.source.display_name());
            ui.separator();
            if let Some(job) = &self.background {
                ui.spinner();
                let done = job.task.done();
                ui.add(
                    egui::ProgressBar::new(done as f32 / job.task.total().max(1) as f32)
                        .desired_width(160.0)
                        .text(format!("{}: {done} / {}", job.label, job.task.total())),
                );
                ui.separator();
            }
            ui.label(format!(
                "snapshot {} / {}",
                self.current(),
                self.len().saturating_sub(1)
            ));
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
