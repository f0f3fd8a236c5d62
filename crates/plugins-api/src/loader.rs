//! Loading friction laws from shared libraries (placeholder).
