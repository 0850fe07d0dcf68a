//! qgait wire protocol (being written).
