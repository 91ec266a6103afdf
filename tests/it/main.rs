//! The integration tests: one binary, one module per area.

mod app;
mod cli;
mod engine;
mod engine_properties;
mod engine_rules;
mod eval;
mod import;
mod lineage;
mod log;
mod scene;
mod sim;
