//! `timestep` (work in progress).
