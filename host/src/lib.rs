//! qgait host library (being written).
