//! `mesh-stiffness` (work in progress).
