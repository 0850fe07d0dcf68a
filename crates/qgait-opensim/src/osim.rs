//! `qgait model import`: the leg chain of a gait2392-family OpenSim model (`.osim`, OpenSim
//! 3.x or 4.x XML) as a [`Gait2392Geometry`].
//!
//! The chain is found by body: the joints whose children are `pelvis`, `femur_<s>`, `tibia_<s>`,
//! `talus_<s>`, `calcn_<s>` and `toes_<s>` (`s` = `r`, `l`), each of whose parent must be the
//! previous body (`ground` for the pelvis). Both XML layouts are read:
//!
//! - 3.x (`Version` < 30000): each joint is nested in its child `<Body>` as
//!   `<Joint><CustomJoint>` with `<parent_body>`, `<location_in_parent>`,
//!   `<orientation_in_parent>`, `<location>`, `<orientation>`; transform functions are wrapped
//!   in `<function>`.
//! - 4.x: joints are in `<JointSet>`; `<socket_parent_frame>`/`<socket_child_frame>` name a
//!   `PhysicalOffsetFrame` in the joint's `<frames>` (its `<socket_parent>` is the body, its
//!   `<translation>`/`<orientation>` the offset) or a body directly; functions are elements
//!   with `name="function"`.
//!
//! What is read: the parent offsets (hip, ankle, subtalar, MTP centres; a knee offset is added
//! to the knee splines), the `CustomJoint` rotation axes with their coordinates, and the knee's
//! two translation functions. Functions supported: `Constant` (0 on unused axes),
//! `LinearFunction` (`1 0` on rotations; any line on a knee translation), `SimmSpline` (knee
//! translations), and any of these inside a `MultiplierFunction` (what OpenSim 4's scale tool
//! writes). Refused, with an error that names the joint or constraint: other joint types,
//! non-zero `orientation_in_parent`/`orientation`/child `location`, `reverse`, rotations that
//! are not the gait2392 coordinates (in gait2392's order and, for pelvis and knee, about
//! gait2392's axes), translations other than the knee's, other function types (e.g.
//! `NaturalCubicSpline`, `GCVSpline`), more than 12 spline knots, and constraints (e.g. a
//! `CoordinateCouplerConstraint`) that involve the chain.
//!
//! The toe tip (gait2392 carries no markers): markers `R.Toe.Tip`/`L.Toe.Tip` on `calcn_<s>` or
//! `toes_<s>` from a marker file given with `--markers`, else from the model's own `MarkerSet`,
//! else the generic station (0.0812, 0.007, ∓0.00108) in `toes_<s>` multiplied axis by axis by
//! the toes' geometry scale factors (3.x `<VisibleObject><scale_factors>`, 4.x
//! `<attached_geometry>` mesh `<scale_factors>`: OpenSim's scale tool multiplies them by the
//! body's scale factors; 1 when absent).

use qgait_kernel::models::gait2392::{Knots, LegGeometry, COORDINATES};
use qgait_kernel::Gait2392Geometry;
use roxmltree::{Document, Node};

use crate::diagnostics::Location;

/// Why an OpenSim model's leg chain cannot be imported.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportError {
    /// The file (the model or the marker file) is not XML.
    #[error("{at}: not XML: {message}")]
    Xml {
        /// Where the XML parser stopped.
        at: Location,
        /// The parser's reason.
        message: String,
    },
    /// The XML is not an OpenSim model (no `<OpenSimDocument Version=...>`).
    #[error("{0}: no <OpenSimDocument Version=...>: not an OpenSim model")]
    NotOpenSim(String),
    /// A number in the model (or the marker file) is not a finite number.
    #[error("{at}: {what}: bad number `{text}`")]
    BadNumber {
        /// The element holding it.
        at: Location,
        /// What the numbers are (e.g. joint `hip_r` rotation1).
        what: String,
        /// The text that is not a number.
        text: String,
    },
    /// An element holds the wrong count of numbers (an offset needs 3).
    #[error("{at}: {what}: expected {expected} numbers, found `{text}`")]
    NumberCount {
        /// The element.
        at: Location,
        /// What the numbers are.
        what: String,
        /// How many it must hold.
        expected: usize,
        /// Its text.
        text: String,
    },
    /// The model's leg chain is not one qgait evaluates: the joint (or constraint) and why.
    #[error("{at}: {message}")]
    Chain {
        /// The model file, and the element's line and column where one element is at fault.
        at: Location,
        /// Which joint and why.
        message: String,
    },
}

impl ImportError {
    /// The refusal of a chain at `at`: which joint (or constraint) and why.
    pub fn chain(at: Location, message: impl Into<String>) -> Self {
        Self::Chain {
            at,
            message: message.into(),
        }
    }

    /// The error with its file named `path` where it has none yet: the functions that read a
    /// parsed document ([`read_joints`], [`function`], ...) know the line and column of what
    /// they refuse, not the file's name.
    pub fn in_file(mut self, path: &str) -> Self {
        if let Self::BadNumber { at, .. } | Self::NumberCount { at, .. } | Self::Chain { at, .. } =
            &mut self
        {
            if at.path.is_empty() {
                at.path = path.to_string();
            }
        }
        self
    }
}

/// Where element `n` starts in its document: line and column (the file is named later, by
/// [`ImportError::in_file`]).
pub fn location_of(n: Node) -> Location {
    let pos = n.document().text_pos_at(n.range().start);
    Location {
        path: String::new(),
        line: Some(pos.row as usize),
        column: Some(pos.col as usize),
    }
}

/// No element in particular: the model as a whole (the file is named by
/// [`ImportError::in_file`]).
fn whole() -> Location {
    Location::file("")
}

/// Parses the XML of an `.osim` file named `source`; a file that is not XML is named as such.
pub fn parse_xml<'a>(text: &'a str, source: &str) -> Result<Document<'a>, ImportError> {
    Document::parse(text).map_err(|e| match e {
        // The parser places these at 1:1; the file ends where they were found (a file cut
        // off, or an element left open).
        roxmltree::Error::UnclosedRootNode | roxmltree::Error::UnexpectedEndOfStream => {
            ImportError::Xml {
                at: Location::in_text(source, text, text.len()),
                message: format!("{e}: the file ends here"),
            }
        }
        e => {
            let pos = e.pos();
            ImportError::Xml {
                at: Location {
                    path: source.to_string(),
                    line: Some(pos.row as usize),
                    column: Some(pos.col as usize),
                },
                message: e.to_string(),
            }
        }
    })
}

/// An imported model: the geometry and one line per choice made (for the file's comment).
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    /// The numbers.
    pub geometry: Gait2392Geometry,
    /// How the file was read and where the toe tip came from.
    pub notes: Vec<String>,
}

/// The generic toe tip in `toes_r` (left: z negated).
pub const GENERIC_TOETIP_RIGHT: [f64; 3] = [0.0812, 0.007, -0.00108];

/// Imports `text` (an `.osim` file named `source` in messages); `markers` is an optional
/// marker file (text and name) holding `R.Toe.Tip`/`L.Toe.Tip`.
pub fn import(
    text: &str,
    source: &str,
    markers: Option<(&str, &str)>,
) -> Result<Imported, ImportError> {
    let (doc, version) = document(text, source)?;
    let in_file = |e: ImportError| e.in_file(source);
    let joints = read_joints(&doc).map_err(in_file)?;
    check_constraints(&doc).map_err(in_file)?;
    // gait2392's table moves every coordinate freely; a locked or clamped one takes the
    // general chain, which holds it at its default or keeps it in its range (`qgait imu`) as
    // OpenSim does.
    if let Some((c, how)) = held_coordinate(&doc) {
        return Err(ImportError::chain(
            Location::file(source),
            format!("coordinate {c} is {how} in the model; gait2392's table moves every coordinate freely"),
        ));
    }
    let mut notes = vec![format!(
        "imported from {source} (OpenSim {} format, Version={version}) by qgait model import",
        if version < 30000 { "3.x" } else { "4.x" }
    )];
    notes.extend(non_zero_defaults(&doc));
    let pelvis = chain_joint(&joints, "ground", "pelvis").map_err(in_file)?;
    check_pelvis(pelvis).map_err(in_file)?;
    let marker_doc = match markers {
        Some((t, s)) => Some((parse_xml(t, s)?, s)),
        None => None,
    };
    let mut legs = Vec::new();
    for s in ["r", "l"] {
        let mut leg = read_leg(&joints, s).map_err(in_file)?;
        let (tip, note) = toe_tip(&doc, source, marker_doc.as_ref(), s, &leg).map_err(in_file)?;
        leg.toetip_in_toes = tip;
        notes.push(note);
        legs.push(leg);
    }
    Ok(Imported {
        geometry: Gait2392Geometry {
            right: legs[0],
            left: legs[1],
        },
        notes,
    })
}

/// Parses an OpenSim model `text` (named `source` in messages): the document and its
/// `<OpenSimDocument Version=...>`.
pub fn document<'a>(text: &'a str, source: &str) -> Result<(Document<'a>, u32), ImportError> {
    let doc = parse_xml(text, source)?;
    let version: u32 = doc
        .descendants()
        .find(|n| n.has_tag_name("OpenSimDocument"))
        .and_then(|n| n.attribute("Version"))
        .and_then(|v| v.trim().parse().ok())
        .ok_or_else(|| ImportError::NotOpenSim(source.to_string()))?;
    Ok((doc, version))
}

/// A transform function, with any `MultiplierFunction` scale applied.
#[derive(Debug, Clone, PartialEq)]
pub enum Function {
    /// `Constant`: the value.
    Constant(f64),
    /// `slope * q + intercept`.
    Linear(f64, f64),
    /// `SimmSpline` knots (x, y).
    SimmSpline(Vec<f64>, Vec<f64>),
    /// `PiecewiseLinearFunction` knots.
    PiecewiseLinear(Vec<f64>, Vec<f64>),
    /// `PolynomialFunction` coefficients, highest power first.
    Polynomial(Vec<f64>),
    /// A type qgait does not evaluate (its XML tag).
    Other(String),
}

/// One axis of a `CustomJoint`'s `SpatialTransform` (or a joint type's axis as one).
#[derive(Debug, Clone)]
pub struct TransformAxis {
    /// `rotation1`..`rotation3`, `translation1`..`translation3`.
    pub name: String,
    /// The coordinates driving it.
    pub coordinates: Vec<String>,
    /// The axis, in the parent offset frame.
    pub axis: [f64; 3],
    /// Its function of the coordinate.
    pub function: Function,
}

/// A joint of a model, in either file format (3.x or 4.x), its frames resolved to bodies.
#[derive(Debug, Clone)]
pub struct Joint {
    /// The joint's name.
    pub name: String,
    /// Its XML tag (`CustomJoint`, `PinJoint`, ...).
    pub kind: String,
    /// The parent body.
    pub parent: String,
    /// The child body.
    pub child: String,
    /// The parent offset frame's translation in the parent body (metres).
    pub location_in_parent: [f64; 3],
    /// The parent offset frame's orientation (body-fixed x-y-z angles, radians).
    pub orientation_in_parent: [f64; 3],
    /// The child offset frame's translation in the child body (metres).
    pub location_in_child: [f64; 3],
    /// The child offset frame's orientation (body-fixed x-y-z angles, radians).
    pub orientation_in_child: [f64; 3],
    /// OpenSim's `reverse` flag.
    pub reverse: bool,
    /// Its transform axes, in order.
    pub axes: Vec<TransformAxis>,
    /// The joint's own coordinates, in order (what a `PinJoint` or `UniversalJoint` turns by).
    pub coordinates: Vec<String>,
    /// Where its element starts (line and column; the file is named by
    /// [`ImportError::in_file`]).
    pub at: Location,
}

/// The first child element of `n` with tag `tag`.
pub fn child<'a, 'i>(n: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    n.children().find(|c| c.is_element() && c.has_tag_name(tag))
}

/// The trimmed text of `n`'s child element `tag`.
pub fn text_of<'a>(n: Node<'a, '_>, tag: &str) -> Option<&'a str> {
    child(n, tag).map(|c| c.text().unwrap_or("").trim())
}

/// The whitespace-separated numbers of `s`, the text of element `n`; `what` names them in the
/// error.
pub fn numbers(n: Node, s: &str, what: &str) -> Result<Vec<f64>, ImportError> {
    s.split_whitespace()
        .map(|v| {
            v.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| ImportError::BadNumber {
                    at: location_of(n),
                    what: what.to_string(),
                    text: v.to_string(),
                })
        })
        .collect()
}

/// The three numbers of `n`'s child element `tag`; `what` names them in the error.
pub fn vec3(n: Node, tag: &str, what: &str) -> Result<[f64; 3], ImportError> {
    match child(n, tag) {
        None => Ok([0.0; 3]),
        Some(c) => {
            let t = c.text().unwrap_or("").trim();
            let what = format!("{what} <{tag}>");
            let v = numbers(c, t, &what)?;
            <[f64; 3]>::try_from(v.as_slice()).map_err(|_| ImportError::NumberCount {
                at: location_of(c),
                what,
                expected: 3,
                text: t.to_string(),
            })
        }
    }
}

/// The `name` attribute of `n` (empty when absent).
pub fn name_of(n: Node) -> String {
    n.attribute("name").unwrap_or("").to_string()
}

/// Parses a function element (`<Constant>`, `<LinearFunction>`, ...).
pub fn function(n: Node, what: &str) -> Result<Function, ImportError> {
    let tag = n.tag_name().name();
    Ok(match tag {
        "Constant" => Function::Constant(
            numbers(n, text_of(n, "value").unwrap_or("0"), what)?
                .first()
                .copied()
                .unwrap_or(0.0),
        ),
        "LinearFunction" => {
            let c = numbers(n, text_of(n, "coefficients").unwrap_or(""), what)?;
            match c.as_slice() {
                [a, b] => Function::Linear(*a, *b),
                _ => {
                    return Err(ImportError::chain(
                        location_of(n),
                        format!("{what}: LinearFunction needs 2 coefficients"),
                    ))
                }
            }
        }
        "SimmSpline" => Function::SimmSpline(
            numbers(n, text_of(n, "x").unwrap_or(""), what)?,
            numbers(n, text_of(n, "y").unwrap_or(""), what)?,
        ),
        "PiecewiseLinearFunction" => Function::PiecewiseLinear(
            numbers(n, text_of(n, "x").unwrap_or(""), what)?,
            numbers(n, text_of(n, "y").unwrap_or(""), what)?,
        ),
        "PolynomialFunction" => {
            Function::Polynomial(numbers(n, text_of(n, "coefficients").unwrap_or(""), what)?)
        }
        "MultiplierFunction" => {
            let inner = child(n, "function")
                .and_then(|f| f.children().find(|c| c.is_element()))
                .ok_or_else(|| {
                    ImportError::chain(
                        location_of(n),
                        format!("{what}: MultiplierFunction without a function"),
                    )
                })?;
            let scale = numbers(n, text_of(n, "scale").unwrap_or("1"), what)?
                .first()
                .copied()
                .unwrap_or(1.0);
            match function(inner, what)? {
                Function::Constant(c) => Function::Constant(c * scale),
                Function::Linear(a, b) => Function::Linear(a * scale, b * scale),
                Function::SimmSpline(x, y) => {
                    Function::SimmSpline(x, y.into_iter().map(|v| v * scale).collect())
                }
                Function::PiecewiseLinear(x, y) => {
                    Function::PiecewiseLinear(x, y.into_iter().map(|v| v * scale).collect())
                }
                Function::Polynomial(c) => {
                    Function::Polynomial(c.into_iter().map(|v| v * scale).collect())
                }
                Function::Other(t) => Function::Other(format!("MultiplierFunction({t})")),
            }
        }
        other => Function::Other(other.to_string()),
    })
}

fn transform_axes(joint: Node, joint_name: &str) -> Result<Vec<TransformAxis>, ImportError> {
    let Some(st) = child(joint, "SpatialTransform") else {
        return Ok(Vec::new());
    };
    let mut axes = Vec::new();
    for ta in st.children().filter(|c| c.has_tag_name("TransformAxis")) {
        let name = name_of(ta);
        let what = format!("joint `{joint_name}` {name}");
        let coordinates: Vec<String> = text_of(ta, "coordinates")
            .unwrap_or("")
            .split_whitespace()
            .map(String::from)
            .collect();
        let axis = vec3(ta, "axis", &what)?;
        let f_node = ta.children().filter(|c| c.is_element()).find_map(|c| {
            if c.has_tag_name("function") {
                c.children().find(|f| f.is_element())
            } else if c.attribute("name") == Some("function") {
                Some(c)
            } else {
                None
            }
        });
        let function = match f_node {
            Some(f) => function(f, &what)?,
            None if coordinates.is_empty() => Function::Constant(0.0),
            None => {
                return Err(ImportError::chain(
                    location_of(ta),
                    format!("{what}: no function"),
                ))
            }
        };
        axes.push(TransformAxis {
            name,
            coordinates,
            axis,
            function,
        });
    }
    Ok(axes)
}

/// The last part of a component path (`../femur_r` → `femur_r`).
pub fn last_path_part(p: &str) -> &str {
    p.trim()
        .trim_end_matches('/')
        .rsplit('/')
        .next()
        .unwrap_or("")
}

/// 4.x: a joint's frame socket → (body, translation, orientation).
fn resolve_frame(
    joint: Node,
    socket: &str,
    joint_name: &str,
) -> Result<(String, [f64; 3], [f64; 3]), ImportError> {
    let target = text_of(joint, socket).ok_or_else(|| {
        ImportError::chain(
            location_of(joint),
            format!("joint `{joint_name}`: no <{socket}>"),
        )
    })?;
    let frame_name = last_path_part(target);
    let offset = child(joint, "frames").and_then(|f| {
        f.children()
            .find(|c| c.is_element() && c.attribute("name") == Some(frame_name))
    });
    match offset {
        Some(frame) => {
            if !frame.has_tag_name("PhysicalOffsetFrame") {
                return Err(ImportError::chain(
                    location_of(frame),
                    format!(
                        "joint `{joint_name}`: frame `{frame_name}` is a {} (only PhysicalOffsetFrame is supported)",
                        frame.tag_name().name()
                    ),
                ));
            }
            let parent = text_of(frame, "socket_parent").unwrap_or("");
            if !(parent.starts_with("/bodyset/") || parent == "/ground") {
                return Err(ImportError::chain(
                    location_of(frame),
                    format!(
                        "joint `{joint_name}`: frame `{frame_name}` hangs on `{parent}` (only a body or ground is supported)"
                    ),
                ));
            }
            let what = format!("joint `{joint_name}` frame `{frame_name}`");
            Ok((
                last_path_part(parent).to_string(),
                vec3(frame, "translation", &what)?,
                vec3(frame, "orientation", &what)?,
            ))
        }
        None => Ok((frame_name.to_string(), [0.0; 3], [0.0; 3])),
    }
}

/// Every joint of the model, in file order, its offset frames resolved to bodies.
pub fn read_joints(doc: &Document) -> Result<Vec<Joint>, ImportError> {
    let mut joints = Vec::new();
    // 4.x: <JointSet><objects>...
    for set in doc.descendants().filter(|n| n.has_tag_name("JointSet")) {
        for j in child(set, "objects")
            .into_iter()
            .flat_map(|o| o.children().filter(|c| c.is_element()))
        {
            let name = name_of(j);
            let (parent, lp, op) = resolve_frame(j, "socket_parent_frame", &name)?;
            let (child_body, lc, oc) = resolve_frame(j, "socket_child_frame", &name)?;
            joints.push(Joint {
                kind: j.tag_name().name().to_string(),
                parent,
                child: child_body,
                location_in_parent: lp,
                orientation_in_parent: op,
                location_in_child: lc,
                orientation_in_child: oc,
                reverse: text_of(j, "reverse") == Some("true"),
                axes: transform_axes(j, &name)?,
                coordinates: joint_coordinates(j),
                name,
                at: location_of(j),
            });
        }
    }
    // 3.x: <Body name=...><Joint><CustomJoint ...>
    for body in doc.descendants().filter(|n| n.has_tag_name("Body")) {
        let Some(j) = child(body, "Joint").and_then(|j| j.children().find(|c| c.is_element()))
        else {
            continue;
        };
        let name = name_of(j);
        let what = format!("joint `{name}`");
        joints.push(Joint {
            kind: j.tag_name().name().to_string(),
            parent: text_of(j, "parent_body").unwrap_or("").to_string(),
            child: name_of(body),
            location_in_parent: vec3(j, "location_in_parent", &what)?,
            orientation_in_parent: vec3(j, "orientation_in_parent", &what)?,
            location_in_child: vec3(j, "location", &what)?,
            orientation_in_child: vec3(j, "orientation", &what)?,
            reverse: text_of(j, "reverse") == Some("true"),
            axes: transform_axes(j, &name)?,
            coordinates: joint_coordinates(j),
            name,
            at: location_of(j),
        });
    }
    for j in &joints {
        for ax in &j.axes {
            if let Some(c) = ax.coordinates.iter().find(|c| !j.coordinates.contains(c)) {
                return Err(ImportError::chain(j.at.clone(), format!(
                    "joint `{}` {} turns by coordinate `{c}`, which the joint does not declare (its coordinates: {}); OpenSim refuses such a model",
                    j.name,
                    ax.name,
                    if j.coordinates.is_empty() {
                        "none".to_string()
                    } else {
                        j.coordinates.join(", ")
                    }
                )));
            }
        }
    }
    Ok(joints)
}

/// The names of a joint's own coordinates (4.x `<coordinates>`, 3.x `<CoordinateSet>`).
fn joint_coordinates(j: Node) -> Vec<String> {
    j.children()
        .filter(|c| c.has_tag_name("coordinates") || c.has_tag_name("CoordinateSet"))
        .flat_map(|c| c.descendants().filter(|d| d.has_tag_name("Coordinate")))
        .map(name_of)
        .collect()
}

/// The one joint moving `body`, checked to hang on `parent` (the chain's next link).
pub fn joint_moving<'a>(
    joints: &'a [Joint],
    parent: &str,
    body: &str,
) -> Result<&'a Joint, ImportError> {
    let found: Vec<&Joint> = joints.iter().filter(|j| j.child == body).collect();
    let j = match found.as_slice() {
        [j] => *j,
        [] => {
            return Err(ImportError::chain(whole(), format!(
                "no joint moves body `{body}` (a leg chain is ground-pelvis-femur-tibia-talus-calcn-toes)"
            )))
        }
        _ => return Err(ImportError::chain(whole(), format!("several joints move body `{body}`"))),
    };
    if j.parent != parent {
        return Err(ImportError::chain(
            j.at.clone(),
            format!(
                "joint `{}` connects `{}` to `{body}`; the leg chain needs `{parent}`",
                j.name, j.parent
            ),
        ));
    }
    Ok(j)
}

/// The joint moving `child`, checked to hang on `parent` and to be a plain `CustomJoint`.
fn chain_joint<'a>(
    joints: &'a [Joint],
    parent: &str,
    child: &str,
) -> Result<&'a Joint, ImportError> {
    let j = joint_moving(joints, parent, child)?;
    let name = &j.name;
    if j.kind != "CustomJoint" {
        return Err(ImportError::chain(
            j.at.clone(),
            format!(
                "joint `{name}` is a {} (only CustomJoint is supported)",
                j.kind
            ),
        ));
    }
    for (what, v) in [
        (
            "orientation_in_parent (parent frame orientation)",
            j.orientation_in_parent,
        ),
        (
            "location in the child (child frame translation)",
            j.location_in_child,
        ),
        (
            "orientation in the child (child frame orientation)",
            j.orientation_in_child,
        ),
    ] {
        if v != [0.0; 3] {
            return Err(ImportError::chain(
                j.at.clone(),
                format!("joint `{name}`: non-zero {what} {v:?} is not supported"),
            ));
        }
    }
    if j.reverse {
        return Err(ImportError::chain(
            j.at.clone(),
            format!("joint `{name}`: reverse=true is not supported"),
        ));
    }
    Ok(j)
}

/// The rotations that move (Constant 0 ones dropped): (axis, coordinate), checked against the
/// expected coordinates in order.
fn rotations(j: &Joint, expected: &[String]) -> Result<Vec<[f64; 3]>, ImportError> {
    let mut out = Vec::new();
    let mut coords = Vec::new();
    for ax in j.axes.iter().filter(|a| a.name.starts_with("rotation")) {
        let what = format!("joint `{}` {}", j.name, ax.name);
        match &ax.function {
            Function::Constant(c) if *c == 0.0 => {}
            Function::Constant(c) => {
                return Err(ImportError::chain(j.at.clone(), format!(
                    "{what}: a constant rotation of {c} rad is not supported"
                )))
            }
            Function::Linear(a, b) if *a == 1.0 && *b == 0.0 && ax.coordinates.len() == 1 => {
                out.push(ax.axis);
                coords.push(ax.coordinates[0].clone());
            }
            Function::Linear(a, b) => {
                return Err(ImportError::chain(j.at.clone(), format!(
                    "{what}: LinearFunction {a} {b} of {:?} is not supported on a rotation (only the identity 1 0 of one coordinate)",
                    ax.coordinates
                )))
            }
            Function::SimmSpline(..) | Function::PiecewiseLinear(..) => {
                return Err(ImportError::chain(j.at.clone(), format!("{what}: a spline rotation is not supported")))
            }
            Function::Polynomial(..) => {
                return Err(ImportError::chain(j.at.clone(), format!("{what}: a polynomial rotation is not supported")))
            }
            Function::Other(t) => {
                return Err(ImportError::chain(j.at.clone(), format!("{what}: function type {t} is not supported")))
            }
        }
    }
    if coords != expected {
        return Err(ImportError::chain(
            j.at.clone(),
            format!(
                "joint `{}` rotates by coordinates [{}]; gait2392's chain needs [{}] in that order",
                j.name,
                coords.join(", "),
                expected.join(", ")
            ),
        ));
    }
    Ok(out)
}

fn no_translation(j: &Joint) -> Result<(), ImportError> {
    for ax in j.axes.iter().filter(|a| a.name.starts_with("translation")) {
        if ax.function != Function::Constant(0.0) {
            return Err(ImportError::chain(j.at.clone(), format!(
                "joint `{}` {}: a translation ({:?}) is not supported here (only the knee translates)",
                j.name, ax.name, ax.function
            )));
        }
    }
    Ok(())
}

fn same_axis(a: [f64; 3], b: [f64; 3]) -> bool {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    n > 0.0 && (0..3).all(|i| (a[i] / n - b[i]).abs() < 1e-12)
}

fn check_pelvis(j: &Joint) -> Result<(), ImportError> {
    let names = ["pelvis_tilt", "pelvis_list", "pelvis_rotation"].map(String::from);
    let axes = rotations(j, &names)?;
    for (a, e) in axes
        .iter()
        .zip([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    {
        if !same_axis(*a, e) {
            return Err(ImportError::chain(
                j.at.clone(),
                format!(
                    "joint `{}`: pelvis axes {axes:?} are not gait2392's z, x, y",
                    j.name
                ),
            ));
        }
    }
    // Pelvis translations are not an input (origin at the pelvis origin): any function is fine.
    Ok(())
}

fn knee_knots(j: &Joint, coordinate: &str) -> Result<(Knots, Knots), ImportError> {
    let mut tx: Option<(Vec<f64>, Vec<f64>)> = None;
    let mut ty: Option<(Vec<f64>, Vec<f64>)> = None;
    for ax in j.axes.iter().filter(|a| a.name.starts_with("translation")) {
        let what = format!("joint `{}` {}", j.name, ax.name);
        if ax.function == Function::Constant(0.0) {
            continue;
        }
        if !matches!(ax.function, Function::Constant(_)) && ax.coordinates != [coordinate] {
            return Err(ImportError::chain(
                j.at.clone(),
                format!(
                    "{what}: a function of {:?}; gait2392's knee translates with {coordinate} only",
                    ax.coordinates
                ),
            ));
        }
        let knots = match &ax.function {
            Function::SimmSpline(x, y) => {
                if x.len() != y.len() || x.len() < 2 || x.len() > qgait_kernel::spline::MAX_KNOTS {
                    return Err(ImportError::chain(j.at.clone(), format!(
                        "{what}: SimmSpline with {} x and {} y knots (qgait supports 2 to {})",
                        x.len(),
                        y.len(),
                        qgait_kernel::spline::MAX_KNOTS
                    )));
                }
                (x.clone(), y.clone())
            }
            // A line is the 2-knot spline through two of its points (linear extrapolation).
            Function::Linear(a, b) => (vec![-1.0, 1.0], vec![b - a, b + a]),
            Function::Constant(c) => (vec![-1.0, 1.0], vec![*c, *c]),
            Function::PiecewiseLinear(..) => {
                return Err(ImportError::chain(j.at.clone(), format!(
                    "{what}: PiecewiseLinearFunction is not supported on gait2392's knee"
                )))
            }
            Function::Polynomial(..) => {
                return Err(ImportError::chain(j.at.clone(), format!(
                    "{what}: PolynomialFunction is not supported on gait2392's knee"
                )))
            }
            Function::Other(t) => {
                return Err(ImportError::chain(j.at.clone(), format!(
                    "{what}: function type {t} is not supported (the knee needs SimmSpline, LinearFunction or Constant)"
                )))
            }
        };
        let slot = if same_axis(ax.axis, [1.0, 0.0, 0.0]) {
            &mut tx
        } else if same_axis(ax.axis, [0.0, 1.0, 0.0]) {
            &mut ty
        } else {
            return Err(ImportError::chain(
                j.at.clone(),
                format!(
                    "{what}: translation along {:?} is not supported (only the femur's x and y)",
                    ax.axis
                ),
            ));
        };
        if slot.is_some() {
            return Err(ImportError::chain(
                j.at.clone(),
                format!("{what}: two translations along the same axis"),
            ));
        }
        *slot = Some(knots);
    }
    let l = j.location_in_parent;
    if l[2] != 0.0 {
        return Err(ImportError::chain(
            j.at.clone(),
            format!(
                "joint `{}`: a knee offset along z ({}) is not supported",
                j.name, l[2]
            ),
        ));
    }
    // The knee's parent offset adds to its translations (both are in the femur frame).
    let with_offset = |k: Option<(Vec<f64>, Vec<f64>)>, d: f64| {
        let (x, y) = k.unwrap_or((vec![-1.0, 1.0], vec![0.0, 0.0]));
        let y: Vec<f64> = if d == 0.0 {
            y
        } else {
            y.iter().map(|v| v + d).collect()
        };
        Knots::new(&x, &y)
    };
    Ok((with_offset(tx, l[0]), with_offset(ty, l[1])))
}

fn read_leg(joints: &[Joint], s: &str) -> Result<LegGeometry, ImportError> {
    let names = |c: &[&str]| -> Vec<String> { c.iter().map(|n| format!("{n}_{s}")).collect() };
    let hip = chain_joint(joints, "pelvis", &format!("femur_{s}"))?;
    let knee = chain_joint(joints, &format!("femur_{s}"), &format!("tibia_{s}"))?;
    let ankle = chain_joint(joints, &format!("tibia_{s}"), &format!("talus_{s}"))?;
    let subtalar = chain_joint(joints, &format!("talus_{s}"), &format!("calcn_{s}"))?;
    let mtp = chain_joint(joints, &format!("calcn_{s}"), &format!("toes_{s}"))?;
    let hip_axes = rotations(
        hip,
        &names(&["hip_flexion", "hip_adduction", "hip_rotation"]),
    )?;
    no_translation(hip)?;
    let knee_axis = rotations(knee, &names(&["knee_angle"]))?;
    if !same_axis(knee_axis[0], [0.0, 0.0, 1.0]) {
        return Err(ImportError::chain(
            knee.at.clone(),
            format!(
                "joint `{}`: knee axis {:?} is not gait2392's z",
                knee.name, knee_axis[0]
            ),
        ));
    }
    let (knee_tx, knee_ty) = knee_knots(knee, &format!("knee_angle_{s}"))?;
    let one_axis = |j: &Joint, coordinate: &str| -> Result<[f64; 3], ImportError> {
        no_translation(j)?;
        Ok(rotations(j, &names(&[coordinate]))?[0])
    };
    debug_assert!(COORDINATES.contains(&format!("mtp_angle_{s}").as_str()));
    Ok(LegGeometry {
        hip_in_pelvis: hip.location_in_parent,
        hip_axes: [hip_axes[0], hip_axes[1], hip_axes[2]],
        knee_tx,
        knee_ty,
        ankle_in_tibia: ankle.location_in_parent,
        ankle_axis: one_axis(ankle, "ankle_angle")?,
        subtalar_in_talus: subtalar.location_in_parent,
        subtalar_axis: one_axis(subtalar, "subtalar_angle")?,
        mtp_in_calcn: mtp.location_in_parent,
        mtp_axis: one_axis(mtp, "mtp_angle")?,
        toetip_in_toes: [0.0; 3],
    })
}

/// Constraints that touch the chain (its coordinates or bodies) are refused.
fn check_constraints(doc: &Document) -> Result<(), ImportError> {
    let mut chain: Vec<String> = COORDINATES.iter().map(|c| c.to_string()).collect();
    for s in ["r", "l"] {
        for b in ["femur", "tibia", "talus", "calcn", "toes"] {
            chain.push(format!("{b}_{s}"));
        }
    }
    chain.push("pelvis".into());
    match constraint_naming(doc, &chain, None) {
        Some((c, hit)) => Err(ImportError::chain(
            location_of(c),
            format!(
                "{} `{}` constrains `{hit}` of the leg chain; constraints are not supported",
                c.tag_name().name(),
                name_of(c)
            ),
        )),
        None => Ok(()),
    }
}

/// Whether a constraint is on (not `isDisabled`, not `isEnforced` false).
pub fn enforced(c: Node) -> bool {
    !(text_of(c, "isDisabled") == Some("true") || text_of(c, "isEnforced") == Some("false"))
}

/// The first enforced constraint (other than those tagged `skip`) whose text names one of
/// `names` (a coordinate or body), and that name.
pub fn constraint_naming<'a, 'i>(
    doc: &'a Document<'i>,
    names: &[String],
    skip: Option<&str>,
) -> Option<(Node<'a, 'i>, String)> {
    for set in doc
        .descendants()
        .filter(|n| n.has_tag_name("ConstraintSet"))
    {
        for c in child(set, "objects")
            .into_iter()
            .flat_map(|o| o.children().filter(|c| c.is_element()))
            .filter(|c| enforced(*c) && skip.is_none_or(|t| !c.has_tag_name(t)))
        {
            let words: Vec<&str> = c
                .descendants()
                .filter_map(|d| d.text())
                .flat_map(|t| t.split(|ch: char| ch.is_whitespace() || ch == '/'))
                .collect();
            if let Some(hit) = names.iter().find(|n| words.contains(&n.as_str())) {
                return Some((c, hit.clone()));
            }
        }
    }
    None
}

/// A model coordinate: default value, whether it is locked, and its range if clamped.
pub struct Coordinate {
    /// The coordinate's name.
    pub name: String,
    /// `default_value`.
    pub default: f64,
    /// `locked`.
    pub locked: bool,
    /// `range`, if `clamped` is true.
    pub clamped: Option<(f64, f64)>,
}

/// The model's coordinates (4.x and 3.x alike: every named `Coordinate`).
pub fn read_coordinates(doc: &Document) -> Vec<Coordinate> {
    doc.descendants()
        .filter(|n| n.has_tag_name("Coordinate") && n.attribute("name").is_some())
        .map(|c| Coordinate {
            name: name_of(c),
            default: text_of(c, "default_value")
                .and_then(|v| v.parse().ok())
                .unwrap_or(0.0),
            locked: text_of(c, "locked") == Some("true"),
            clamped: (text_of(c, "clamped") == Some("true"))
                .then(|| {
                    let r: Vec<f64> = text_of(c, "range")?
                        .split_whitespace()
                        .filter_map(|v| v.parse().ok())
                        .collect();
                    (r.len() == 2 && r[0] <= r[1]).then(|| (r[0], r[1]))
                })
                .flatten(),
        })
        .collect()
}

/// The first of the 17 chain coordinates the model locks or clamps, and which.
fn held_coordinate(doc: &Document) -> Option<(String, &'static str)> {
    read_coordinates(doc)
        .into_iter()
        .filter(|c| COORDINATES.contains(&c.name.as_str()))
        .find_map(|c| match (c.locked, c.clamped) {
            (true, _) => Some((c.name, "locked")),
            (false, Some(_)) => Some((c.name, "clamped")),
            (false, None) => None,
        })
}

/// Notes for chain coordinates whose `default_value` is not 0: OpenSim uses the default for a
/// coordinate a motion lacks, qgait uses 0.
fn non_zero_defaults(doc: &Document) -> Vec<String> {
    doc.descendants()
        .filter(|n| n.has_tag_name("Coordinate"))
        .filter_map(|c| {
            let name = c.attribute("name")?;
            let v: f64 = text_of(c, "default_value")?.parse().ok()?;
            (COORDINATES.contains(&name) && v != 0.0).then(|| {
                format!(
                    "coordinate {name} has default_value {v} in the model; qgait takes a coordinate absent from a motion as 0"
                )
            })
        })
        .collect()
}

/// A marker `name` in a document: (body, location).
pub fn marker(doc: &Document, name: &str) -> Result<Option<(String, [f64; 3])>, ImportError> {
    let Some(m) = doc
        .descendants()
        .find(|n| n.has_tag_name("Marker") && n.attribute("name") == Some(name))
    else {
        return Ok(None);
    };
    let body = text_of(m, "socket_parent_frame")
        .or_else(|| text_of(m, "body"))
        .map(last_path_part)
        .unwrap_or("")
        .to_string();
    Ok(Some((
        body,
        vec3(m, "location", &format!("marker `{name}`"))?,
    )))
}

/// The toes body's geometry scale factors (1 when absent).
fn toes_scale(doc: &Document, s: &str) -> [f64; 3] {
    let Some(body) = doc
        .descendants()
        .find(|n| n.has_tag_name("Body") && n.attribute("name") == Some(&format!("toes_{s}")))
    else {
        return [1.0; 3];
    };
    let scale = child(body, "VisibleObject")
        .and_then(|v| child(v, "scale_factors"))
        .or_else(|| {
            child(body, "attached_geometry")
                .and_then(|g| g.children().find(|c| c.is_element()))
                .and_then(|m| child(m, "scale_factors"))
        })
        .and_then(|n| numbers(n, n.text()?, "").ok())
        .and_then(|v| <[f64; 3]>::try_from(v.as_slice()).ok());
    scale.unwrap_or([1.0; 3])
}

/// A marker found: `(body, location)` and the file it came from.
pub type FoundMarker<'f> = Option<((String, [f64; 3]), &'f str)>;

/// Marker `R.Toe.Tip`/`L.Toe.Tip` of side `s`: from the marker file if given, else from the
/// model (`source`): its name, `(body, location)` and the file it came from.
pub fn toe_marker<'f>(
    model: &Document,
    source: &'f str,
    markers: Option<&(Document, &'f str)>,
    s: &str,
) -> Result<(&'static str, FoundMarker<'f>), ImportError> {
    let name = if s == "r" { "R.Toe.Tip" } else { "L.Toe.Tip" };
    let found = match markers {
        Some((doc, file)) => marker(doc, name)
            .map_err(|e| e.in_file(file))?
            .map(|m| (m, *file)),
        None => None,
    };
    let found = match found {
        Some(f) => Some(f),
        None => marker(model, name)
            .map_err(|e| e.in_file(source))?
            .map(|m| (m, source)),
    };
    Ok((name, found))
}

/// gait2392's toe tip in `toes_<s>` times the toes' geometry scale factors, and the note saying so.
pub fn generic_toe_tip(model: &Document, s: &str, name: &str) -> ([f64; 3], String) {
    let k = toes_scale(model, s);
    let g = GENERIC_TOETIP_RIGHT;
    let z = if s == "r" { g[2] } else { -g[2] };
    (
        [g[0] * k[0], g[1] * k[1], z * k[2]],
        format!(
            "toe tip {s}: no {name} marker; generic ({}, {}, {z}) in toes_{s} times the toes' geometry scale factors {k:?}",
            g[0], g[1]
        ),
    )
}

fn toe_tip(
    model: &Document,
    source: &str,
    markers: Option<&(Document, &str)>,
    s: &str,
    leg: &LegGeometry,
) -> Result<([f64; 3], String), ImportError> {
    let (name, found) = toe_marker(model, source, markers, s)?;
    if let Some(((body, loc), file)) = found {
        let tip = if body == format!("toes_{s}") {
            loc
        } else if body == format!("calcn_{s}") {
            // The MTP joint has no orientation offset (checked), so toes = calcn - MTP centre.
            [0, 1, 2].map(|i| loc[i] - leg.mtp_in_calcn[i])
        } else {
            return Err(ImportError::chain(
                Location::file(file),
                format!(
                    "marker `{name}` is on `{body}`; the toe tip must be on calcn_{s} or toes_{s}"
                ),
            ));
        };
        return Ok((
            tip,
            format!("toe tip {s}: marker {name} from {file} on {body} at {loc:?}"),
        ));
    }
    Ok(generic_toe_tip(model, s, name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_cut_off_is_named_where_it_ends() {
        let text = "<?xml version=\"1.0\"?>\n<OpenSimDocument Version=\"40000\">\n\t<Model name=\"m\">\n\t\t<Body";
        let e = parse_xml(text, "m.osim").err().unwrap().to_string();
        assert!(e.starts_with("m.osim:4:8: not XML: "), "{e}");
        let text =
            "<?xml version=\"1.0\"?>\n<OpenSimDocument Version=\"40000\">\n\t<Model name=\"m\">\n";
        let e = parse_xml(text, "m.osim").err().unwrap().to_string();
        assert!(
            e.starts_with("m.osim:4:1: not XML: ") && e.ends_with("the file ends here"),
            "{e}"
        );
    }

    #[test]
    fn functions_with_multipliers_scale_their_values() {
        let xml = r#"<MultiplierFunction name="function"><function><SimmSpline><x>0 1</x><y>1 2</y></SimmSpline></function><scale>1.5</scale></MultiplierFunction>"#;
        let doc = Document::parse(xml).unwrap();
        assert_eq!(
            function(doc.root_element(), "t").unwrap(),
            Function::SimmSpline(vec![0.0, 1.0], vec![1.5, 3.0])
        );
        let doc = Document::parse("<NaturalCubicSpline/>").unwrap();
        assert_eq!(
            function(doc.root_element(), "t").unwrap(),
            Function::Other("NaturalCubicSpline".into())
        );
    }
    #[test]
    fn a_refusal_names_the_element_line_and_column() {
        let xml = "<OpenSimDocument Version=\"40000\">\n<JointSet><objects>\n  <PinJoint name=\"hip_r\">\n    <socket_parent_frame>pelvis</socket_parent_frame>\n    <socket_child_frame>femur_r</socket_child_frame>\n    <frames><PhysicalOffsetFrame name=\"femur_r\"><socket_parent>/bodyset/femur_r</socket_parent>\n      <translation>0 1e</translation></PhysicalOffsetFrame></frames>\n  </PinJoint>\n</objects></JointSet></OpenSimDocument>";
        let doc = Document::parse(xml).unwrap();
        let e = read_joints(&doc).unwrap_err().in_file("m.osim");
        assert_eq!(
            e.to_string(),
            "m.osim:7:7: joint `hip_r` frame `femur_r` <translation>: bad number `1e`"
        );
        let two = xml.replace("0 1e", "0 1");
        let doc = Document::parse(&two).unwrap();
        let e = read_joints(&doc).unwrap_err().in_file("m.osim");
        assert_eq!(
            e.to_string(),
            "m.osim:7:7: joint `hip_r` frame `femur_r` <translation>: expected 3 numbers, found `0 1`"
        );
    }
}
