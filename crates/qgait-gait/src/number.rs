//! Numbers as the report, its CSVs and `summary.json` write them.

/// A number with at most `decimals` decimals, without trailing zeros.
pub fn round(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}
