//! The conformance suite of friction-math §5 (placeholder).
