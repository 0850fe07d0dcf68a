//! An imported OpenSim lower-limb chain that is not gait2392's shape (Rajagopal 2015/2016,
//! gait10dof18musc, ...): [`ChainModel`], the numbers of its 11 joints as OpenSim states them,
//! evaluated by the kernel's [`LowerLimb`] table, and its file (`CHAIN.toml`, written by
//! `qgait model import`, read by `--model`).
//!
//! The file is TOML: comment lines (what the import left out and why), then one `[[joints]]`
//! table per body in [`BODIES`] order, each with the OpenSim joint's `name` and `type`, the
//! parent and child offset frames (`parent_translation`, `parent_orientation`,
//! `child_translation`, `child_orientation`: metres, and radians as body-fixed x-y-z angles),
//! and its `[[joints.rotations]]` (body-fixed, in order) and `[[joints.translations]]` (along
//! axes of the parent offset frame), each an `axis`, an optional `coordinate` (one of the 17
//! gait2392 coordinate names, or a coupler's `dependent`) and a `function` (`type` `Constant`
//! with `value`, `Linear` with `slope` and `intercept`, `SimmSpline` or `PiecewiseLinear` with
//! knots `x` and `y`, `Polynomial` with `coefficients`, highest power first); then `[[couplers]]` (`dependent`, `independent`, `function`), one
//! `[[toe_tips]]` per side (right first: `body`, `location` in it) and the `[[ranges]]` the
//! model clamps its input coordinates to (`coordinate`, `min`, `max`; used by `qgait imu`).

use qgait_kernel::models::custom::{
    Argument, BodyPoint, Coupler, CustomJoint, Driven, Function, Functions, Offset,
    MAX_POLYNOMIALS, MAX_SPLINES, MAX_SPLINE_KNOTS,
};
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::models::LowerLimb;
use qgait_kernel::{Polynomial, Spline, Vec3};
use serde::{Deserialize, Serialize};

use crate::error::ModelError;
use crate::toml_path::{Fault, Step, Step::Index, Step::Key};

/// The bodies of the chain, in table order: joint `i` moves body `i`.
pub const BODIES: [&str; 11] = [
    "pelvis", "femur_r", "tibia_r", "talus_r", "calcn_r", "toes_r", "femur_l", "tibia_l",
    "talus_l", "calcn_l", "toes_l",
];

/// A transform function of one argument.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type")]
pub enum FunctionData {
    /// OpenSim `Constant`.
    Constant {
        /// The value.
        value: f64,
    },
    /// OpenSim `LinearFunction`.
    Linear {
        /// Slope.
        slope: f64,
        /// Value at 0.
        intercept: f64,
    },
    /// OpenSim `SimmSpline` (any `MultiplierFunction` scale applied to `y`).
    SimmSpline {
        /// Abscissae.
        x: Vec<f64>,
        /// Values.
        y: Vec<f64>,
    },
    /// OpenSim `PiecewiseLinearFunction`.
    PiecewiseLinear {
        /// Abscissae.
        x: Vec<f64>,
        /// Values.
        y: Vec<f64>,
    },
    /// OpenSim `PolynomialFunction` (any `MultiplierFunction` scale applied to the
    /// coefficients).
    Polynomial {
        /// Coefficients, highest power first.
        coefficients: Vec<f64>,
    },
}

impl FunctionData {
    /// The kernel's spline of a spline function.
    fn spline(&self) -> Option<Result<Spline<f64, MAX_SPLINE_KNOTS>, qgait_kernel::ModelError>> {
        match self {
            Self::SimmSpline { x, y } => Some(Spline::from_knots(x, y)),
            Self::PiecewiseLinear { x, y } => Some(Spline::piecewise_linear(x, y)),
            _ => None,
        }
    }

    /// The value at `v` (what a coordinate held at `v` contributes), evaluated by the kernel.
    pub fn at(&self, v: f64) -> Result<f64, qgait_kernel::ModelError> {
        Ok(match self {
            Self::Constant { value } => *value,
            Self::Linear { slope, intercept } => {
                let chain = Function::Linear {
                    slope: *slope,
                    intercept: *intercept,
                };
                return Ok(eval_one(chain, None, v));
            }
            Self::Polynomial { coefficients } => Polynomial::new(coefficients)?.eval(v),
            Self::SimmSpline { .. } | Self::PiecewiseLinear { .. } => {
                let s = self.spline().expect("a spline")?;
                return Ok(eval_one(Function::Spline(0), Some(s), v));
            }
        })
    }
}

/// `f(v)` by the kernel: a one-body chain translating by `f` of its one coordinate.
fn eval_one(f: Function<f64>, spline: Option<Spline<f64, MAX_SPLINE_KNOTS>>, v: f64) -> f64 {
    let mut joint = CustomJoint::WELD;
    joint.translations[0] = Driven {
        axis: Vec3::unit_x(),
        function: f,
        argument: Argument::Coordinate(0),
    };
    let splines: Vec<_> = spline.into_iter().collect();
    let point = BodyPoint {
        body: 0,
        offset: Vec3::zero(),
    };
    let functions = Functions::splines(&splines);
    qgait_kernel::models::CustomChain::<f64, 1, 1, 1>::new([joint], [point], functions, &[])
        .map(|c| c.forward(&[v])[0].x)
        .unwrap_or(f64::NAN)
}

/// One transform axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxisData {
    /// Direction.
    pub axis: [f64; 3],
    /// The coordinate the function takes (none: evaluated at 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coordinate: Option<String>,
    /// The function.
    pub function: FunctionData,
}

/// The joint that moves one body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointData {
    /// The OpenSim joint's name.
    pub name: String,
    /// Its OpenSim type (`CustomJoint`, `PinJoint`, ...).
    #[serde(rename = "type")]
    pub kind: String,
    /// The body it moves.
    pub body: String,
    /// Parent offset frame origin in the parent body.
    pub parent_translation: [f64; 3],
    /// Parent offset frame orientation (body-fixed x-y-z, radians).
    pub parent_orientation: [f64; 3],
    /// Child offset frame origin in the moved body: the joint centre.
    pub child_translation: [f64; 3],
    /// Child offset frame orientation.
    pub child_orientation: [f64; 3],
    /// Rotations, body-fixed, in order.
    #[serde(default)]
    pub rotations: Vec<AxisData>,
    /// Translations along axes of the parent offset frame.
    #[serde(default)]
    pub translations: Vec<AxisData>,
}

/// A coupled coordinate: `dependent = function(independent)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CouplerData {
    /// The coupled coordinate's name.
    pub dependent: String,
    /// The input coordinate it follows.
    pub independent: String,
    /// The coupling function.
    pub function: FunctionData,
}

/// A point fixed in a body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointData {
    /// One of [`BODIES`].
    pub body: String,
    /// Position in the body (metres).
    pub location: [f64; 3],
}

/// The range an input coordinate is clamped to in the model (OpenSim's `range` with
/// `clamped` true): what an inverse kinematics solve (`qgait imu`) keeps it within, as
/// OpenSim's does. FK does not clamp.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RangeData {
    /// One of the 17 gait2392 coordinate names.
    pub coordinate: String,
    /// Lower bound (radians, or metres for a translation).
    pub min: f64,
    /// Upper bound.
    pub max: f64,
}

/// An imported lower-limb chain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChainModel {
    /// One joint per body of [`BODIES`], in that order.
    pub joints: Vec<JointData>,
    /// Coupled coordinates the joints use.
    #[serde(default)]
    pub couplers: Vec<CouplerData>,
    /// The toe tips, right then left.
    pub toe_tips: Vec<PointData>,
    /// The clamped ranges of the input coordinates (none: unbounded).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ranges: Vec<RangeData>,
}

impl ChainModel {
    /// The kernel's table: points `hip, knee, ankle, subtalar, mtp` (the child frame origins of
    /// the joints moving femur, tibia, talus, calcn, toes) and `toetip` per side, right first
    /// ([`POINTS`](qgait_kernel::models::gait2392::POINTS) order).
    /// `name` names the model in the error.
    pub fn chain(&self, name: &str) -> Result<LowerLimb<f64>, ModelError> {
        self.build().map_err(|fault| fault.in_model(name))
    }

    /// [`chain`](Self::chain), a refusal saying where in the file the value refused is.
    pub(crate) fn build(&self) -> Result<LowerLimb<f64>, Fault> {
        if self.joints.len() != BODIES.len() || self.toe_tips.len() != 2 {
            return Err(Fault::whole(format!(
                "{} joints and {} toe tips; a lower-limb chain has {} joints ({}) and 2 toe tips",
                self.joints.len(),
                self.toe_tips.len(),
                BODIES.len(),
                BODIES.join(", ")
            )));
        }
        let mut splines = Vec::new();
        let mut polynomials = Vec::new();
        let mut function = |f: &FunctionData, what: &str, at: Vec<Step>| {
            let fault = |message| Fault {
                message,
                at: [at.as_slice(), &[Key("function")]].concat(),
            };
            Ok::<_, Fault>(match f {
                FunctionData::Constant { value } => Function::Constant(*value),
                FunctionData::Linear { slope, intercept } => Function::Linear {
                    slope: *slope,
                    intercept: *intercept,
                },
                FunctionData::Polynomial { coefficients } => {
                    let p = Polynomial::new(coefficients).map_err(|e| {
                        fault(format!("{what}: {e} ({} given)", coefficients.len()))
                    })?;
                    if polynomials.len() == MAX_POLYNOMIALS {
                        return Err(fault(format!(
                            "{what}: more than {MAX_POLYNOMIALS} polynomials in one chain"
                        )));
                    }
                    polynomials.push(p);
                    Function::Polynomial(polynomials.len() - 1)
                }
                FunctionData::SimmSpline { .. } | FunctionData::PiecewiseLinear { .. } => {
                    let s = f.spline().expect("a spline").map_err(|e| {
                        fault(format!(
                            "{what}: {e} (2 to {MAX_SPLINE_KNOTS} increasing knots)"
                        ))
                    })?;
                    if splines.len() == MAX_SPLINES {
                        return Err(fault(format!(
                            "{what}: more than {MAX_SPLINES} splines in one chain"
                        )));
                    }
                    splines.push(s);
                    Function::Spline(splines.len() - 1)
                }
            })
        };
        let input = |name: &str| COORDINATES.iter().position(|c| *c == name);
        let mut couplers = Vec::new();
        for (i, c) in self.couplers.iter().enumerate() {
            let what = format!("coupler of `{}`", c.dependent);
            let at = vec![Key("couplers"), Index(i)];
            let independent = input(&c.independent).ok_or_else(|| Fault {
                message: format!(
                    "{what}: independent coordinate `{}` is not one of {}",
                    c.independent,
                    COORDINATES.join(", ")
                ),
                at: [at.as_slice(), &[Key("independent")]].concat(),
            })?;
            couplers.push(Coupler {
                independent,
                function: function(&c.function, &what, at)?,
            });
        }
        let mut joints = [CustomJoint::WELD; 11];
        for (b, (j, body)) in self.joints.iter().zip(BODIES).enumerate() {
            let joint = [Key("joints"), Index(b)];
            if j.body != body {
                return Err(Fault {
                    message: format!(
                        "joint `{}` moves `{}`; joint {b} must move `{body}`",
                        j.name, j.body
                    ),
                    at: [joint.as_slice(), &[Key("body")]].concat(),
                });
            }
            let mut driven = |axes: &[AxisData], kind: &str, key: &'static str| {
                let at = [joint.as_slice(), &[Key(key)]].concat();
                if axes.len() > 3 {
                    return Err(Fault {
                        message: format!("joint `{}`: more than 3 {kind}", j.name),
                        at: [at.as_slice(), &[Index(3)]].concat(),
                    });
                }
                let mut out = [Driven::NONE; 3];
                for (k, (slot, a)) in out.iter_mut().zip(axes).enumerate() {
                    let what = format!("joint `{}` {kind} {}", j.name, k + 1);
                    let at = [at.as_slice(), &[Index(k)]].concat();
                    let argument = match &a.coordinate {
                        None => Argument::None,
                        Some(n) => {
                            if let Some(k) = self.couplers.iter().position(|c| &c.dependent == n) {
                                Argument::Coupled(k)
                            } else if let Some(i) = input(n) {
                                Argument::Coordinate(i)
                            } else {
                                return Err(Fault {
                                    message: format!(
                                        "{what}: coordinate `{n}` is neither an input ({}) nor coupled",
                                        COORDINATES.join(", ")
                                    ),
                                    at: [at.as_slice(), &[Key("coordinate")]].concat(),
                                });
                            }
                        }
                    };
                    *slot = Driven {
                        axis: Vec3::from_f64(a.axis),
                        function: function(&a.function, &what, at)?,
                        argument,
                    };
                }
                Ok(out)
            };
            let rotations = driven(&j.rotations, "rotation", "rotations")?;
            let translations = driven(&j.translations, "translation", "translations")?;
            joints[b] = CustomJoint {
                parent: match b {
                    0 => None,
                    1 | 6 => Some(0),
                    _ => Some(b - 1),
                },
                in_parent: Offset::from_xyz(
                    Vec3::from_f64(j.parent_translation),
                    j.parent_orientation,
                ),
                in_child: Offset::from_xyz(
                    Vec3::from_f64(j.child_translation),
                    j.child_orientation,
                ),
                rotations,
                translations,
            };
        }
        let body_index = |name: &str, side: usize| {
            BODIES.iter().position(|b| *b == name).ok_or_else(|| Fault {
                message: format!("toe tip on `{name}`, which is not a body of the chain"),
                at: vec![Key("toe_tips"), Index(side), Key("body")],
            })
        };
        let mut points = [BodyPoint {
            body: 0,
            offset: Vec3::zero(),
        }; 12];
        for side in 0..2 {
            for k in 0..5 {
                let b = 1 + 5 * side + k;
                points[6 * side + k] = BodyPoint {
                    body: b,
                    offset: Vec3::from_f64(self.joints[b].child_translation),
                };
            }
            let tip = &self.toe_tips[side];
            points[6 * side + 5] = BodyPoint {
                body: body_index(&tip.body, side)?,
                offset: Vec3::from_f64(tip.location),
            };
        }
        let functions = Functions {
            splines: &splines,
            polynomials: &polynomials,
        };
        LowerLimb::new(joints, points, functions, &couplers)
            .map_err(|e| Fault::whole(e.to_string()))
    }

    /// The clamped ranges by input coordinate ([`COORDINATES`] order; unbounded where none is
    /// given), or the first range naming a coordinate that is not an input; `name` names the
    /// model in the error.
    pub fn bounds(&self, name: &str) -> Result<([f64; 17], [f64; 17]), ModelError> {
        self.checked_bounds().map_err(|fault| fault.in_model(name))
    }

    /// [`bounds`](Self::bounds), a refusal saying where in the file the range refused is.
    fn checked_bounds(&self) -> Result<([f64; 17], [f64; 17]), Fault> {
        let mut min = [f64::NEG_INFINITY; 17];
        let mut max = [f64::INFINITY; 17];
        for (k, r) in self.ranges.iter().enumerate() {
            let at = |key| vec![Key("ranges"), Index(k), Key(key)];
            let i = COORDINATES
                .iter()
                .position(|c| *c == r.coordinate)
                .ok_or_else(|| Fault {
                    message: format!(
                        "range of `{}`: not one of {}",
                        r.coordinate,
                        COORDINATES.join(", ")
                    ),
                    at: at("coordinate"),
                })?;
            if r.min.is_nan() || r.max.is_nan() || r.min > r.max {
                return Err(Fault {
                    message: format!(
                        "range of `{}`: min {} above max {}",
                        r.coordinate, r.min, r.max
                    ),
                    at: at("min"),
                });
            }
            (min[i], max[i]) = (r.min, r.max);
        }
        Ok((min, max))
    }

    /// The file text: `comment` lines, then the tables.
    pub fn to_toml(&self, comment: &[String]) -> String {
        let mut text = String::new();
        for line in comment {
            text.push_str("# ");
            text.push_str(line);
            text.push('\n');
        }
        text.push_str(&toml::to_string(self).expect("plain data serialises"));
        text
    }

    /// Whether `text` is a chain file (it has `[[joints]]` tables) rather than a SUBJECT.toml.
    pub fn is_chain_file(text: &str) -> bool {
        text.lines().any(|l| l.trim() == "[[joints]]")
    }

    /// Reads a chain file `source` and checks it with the kernel.
    pub fn parse(text: &str, source: &str) -> Result<Self, ModelError> {
        let model: Self = toml::from_str(text)
            .map_err(|e| super::toml_error(text, source, e.span(), e.message()))?;
        model
            .build()
            .and_then(|_| model.checked_bounds())
            .map_err(|fault| fault.in_file(text, source))?;
        Ok(model)
    }
}
