//! `backlash` (work in progress).
