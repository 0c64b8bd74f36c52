//! Placeholder: filled in by the link work.
