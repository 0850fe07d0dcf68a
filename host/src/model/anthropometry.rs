//! Segment lengths from a TOML file.
//!
//! Keys (metres): `pelvis_half_width`, `femur`, `tibia`, `foot`. Each may instead be given per
//! side as `<key>_r` and `<key>_l`. A length not given keeps the gait2392 value (with a
//! warning); unknown keys, giving both `<key>` and `<key>_r`/`_l`, non-numbers, and lengths that
//! are not positive are errors. Example:
//!
//! ```toml
//! pelvis_half_width = 0.0835
//! femur_r = 0.40
//! femur_l = 0.39
//! tibia = 0.43
//! foot = 0.21
//! ```

use std::path::Path;

use qgait_kernel::anthropometry::{Anthropometry, Limb};

use crate::diagnostics::Warning;

const KEYS: [&str; 4] = ["pelvis_half_width", "femur", "tibia", "foot"];

/// Reads an anthropometry file.
pub fn read(path: &Path) -> Result<(Anthropometry<f64>, Vec<Warning>), String> {
    let shown = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{shown}: cannot read: {e}"))?;
    parse(&text, &shown)
}

/// Parses the text of an anthropometry file; `source` names it in messages.
pub fn parse(text: &str, source: &str) -> Result<(Anthropometry<f64>, Vec<Warning>), String> {
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
            format!("{source}:{line}:{column}: {}", one_line(e.message()))
        }
        None => format!("{source}: {}", one_line(e.message())),
    })?;
    for key in table.keys() {
        let known = KEYS
            .iter()
            .any(|k| key == k || key == &format!("{k}_r") || key == &format!("{k}_l"));
        if !known {
            return Err(format!(
                "{source}: unknown key `{key}` (expected pelvis_half_width, femur, tibia, foot, each optionally with _r/_l)"
            ));
        }
    }
    let number = |key: &str| -> Result<Option<f64>, String> {
        let Some(v) = table.get(key) else {
            return Ok(None);
        };
        let x = match v {
            toml::Value::Float(f) => *f,
            toml::Value::Integer(i) => *i as f64,
            other => {
                return Err(format!(
                    "{source}: `{key}` must be a number in metres, found {}",
                    other.type_str()
                ))
            }
        };
        let min_ok = if key.starts_with("pelvis") {
            x >= 0.0
        } else {
            x > 0.0
        };
        if !x.is_finite() || !min_ok || x > 3.0 {
            return Err(format!(
                "{source}: `{key}` = {x} is not a plausible length in metres"
            ));
        }
        Ok(Some(x))
    };
    let mut warnings = Vec::new();
    let default = Limb::<f64>::gait2392();
    let defaults = [
        default.pelvis_half_width,
        default.femur,
        default.tibia,
        default.foot,
    ];
    let mut sides = [[0.0; 4]; 2];
    let mut missing: [Vec<&str>; 2] = [Vec::new(), Vec::new()];
    for (i, key) in KEYS.iter().enumerate() {
        let both = number(key)?;
        for (s, suffix) in ["r", "l"].iter().enumerate() {
            let split_key = format!("{key}_{suffix}");
            sides[s][i] = match (both, number(&split_key)?) {
                (Some(_), Some(_)) => {
                    return Err(format!(
                        "{source}: both `{key}` and `{split_key}` are given; use one"
                    ))
                }
                (Some(v), None) | (None, Some(v)) => v,
                (None, None) => {
                    missing[s].push(*key);
                    defaults[i]
                }
            };
        }
    }
    for (s, side) in ["right", "left"].iter().enumerate() {
        if !missing[s].is_empty() {
            warnings.push(Warning(format!(
                "{source}: no {} for the {side} side; using the gait2392 value(s)",
                missing[s].join(", ")
            )));
        }
    }
    let limb = |v: [f64; 4]| Limb {
        pelvis_half_width: v[0],
        femur: v[1],
        tibia: v[2],
        foot: v[3],
    };
    Ok((
        Anthropometry {
            right: limb(sides[0]),
            left: limb(sides[1]),
        },
        warnings,
    ))
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_and_split_keys() {
        let text =
            "pelvis_half_width = 0.08\nfemur_r = 0.40\nfemur_l = 0.39\ntibia = 0.43\nfoot = 0.2\n";
        let (a, w) = parse(text, "a.toml").unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(a.right.femur, 0.40);
        assert_eq!(a.left.femur, 0.39);
        assert_eq!(a.left.pelvis_half_width, 0.08);
        assert_eq!(a.right.foot, 0.2);
    }

    #[test]
    fn missing_lengths_default_to_gait2392_with_a_warning() {
        let (a, w) = parse("femur = 1\n", "a.toml").unwrap();
        assert_eq!(a.right.femur, 1.0);
        assert_eq!(a.left.tibia, Limb::<f64>::gait2392().tibia);
        assert_eq!(w.len(), 2);
        assert_eq!(w[0].0, "a.toml: no pelvis_half_width, tibia, foot for the right side; using the gait2392 value(s)");
    }

    #[test]
    fn bad_files_are_errors() {
        for (text, needle) in [
            ("femur = 0.4\nfemur_r = 0.4\n", "both `femur` and `femur_r`"),
            ("femr = 0.4\n", "unknown key `femr`"),
            ("femur = \"long\"\n", "must be a number"),
            ("femur = -0.4\n", "not a plausible length"),
            ("tibia = 0.4\nfemur = \n", "a.toml:2:9: "),
        ] {
            let err = parse(text, "a.toml").unwrap_err();
            assert!(err.contains(needle), "{text:?}: {err}");
            assert!(!err.contains('\n'), "{err}");
        }
    }
}
