//! Environment-map parameterizations.
#![no_std]
#![forbid(unsafe_code)]
