//! The integration tests: one binary, one module per area.

mod app;
mod cli;
mod engine;
mod engine_properties;
mod eval;
mod import;
mod import_fuzz;
mod import_hostile;
mod log;
mod peak;
mod scene;
mod sim;
