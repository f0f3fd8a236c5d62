//! The versioned C-ABI table that dynamic plugins export (placeholder, filled in by the loader work).
