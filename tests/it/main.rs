//! The integration tests: one binary, one module per area.

mod app;
mod engine;
mod engine_properties;
mod scene;
