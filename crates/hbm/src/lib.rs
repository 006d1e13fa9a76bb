//! `hbm` (work in progress).
