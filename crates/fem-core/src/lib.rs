//! # fem-core: the explicit engine (skeleton; issue 4).
