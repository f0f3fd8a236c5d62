//! # tools-nurbs: rigid NURBS and faceted tools (skeleton; issue 3).
