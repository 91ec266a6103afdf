//! The integration-test binary (one binary, one module a concern).

mod scene;
