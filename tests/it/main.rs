//! The integration tests: one binary, one module per area.

mod engine;
mod engine_properties;
mod cli;
mod eval;
mod log;
mod sim;
