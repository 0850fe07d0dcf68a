//! Segment lengths from a TOML file.
//!
//! Keys (metres): `pelvis_half_width`, `femur`, `tibia`, `foot`. Each may instead be given per
//! side as `<key>_r` and `<key>_l`. A length not given keeps the gait2392 value (with a
//! warning); unknown keys, giving both `<key>` and `<key>_r`/`_l`, non-numbers, and lengths that
//! are not positive (a pelvis half-width may be zero) or above 3 m are errors, each naming the
//! file, line and column. Read with serde, as `SUBJECT.toml` is ([`super::subject`]). Example:
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
use serde::de::{self, Deserializer, Visitor};
use serde::Deserialize;
use toml::Spanned;

use super::toml_error;
use crate::error::ModelError;
use qgait_opensim::diagnostics::{Location, Warning, WarningText};

/// One length as the file gives it: for both sides, right, left.
type Given<'a> = [&'a Option<Spanned<Metres>>; 3];

/// Declares the file's struct, a field per key, and `lengths`, each length's three keys: `$key`
/// for both sides, `$right`, `$left`. The keys are named once, here.
macro_rules! anthropometry_file {
    ($($key:ident, $right:ident, $left:ident;)*) => {
        /// The file: each length for both sides, or per side (`_r`, `_l`); every key optional.
        #[derive(Debug, Default, Deserialize)]
        #[serde(deny_unknown_fields)]
        struct AnthropometryFile {
            $(
                $key: Option<Spanned<Metres>>,
                $right: Option<Spanned<Metres>>,
                $left: Option<Spanned<Metres>>,
            )*
        }

        impl AnthropometryFile {
            /// Each length's keys, in [`Limb`] order: the name and its three ways of being
            /// given.
            fn lengths(&self) -> [(&'static str, Given<'_>); 4] {
                [$((stringify!($key), [&self.$key, &self.$right, &self.$left]),)*]
            }
        }
    };
}

anthropometry_file! {
    pelvis_half_width, pelvis_half_width_r, pelvis_half_width_l;
    femur, femur_r, femur_l;
    tibia, tibia_r, tibia_l;
    foot, foot_r, foot_l;
}

/// A length in metres: a TOML float or integer (anything else is an error that says so).
#[derive(Debug, Clone, Copy)]
struct Metres(f64);

impl<'de> Deserialize<'de> for Metres {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Number;
        impl Visitor<'_> for Number {
            type Value = Metres;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number (a length in metres)")
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<Metres, E> {
                Ok(Metres(x))
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<Metres, E> {
                Ok(Metres(x as f64))
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<Metres, E> {
                Ok(Metres(x as f64))
            }
        }
        d.deserialize_any(Number)
    }
}

/// Reads an anthropometry file.
pub fn read(path: &Path) -> Result<(Anthropometry<f64>, Vec<Warning>), ModelError> {
    let shown = path.display().to_string();
    let text = crate::error::read_text(path, &shown)?;
    parse(&text, &shown)
}

/// Parses the text of an anthropometry file; `source` names it in messages, with the line and
/// column of the offending key or value.
pub fn parse(text: &str, source: &str) -> Result<(Anthropometry<f64>, Vec<Warning>), ModelError> {
    let file: AnthropometryFile =
        toml::from_str(text).map_err(|e| toml_error(text, source, e.span(), e.message()))?;
    let default = Limb::<f64>::gait2392();
    let defaults = [
        default.pelvis_half_width,
        default.femur,
        default.tibia,
        default.foot,
    ];
    let mut sides = [[0.0; 4]; 2];
    let mut missing: [Vec<&str>; 2] = [Vec::new(), Vec::new()];
    for (i, (key, [both, right, left])) in file.lengths().into_iter().enumerate() {
        for (s, (split, suffix)) in [(right, "r"), (left, "l")].into_iter().enumerate() {
            sides[s][i] = match (both, split) {
                (Some(_), Some(v)) => {
                    return Err(toml_error(
                        text,
                        source,
                        Some(v.span()),
                        &format!("both `{key}` and `{key}_{suffix}` are given; use one"),
                    ))
                }
                (Some(v), None) | (None, Some(v)) => {
                    let x = v.get_ref().0;
                    // A zero pelvis half-width puts both hips at the pelvis origin; a zero
                    // segment length is no segment.
                    let lowest_ok = if i == 0 { x >= 0.0 } else { x > 0.0 };
                    if !x.is_finite() || !lowest_ok || x > 3.0 {
                        return Err(toml_error(
                            text,
                            source,
                            Some(v.span()),
                            &format!("{x} is not a plausible length in metres"),
                        ));
                    }
                    x
                }
                (None, None) => {
                    missing[s].push(key);
                    defaults[i]
                }
            };
        }
    }
    let mut warnings = Vec::new();
    for (s, side) in ["right", "left"].iter().enumerate() {
        if !missing[s].is_empty() {
            warnings.push(Warning::MissingDefaulted(WarningText {
                at: Some(Location::file(source)),
                detail: format!(
                    "no {} for the {side} side; using the gait2392 value(s)",
                    missing[s].join(", ")
                ),
            }));
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
        assert_eq!(w[0].to_string(), "a.toml: no pelvis_half_width, tibia, foot for the right side; using the gait2392 value(s)");
    }

    #[test]
    fn integers_are_metres_and_a_zero_pelvis_half_width_is_allowed() {
        let (a, w) = parse(
            "pelvis_half_width = 0\nfemur = 1\ntibia = 1\nfoot = 1\n",
            "a.toml",
        )
        .unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(a.left.pelvis_half_width, 0.0);
        assert_eq!(a.right.tibia, 1.0);
    }

    #[test]
    fn bad_files_are_errors() {
        for (text, needle) in [
            (
                "femur = 0.4\nfemur_r = 0.4\n",
                "a.toml:2:11: both `femur` and `femur_r` are given",
            ),
            (
                "tibia = 0.4\nfemr = 0.4\n",
                "a.toml:2:1: unknown field `femr`",
            ),
            (
                "foot = 0.2\nfemur = \"long\"\n",
                "a.toml:2:9: invalid type: string \"long\", expected a number (a length in metres)",
            ),
            (
                "femur = 0.4\ntibia_l = -0.4\n",
                "a.toml:2:11: -0.4 is not a plausible length in metres",
            ),
            ("foot = 0\n", "a.toml:1:8: 0 is not a plausible"),
            ("femur = nan\n", "a.toml:1:9: NaN is not a plausible"),
            (
                "pelvis_half_width = 3.5\n",
                "a.toml:1:21: 3.5 is not a plausible",
            ),
            ("[femur]\nr = 0.4\n", "a.toml:1:1: invalid type: map"),
            ("tibia = 0.4\nfemur = \n", "a.toml:2:9: "),
        ] {
            let err = parse(text, "a.toml").unwrap_err().to_string();
            assert!(err.starts_with(needle), "{text:?}: {err}");
            assert!(!err.contains('\n'), "{err}");
        }
    }
}
