//! The one model choice: `--model hak|phak|gait2392|SUBJECT.toml|CHAIN.toml|MODEL.osim` with
//! `--anthropometry FILE.toml`, loaded and checked, as every command that takes a model uses it
//! (the CLI's `ModelArgs` builds it; the hub's configuration is derived from it).

use std::path::Path;

use qgait_kernel::anthropometry::Anthropometry;
use qgait_kernel::{Gait2392, Gait2392Geometry};

use crate::chain::ChainModel;
use crate::error::ModelError;
use crate::subject;
use qgait_opensim::osim::ImportError;

/// A kinematic model with its numbers.
#[derive(Debug, Clone, PartialEq)]
pub enum Model {
    /// Each leg a sagittal hip-knee-ankle chain hung at its hip from a level, forward-facing
    /// pelvis (pelvis angles ignored): the hips at ±pelvis half-width on the z axis, as the hub
    /// computes HAK ([`qgait_kernel::models::Phak::fk_hak`]), so HAK and PHAK poses are in the
    /// same frame.
    Hak {
        /// Segment lengths when given (`--anthropometry`); `None` means gait2392's
        /// ([`Model::lengths`]), and for a hub "keep the lengths it has".
        stated: Option<Anthropometry<f64>>,
    },
    /// The paper's 8-DoF model: both legs with the shared pelvis rotation and list.
    Phak {
        /// As for [`Model::Hak`].
        stated: Option<Anthropometry<f64>>,
    },
    /// gait2392's chain: the generic model, a subject file or an imported `.osim`.
    Gait2392 {
        /// The numbers.
        geometry: Box<Gait2392Geometry>,
        /// `gait2392`, or the file as given.
        name: String,
    },
    /// Any other OpenSim lower-limb chain (Rajagopal 2015/2016, gait10dof18musc, ...): an
    /// imported `.osim` or a chain file from `qgait model import`.
    Chain {
        /// The joints as OpenSim states them.
        chain: Box<ChainModel>,
        /// The file as given.
        name: String,
    },
}

impl Model {
    /// `hak`, `phak`, `gait2392`, the path of a `SUBJECT.toml` (read and checked here), or an
    /// OpenSim model `.osim` (its leg chain imported as `qgait model import` does), with the
    /// segment lengths `stated` (HAK and PHAK only). Returns the notes of an `.osim` import
    /// (where the toe tip came from).
    pub fn load(
        arg: &str,
        stated: Option<Anthropometry<f64>>,
    ) -> Result<(Self, Vec<String>), ModelError> {
        let path = Path::new(arg);
        let is_osim = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("osim"));
        let (model, notes) = match arg {
            "hak" => (Self::Hak { stated }, Vec::new()),
            "phak" => (Self::Phak { stated }, Vec::new()),
            "gait2392" => (
                Self::Gait2392 {
                    geometry: Box::new(Gait2392Geometry::generic()),
                    name: arg.to_string(),
                },
                Vec::new(),
            ),
            _ if is_osim => {
                let text = crate::error::read_text(path, arg)?;
                // The first note says where it was imported from; the others are worth showing.
                let (model, notes) = Self::import(&text, arg, None)?;
                (model, notes.into_iter().skip(1).collect())
            }
            _ if arg.to_ascii_lowercase().ends_with(".toml") || path.is_file() => {
                let text = crate::error::read_text(path, arg)?;
                let model = if ChainModel::is_chain_file(&text) {
                    Self::Chain {
                        chain: Box::new(ChainModel::parse(&text, arg)?),
                        name: arg.to_string(),
                    }
                } else {
                    Self::Gait2392 {
                        geometry: Box::new(subject::parse(&text, arg)?),
                        name: arg.to_string(),
                    }
                };
                (model, Vec::new())
            }
            _ => return Err(ModelError::Unknown(arg.to_string())),
        };
        if let Self::Gait2392 { name, .. } | Self::Chain { name, .. } = &model {
            if stated.is_some() {
                return Err(ModelError::LengthsNotApplicable(name.clone()));
            }
        }
        Ok((model, notes))
    }

    /// The leg chain of an OpenSim model `text` (named `source`; `markers` as for
    /// [`qgait_opensim::osim::import`]): gait2392's table when the chain has gait2392's shape
    /// (its family: the faster evaluation, the hub's subject upload), else a general chain.
    /// Returns the import's notes.
    pub fn import(
        text: &str,
        source: &str,
        markers: Option<(&str, &str)>,
    ) -> Result<(Self, Vec<String>), ModelError> {
        match qgait_opensim::osim::import(text, source, markers) {
            Ok(imported) => Ok((
                Self::Gait2392 {
                    geometry: Box::new(imported.geometry),
                    name: source.to_string(),
                },
                imported.notes,
            )),
            Err(ImportError::Chain { .. }) => {
                let imported = crate::leg_chain::import(text, source, markers)?;
                Ok((
                    Self::Chain {
                        chain: Box::new(imported.model),
                        name: source.to_string(),
                    },
                    imported.notes,
                ))
            }
            Err(e) => Err(e.into()),
        }
    }

    /// The segment lengths of HAK and PHAK: as stated, or gait2392's; `None` for gait2392
    /// models, which have their own geometry.
    pub fn lengths(&self) -> Option<Anthropometry<f64>> {
        match self {
            Self::Hak { stated } | Self::Phak { stated } => {
                Some(stated.unwrap_or_else(Anthropometry::gait2392))
            }
            Self::Gait2392 { .. } | Self::Chain { .. } => None,
        }
    }

    /// The gait2392 geometry of a gait2392 model.
    pub fn geometry(&self) -> Option<&Gait2392Geometry> {
        match self {
            Self::Gait2392 { geometry, .. } => Some(geometry),
            _ => None,
        }
    }

    /// `hak`, `phak`, or the gait2392 model's name (`gait2392` or its file).
    pub fn name(&self) -> &str {
        match self {
            Self::Hak { .. } => "hak",
            Self::Phak { .. } => "phak",
            Self::Gait2392 { name, .. } | Self::Chain { name, .. } => name,
        }
    }

    /// Checks the numbers with the kernel (lengths or geometry it would refuse).
    pub fn check(&self) -> Result<(), ModelError> {
        let rejected = |error| ModelError::Rejected {
            name: self.name().to_string(),
            error,
        };
        match self {
            Self::Gait2392 { geometry, .. } => {
                Gait2392::<f64>::new(geometry).map(drop).map_err(rejected)
            }
            Self::Chain { chain, name } => chain.chain(name).map(drop),
            _ => qgait_kernel::models::Phak::<f64>::new(&self.lengths().expect("a stick model"))
                .map(drop)
                .map_err(rejected),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_load_their_models() {
        let (hak, _) = Model::load("hak", None).unwrap();
        assert_eq!(hak, Model::Hak { stated: None });
        assert_eq!(hak.lengths(), Some(Anthropometry::gait2392()));
        let (g, _) = Model::load("gait2392", None).unwrap();
        assert_eq!(g.geometry(), Some(&Gait2392Geometry::generic()));
        assert_eq!(g.name(), "gait2392");
    }

    #[test]
    fn bad_choices_are_typed_errors() {
        assert!(matches!(
            Model::load("gait2354", None),
            Err(ModelError::Unknown(m)) if m == "gait2354"
        ));
        assert!(matches!(
            Model::load("/nonexistent/s.toml", None),
            Err(ModelError::Read { .. })
        ));
        assert!(matches!(
            Model::load("gait2392", Some(Anthropometry::gait2392())),
            Err(ModelError::LengthsNotApplicable(_))
        ));
    }
}
