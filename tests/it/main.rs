//! The integration tests: one binary, one module per area.

mod app;
mod app_views;
mod architecture;
mod cli;
mod confirmation;
mod echo;
mod engine;
mod engine_properties;
mod engine_rules;
mod eval;
mod figure;
mod golden;
mod import;
mod import_firings;
mod import_fuzz;
mod import_hostile;
mod lineage;
mod log;
mod long_runs;
mod peak;
mod pose_correction;
mod scene;
mod seen_through;
mod sim;
mod suite;
mod support;
