//! Monomorphised pairings of built-in laws and formulations (placeholder).
