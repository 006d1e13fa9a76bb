//! `validate` (work in progress).
