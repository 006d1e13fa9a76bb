//! `gear-geometry` (work in progress).
