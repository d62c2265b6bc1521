//! Helpers shared by the integration tests (each test file uses some).
#![allow(unused_imports)]

pub(crate) use envmap_tests::{entries, text};
