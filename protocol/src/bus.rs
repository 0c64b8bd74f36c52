//! Placeholder: filled in by the bus work.
