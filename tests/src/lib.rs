//! Shared helpers for the verification and system tests.
