//! Environment-map images, conversions and rendering.
#![forbid(unsafe_code)]
