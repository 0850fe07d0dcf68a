//! `qgait model import` for any OpenSim lower-limb model (Rajagopal 2015/2016,
//! gait10dof18musc, ...): its leg chain as a [`ChainModel`].
//!
//! The chain is found by body, whatever the joints are called: the joints moving `pelvis`
//! (from `ground`), then per side `femur_<s>`, `tibia_<s>`, `talus_<s>`, `calcn_<s>`, `toes_<s>`,
//! each from the previous body. Joint types: `CustomJoint` (its `SpatialTransform`), `PinJoint`
//! (about the frames' z), `UniversalJoint` (x, then y), `GimbalJoint` (x, y, z), `SliderJoint`
//! (along x), `PlanarJoint` (about z, along x and y) and `WeldJoint`; offset frames with any
//! translation and orientation. Each transform axis's function (`Constant`, `LinearFunction`,
//! `SimmSpline`, `PiecewiseLinearFunction`, any of them in a `MultiplierFunction`) takes one
//! coordinate: one of the 17 gait2392 coordinates (an input), a coordinate made dependent by an
//! enforced `CoordinateCouplerConstraint` on an input (evaluated as the coupler says), or any
//! other (a locked coordinate, or one that is not an input, e.g. `pelvis_tx`): held at its
//! default value, the axis then a constant. The pelvis joint's translations and the pelvis
//! offsets' translations are dropped: points are relative to the pelvis origin, as for
//! gait2392. Every other body (upper body, patellae, ...) and constraint not used is left out,
//! with a note.
//!
//! Refused, each naming the joint and why: a chain body no joint moves (or several do), a joint
//! from the wrong parent, `reverse`, a joint type whose motion is not one function of one
//! coordinate per axis (`BallJoint`, `FreeJoint`, ...), an axis driven by several coordinates,
//! function types the kernel does not evaluate (`NaturalCubicSpline`, `GCVSpline`,
//! `PolynomialFunction`, ...), splines of more than 16 knots, a coupler of several or non-input
//! independent coordinates, and other constraints on a chain body.
//!
//! The toe tip: marker `R.Toe.Tip`/`L.Toe.Tip` (from `--markers`, else the model's markers) on
//! any chain body, else gait2392's (0.0812, 0.007, ∓0.00108) in `toes_<s>` times the toes'
//! geometry scale factors.

use qgait_kernel::models::gait2392::COORDINATES;
use roxmltree::Document;

use crate::chain::{
    AxisData, ChainModel, CouplerData, FunctionData, JointData, PointData, RangeData, BODIES,
};
use qgait_opensim::diagnostics::Location;
use qgait_opensim::osim::{
    self, child, function, generic_toe_tip, location_of, name_of, read_coordinates, read_joints,
    text_of, toe_marker, Coordinate, Function, ImportError, Joint,
};

/// An imported chain and one line per choice made.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedChain {
    /// The chain.
    pub model: ChainModel,
    /// How the file was read: what was held, left out, where the toe tip came from.
    pub notes: Vec<String>,
}

struct Coupling {
    name: String,
    /// Where its element is.
    at: Location,
    dependent: String,
    independent: Vec<String>,
    function: Function,
}

/// Imports the leg chain of `text` (an `.osim` named `source`); `markers` as for
/// [`osim::import`].
pub fn import(
    text: &str,
    source: &str,
    markers: Option<(&str, &str)>,
) -> Result<ImportedChain, ImportError> {
    let (doc, version) = osim::document(text, source)?;
    let in_file = |e: ImportError| e.in_file(source);
    let mut notes = vec![format!(
        "imported from {source} (OpenSim Version={version}) by qgait model import as a general lower-limb chain"
    )];
    let joints = read_joints(&doc).map_err(in_file)?;
    let coordinates = read_coordinates(&doc);
    let couplings = read_couplings(&doc).map_err(in_file)?;
    let mut state = State {
        coordinates: &coordinates,
        couplings: &couplings,
        used: Vec::new(),
        notes: Vec::new(),
        leg_body: None,
    };
    let moved = |body: &str| joints.iter().any(|j| j.child == body);
    let missing = match (moved("femur_r"), moved("femur_l")) {
        (true, false) => Some(("femur_l", "femur_r")),
        (false, true) => Some(("femur_r", "femur_l")),
        _ => None,
    };
    if let Some((side, other)) = missing {
        // leg39, leg6dof9musc: one leg on a pelvis.
        return Err(ImportError::chain(Location::file(source), format!(
            "a single-leg model: no joint moves `{side}` (only `{other}`); qgait's lower-limb chains have both legs"
        )));
    }
    let mut out = Vec::new();
    for (b, body) in BODIES.iter().enumerate() {
        let parent = match b {
            0 => "ground",
            1 | 6 => "pelvis",
            _ => BODIES[b - 1],
        };
        let j = osim::joint_moving(&joints, parent, body).map_err(in_file)?;
        let before = state.notes.len();
        state.leg_body = (b > 0).then_some(*body);
        let mut data = state.joint(j).map_err(in_file)?;
        if b == 0 {
            // (What the dropped translations would have held is not worth a note.)
            let prefix = format!("joint `{}` translation", j.name);
            let mut k = before;
            while k < state.notes.len() {
                if state.notes[k].starts_with(&prefix) {
                    state.notes.remove(k);
                } else {
                    k += 1;
                }
            }
            // Points are relative to the pelvis origin: the pelvis does not translate.
            data.parent_translation = [0.0; 3];
            data.child_translation = [0.0; 3];
            if !data.translations.is_empty() {
                notes.push(format!(
                    "joint `{}`: pelvis translations left out (points are relative to the pelvis origin)",
                    j.name
                ));
            }
            data.translations.clear();
        }
        out.push(data);
    }
    notes.append(&mut state.notes);
    let mut couplers = Vec::new();
    for c in &couplings {
        if !state.used.contains(&c.dependent) {
            continue;
        }
        let what = format!("CoordinateCouplerConstraint `{}`", c.name);
        let [independent] = c.independent.as_slice() else {
            return Err(ImportError::chain(
                c.at.clone(),
                format!(
                    "{what}: {} depends on [{}]; a chain coordinate may follow one input",
                    c.dependent,
                    c.independent.join(", ")
                ),
            ));
        };
        if !COORDINATES.contains(&independent.as_str()) {
            return Err(ImportError::chain(
                c.at.clone(),
                format!(
                    "{what}: {} follows `{independent}`, which is not a chain input ({})",
                    c.dependent,
                    COORDINATES.join(", ")
                ),
            ));
        }
        couplers.push(CouplerData {
            dependent: c.dependent.clone(),
            independent: independent.clone(),
            function: function_data(&c.function, &what, &c.at).map_err(in_file)?,
        });
        notes.push(format!(
            "{what}: {} evaluated as a function of {independent}",
            c.dependent
        ));
    }
    let unused: Vec<&str> = couplings
        .iter()
        .filter(|c| !state.used.contains(&c.dependent))
        .map(|c| c.name.as_str())
        .collect();
    if !unused.is_empty() {
        notes.push(format!(
            "left out: constraints on bodies outside the leg chain: {}",
            unused.join(", ")
        ));
    }
    check_other_constraints(&doc).map_err(in_file)?;
    let others: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("Body"))
        .map(name_of)
        .filter(|n| !n.is_empty() && !BODIES.contains(&n.as_str()))
        .collect();
    if !others.is_empty() {
        notes.push(format!(
            "left out: bodies outside the leg chain (upper body, patellae, ...): {}",
            others.join(", ")
        ));
    }
    let marker_doc = match markers {
        Some((t, s)) => Some((osim::parse_xml(t, s)?, s)),
        None => None,
    };
    let mut toe_tips = Vec::new();
    for s in ["r", "l"] {
        let (tip, note) = toe_tip(&doc, source, marker_doc.as_ref(), s).map_err(in_file)?;
        toe_tips.push(tip);
        notes.push(note);
    }
    // The clamped ranges of the inputs the chain moves (what `qgait imu` keeps them within).
    let ranges = COORDINATES
        .iter()
        .filter(|c| {
            out.iter().any(|j| {
                j.rotations
                    .iter()
                    .chain(&j.translations)
                    .any(|a| a.coordinate.as_deref() == Some(**c))
            })
        })
        .filter_map(|c| {
            let m = coordinates.iter().find(|m| m.name == *c)?;
            let (min, max) = m.clamped?;
            Some(RangeData {
                coordinate: c.to_string(),
                min,
                max,
            })
        })
        .collect();
    let model = ChainModel {
        joints: out,
        couplers,
        toe_tips,
        ranges,
    };
    model
        .build()
        .map_err(|fault| ImportError::chain(Location::file(source), fault.message))?;
    Ok(ImportedChain { model, notes })
}

/// What the joints read so far need.
struct State<'a> {
    coordinates: &'a [Coordinate],
    couplings: &'a [Coupling],
    /// Coupled coordinates the chain uses.
    used: Vec<String>,
    notes: Vec<String>,
    /// The leg body the joint being read moves (`None` for the pelvis): a free coordinate of a
    /// leg joint must be an input.
    leg_body: Option<&'static str>,
}

impl State<'_> {
    fn joint(&mut self, j: &Joint) -> Result<JointData, ImportError> {
        let name = &j.name;
        if j.reverse {
            return Err(ImportError::chain(j.at.clone(), format!(
                "joint `{name}`: reverse=true is not supported (the chain runs from the pelvis down)"
            )));
        }
        let line = |c: usize| -> Result<(String, Function), ImportError> {
            let coordinate = j.coordinates.get(c).ok_or_else(|| {
                ImportError::chain(
                    j.at.clone(),
                    format!("joint `{name}` ({}): coordinate {} missing", j.kind, c + 1),
                )
            })?;
            Ok((coordinate.clone(), Function::Linear(1.0, 0.0)))
        };
        let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        let (rotations, translations): (Vec<_>, Vec<_>) = match j.kind.as_str() {
            "CustomJoint" => {
                let mut r = Vec::new();
                let mut t = Vec::new();
                for a in &j.axes {
                    let what = format!("joint `{name}` {}", a.name);
                    let coordinate = match a.coordinates.as_slice() {
                        [] => None,
                        [c] => Some(c.clone()),
                        many => {
                            return Err(ImportError::chain(j.at.clone(), format!(
                                "{what}: a function of several coordinates [{}]; each axis must follow one",
                                many.join(", ")
                            )))
                        }
                    };
                    let axis = self.axis(a.axis, coordinate, &a.function, &what, &j.at)?;
                    if a.name.starts_with("rotation") {
                        r.push(axis);
                    } else {
                        t.push(axis);
                    }
                }
                (r, t)
            }
            "PinJoint" => {
                let (c, f) = line(0)?;
                (vec![self.axis(z, Some(c), &f, name, &j.at)?], vec![])
            }
            "UniversalJoint" => {
                let (c0, f0) = line(0)?;
                let (c1, f1) = line(1)?;
                (
                    vec![self.axis(x, Some(c0), &f0, name, &j.at)?, self.axis(y, Some(c1), &f1, name, &j.at)?],
                    vec![],
                )
            }
            "GimbalJoint" => {
                let mut r = Vec::new();
                for (k, a) in [x, y, z].into_iter().enumerate() {
                    let (c, f) = line(k)?;
                    r.push(self.axis(a, Some(c), &f, name, &j.at)?);
                }
                (r, vec![])
            }
            "SliderJoint" => {
                let (c, f) = line(0)?;
                (vec![], vec![self.axis(x, Some(c), &f, name, &j.at)?])
            }
            "PlanarJoint" => {
                let (c0, f0) = line(0)?;
                let (c1, f1) = line(1)?;
                let (c2, f2) = line(2)?;
                (
                    vec![self.axis(z, Some(c0), &f0, name, &j.at)?],
                    vec![self.axis(x, Some(c1), &f1, name, &j.at)?, self.axis(y, Some(c2), &f2, name, &j.at)?],
                )
            }
            "WeldJoint" => (vec![], vec![]),
            other => {
                return Err(ImportError::chain(j.at.clone(), format!(
                    "joint `{name}` is a {other}: its motion is not one function of one coordinate per axis, which is what a leg chain is made of (CustomJoint, PinJoint, UniversalJoint, GimbalJoint, SliderJoint, PlanarJoint, WeldJoint)"
                )))
            }
        };
        Ok(JointData {
            name: name.clone(),
            kind: j.kind.clone(),
            body: j.child.clone(),
            parent_translation: j.location_in_parent,
            parent_orientation: j.orientation_in_parent,
            child_translation: j.location_in_child,
            child_orientation: j.orientation_in_child,
            rotations,
            translations,
        })
    }

    /// One axis, its coordinate resolved: an input or a used coupler kept, anything else held.
    fn axis(
        &mut self,
        axis: [f64; 3],
        coordinate: Option<String>,
        f: &Function,
        what: &str,
        at: &Location,
    ) -> Result<AxisData, ImportError> {
        let function = function_data(f, what, at)?;
        let held = |value: f64, why: String, notes: &mut Vec<String>| {
            let v = function
                .at(value)
                .map_err(|e| ImportError::chain(at.clone(), format!("{what}: {e}")))?;
            notes.push(why);
            Ok::<_, ImportError>(AxisData {
                axis,
                coordinate: None,
                function: FunctionData::Constant { value: v },
            })
        };
        let Some(c) = coordinate else {
            return if matches!(function, FunctionData::Constant { .. }) {
                Ok(AxisData {
                    axis,
                    coordinate: None,
                    function,
                })
            } else {
                held(
                    0.0,
                    format!("{what}: no coordinate: evaluated at 0"),
                    &mut self.notes,
                )
            };
        };
        if matches!(function, FunctionData::Constant { .. }) {
            return Ok(AxisData {
                axis,
                coordinate: None,
                function,
            });
        }
        let model = self.coordinates.iter().find(|m| m.name == c);
        let default = model.map_or(0.0, |m| m.default);
        if model.is_some_and(|m| m.locked) {
            return held(
                default,
                format!(
                    "{what}: coordinate {c} is locked in the model: held at its default {default}"
                ),
                &mut self.notes,
            );
        }
        if self.couplings.iter().any(|k| k.dependent == c) {
            if !self.used.contains(&c) {
                self.used.push(c.clone());
            }
            return Ok(AxisData {
                axis,
                coordinate: Some(c),
                function,
            });
        }
        if COORDINATES.contains(&c.as_str()) {
            return Ok(AxisData {
                axis,
                coordinate: Some(c),
                function,
            });
        }
        if let Some(body) = self.leg_body {
            // Held, the leg would not follow the motion's coordinate of that name.
            return Err(ImportError::chain(at.clone(), format!(
                "{what}: coordinate `{c}` moves `{body}` but is not one of the chain's inputs ({}): rename it in the model to the input it is (e.g. hip_flexion_r), or lock it to hold it at its default",
                COORDINATES.join(", ")
            )));
        }
        held(
            default,
            format!("{what}: coordinate {c} is not a chain input: held at its default {default}"),
            &mut self.notes,
        )
    }
}

fn function_data(f: &Function, what: &str, at: &Location) -> Result<FunctionData, ImportError> {
    Ok(match f {
        Function::Constant(value) => FunctionData::Constant { value: *value },
        Function::Linear(slope, intercept) => FunctionData::Linear {
            slope: *slope,
            intercept: *intercept,
        },
        Function::SimmSpline(x, y) => FunctionData::SimmSpline {
            x: x.clone(),
            y: y.clone(),
        },
        Function::PiecewiseLinear(x, y) => FunctionData::PiecewiseLinear {
            x: x.clone(),
            y: y.clone(),
        },
        Function::Polynomial(coefficients) => FunctionData::Polynomial {
            coefficients: coefficients.clone(),
        },
        Function::Other(t) => {
            return Err(ImportError::chain(at.clone(), format!(
                "{what}: function type {t} is not supported (Constant, LinearFunction, SimmSpline, PiecewiseLinearFunction, PolynomialFunction, MultiplierFunction of these)"
            )))
        }
    })
}

fn read_couplings(doc: &Document) -> Result<Vec<Coupling>, ImportError> {
    let mut out = Vec::new();
    for c in doc
        .descendants()
        .filter(|n| n.has_tag_name("CoordinateCouplerConstraint") && osim::enforced(*n))
    {
        let name = name_of(c);
        let what = format!("CoordinateCouplerConstraint `{name}`");
        let f = child(c, "coupled_coordinates_function")
            .and_then(|f| f.children().find(|e| e.is_element()))
            .ok_or_else(|| {
                ImportError::chain(
                    location_of(c),
                    format!("{what}: no coupled_coordinates_function"),
                )
            })?;
        let words = |tag: &str| -> Vec<String> {
            text_of(c, tag)
                .unwrap_or("")
                .split_whitespace()
                .map(String::from)
                .collect()
        };
        out.push(Coupling {
            dependent: words("dependent_coordinate_name").join(" "),
            independent: words("independent_coordinate_names"),
            function: function(f, &what)?,
            name,
            at: location_of(c),
        });
    }
    Ok(out)
}

/// Constraints other than couplers that name a chain body are refused.
fn check_other_constraints(doc: &Document) -> Result<(), ImportError> {
    let bodies: Vec<String> = BODIES.iter().map(|b| b.to_string()).collect();
    match osim::constraint_naming(doc, &bodies, Some("CoordinateCouplerConstraint")) {
        Some((c, hit)) => Err(ImportError::chain(location_of(c), format!(
            "{} `{}` constrains body `{hit}` of the leg chain; only CoordinateCouplerConstraint is supported",
            c.tag_name().name(),
            name_of(c)
        ))),
        None => Ok(()),
    }
}

fn toe_tip(
    model: &Document,
    source: &str,
    markers: Option<&(Document, &str)>,
    s: &str,
) -> Result<(PointData, String), ImportError> {
    let (name, found) = toe_marker(model, source, markers, s)?;
    if let Some(((body, location), file)) = found {
        if !BODIES[1..].contains(&body.as_str()) {
            return Err(ImportError::chain(
                Location::file(file),
                format!("marker `{name}` is on `{body}`; the toe tip must be on a leg body"),
            ));
        }
        let note = format!("toe tip {s}: marker {name} from {file} on {body} at {location:?}");
        return Ok((PointData { body, location }, note));
    }
    let (location, note) = generic_toe_tip(model, s, name);
    Ok((
        PointData {
            body: format!("toes_{s}"),
            location,
        },
        note,
    ))
}
