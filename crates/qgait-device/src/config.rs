//! The messages that configure a qgait hub (`qgait config`): a `Config` for HAK, PHAK and the
//! generic gait2392, a subject gait2392 model as its six parts (`SubjectLeg`, `SubjectKnee`)
//! followed by the `SubjectConfig` that switches to it, or an imported chain as its table's
//! `ChainTable` parts followed by its `ChainTableConfig`. Layouts: `docs/protocol.md`, sections
//! 4.4 to 4.9.

use qgait_kernel::Gait2392Geometry;
use qgait_proto::device_model::{parts_of, ChainUpload, ConfigError, SubjectParts};
pub use qgait_proto::HubModel;
use qgait_proto::{
    crc32c, encode_frame, encode_message, Config, EncodeError, Message, MissingPolicy,
    SubjectConfig, MAX_FRAME_LEN, MAX_MESSAGE_LEN,
};

/// The settings every configuration carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HubSettings {
    /// Incomplete samples: drop or hold the last values.
    pub missing_policy: MissingPolicy,
    /// Reorder window (samples).
    pub reorder_window: u8,
    /// Ask the hub for a `Status` in answer.
    pub request_status: bool,
}

/// Why a configuration cannot be sent.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum HubConfigError {
    /// A subject model or a chain does not fit the parts a hub takes (e.g. a spline with too
    /// many knots).
    #[error("the model cannot be sent in parts")]
    Parts(#[from] ConfigError),
    /// A message does not encode (a number or a length outside what the wire carries).
    #[error("a configuration message does not encode")]
    Encode(#[from] EncodeError),
}

/// The messages to send, in order. A subject model's upload id, unless given, is the low byte
/// of the CRC-32C of its parts' message bytes: sending another model never reuses the id of
/// the parts a hub holds (except by a 1-in-256 chance), so a lost part can never leave a hub
/// mixing two models.
pub fn messages(model: &HubModel, settings: HubSettings) -> Result<Vec<Message>, HubConfigError> {
    match model {
        HubModel::Stick { .. } | HubModel::Gait2392 => Ok(vec![Message::Config(Config {
            model: model.id(),
            anthropometry: model.lengths(),
            missing_policy: settings.missing_policy,
            reorder_window: settings.reorder_window,
            request_status: settings.request_status,
        })]),
        HubModel::Subject { geometry, upload } => {
            let id = match upload {
                Some(id) => *id,
                None => upload_id(&subject_parts(geometry, 0)?)?,
            };
            let mut out = subject_parts(geometry, id)?;
            out.push(Message::SubjectConfig(SubjectConfig {
                upload: id,
                missing_policy: settings.missing_policy,
                reorder_window: settings.reorder_window,
                request_status: settings.request_status,
            }));
            Ok(out)
        }
        HubModel::Chain { chain, upload } => {
            let packed = ChainUpload::of_chain(&**chain, 0)?;
            // Without an id, the low byte of the table's CRC, as a subject's (below).
            let upload = ChainUpload {
                upload: upload.unwrap_or(packed.crc as u8),
                ..packed
            };
            let mut out: Vec<Message> = upload.parts().map(Message::ChainTable).collect();
            out.push(Message::ChainTableConfig(upload.config(
                settings.missing_policy,
                settings.reorder_window,
                settings.request_status,
            )));
            Ok(out)
        }
    }
}

/// The low byte of the CRC-32C of the parts' message bytes (under upload 0).
fn upload_id(probe: &[Message]) -> Result<u8, HubConfigError> {
    let mut bytes = Vec::new();
    for m in probe {
        let mut buf = [0u8; MAX_MESSAGE_LEN];
        let encoded = encode_message(m, &mut buf)?;
        bytes.extend_from_slice(encoded);
    }
    Ok(crc32c(&bytes) as u8)
}

/// The frames of `messages`, each preceded by a 0x00 (which a receiver skips, and which ends
/// any partial frame it had).
pub fn frames(messages: &[Message]) -> Result<Vec<u8>, HubConfigError> {
    let mut out = Vec::new();
    for m in messages {
        let mut buf = [0u8; MAX_FRAME_LEN];
        let frame = encode_frame(m, &mut buf)?;
        out.push(0);
        out.extend_from_slice(frame);
    }
    Ok(out)
}

/// The six parts of a subject model, numbers rounded to `f32`: the legs (right, left), then
/// the knee splines (right tx, right ty, left tx, left ty).
pub fn subject_parts(g: &Gait2392Geometry, upload: u8) -> Result<Vec<Message>, HubConfigError> {
    let (legs, knees) = parts_of(g, upload)?;
    Ok(legs
        .into_iter()
        .map(Message::SubjectLeg)
        .chain(knees.into_iter().map(Message::SubjectKnee))
        .collect())
}

/// The model a hub assembles from `parts` (the inverse of [`subject_parts`]; the hub's own
/// [`SubjectParts`]), or `None` if a part is missing or a number out of the hub's range: what
/// the host predicts the hub computes with.
pub fn geometry_of_parts(parts: &[Message]) -> Option<Gait2392Geometry> {
    let mut held = SubjectParts::new();
    for m in parts {
        match m {
            Message::SubjectLeg(l) => held.add_leg(l),
            Message::SubjectKnee(k) => held.add_knee(k),
            _ => {}
        }
    }
    Some(held.geometry(held.upload()?).ok()?.cast())
}

#[cfg(test)]
mod tests {
    use super::*;
    use qgait_proto::FrameDecoder;

    const SETTINGS: HubSettings = HubSettings {
        missing_policy: MissingPolicy::HoldLast,
        reorder_window: 3,
        request_status: true,
    };

    fn decode(bytes: &[u8]) -> Vec<Message> {
        let mut d = FrameDecoder::new();
        bytes
            .iter()
            .filter_map(|&b| d.push(b))
            .map(|r| r.expect("every frame decodes"))
            .collect()
    }

    #[test]
    fn a_subject_model_goes_out_as_six_parts_then_its_config() {
        let mut g = Gait2392Geometry::generic();
        g.right.ankle_in_tibia[1] = -0.47;
        let model = HubModel::Subject {
            geometry: Box::new(g),
            upload: None,
        };
        let sent = decode(&frames(&messages(&model, SETTINGS).unwrap()).unwrap());
        assert_eq!(sent.len(), 7);
        let Message::SubjectConfig(c) = sent[6] else {
            panic!("{:?}", sent[6])
        };
        assert!(c.request_status && c.reorder_window == 3);
        assert!(sent[..6].iter().all(|m| match m {
            Message::SubjectLeg(l) => l.upload == c.upload,
            Message::SubjectKnee(k) => k.upload == c.upload,
            _ => false,
        }));
        let back = geometry_of_parts(&sent[..6]).unwrap();
        assert_eq!(back.right.ankle_in_tibia[1], -0.47f32 as f64);
        assert_eq!(back.left.knee_tx.n, 12);
        assert!((back.left.mtp_axis[2] - g.left.mtp_axis[2]).abs() < 1e-7);
        // Another model gets another upload id; the same model the same one.
        let generic = HubModel::Subject {
            geometry: Box::new(Gait2392Geometry::generic()),
            upload: None,
        };
        let other = messages(&generic, SETTINGS).unwrap();
        assert!(matches!(other[6], Message::SubjectConfig(o) if o.upload != c.upload));
        assert_eq!(messages(&model, SETTINGS).unwrap()[6], sent[6]);
    }

    #[test]
    fn built_in_models_are_one_config() {
        use qgait_kernel::Anthropometry;
        use qgait_proto::ModelId;
        let a = Anthropometry::<f64>::gait2392();
        let stick = HubModel::Stick {
            model: ModelId::Phak,
            anthropometry: Some(a),
        };
        let sent = decode(&frames(&messages(&stick, SETTINGS).unwrap()).unwrap());
        let [Message::Config(c)] = sent.as_slice() else {
            panic!("{sent:?}")
        };
        assert_eq!(c.model, ModelId::Phak);
        assert_eq!(
            c.anthropometry.unwrap()[1],
            a.left.to_array().map(|l| l as f32)
        );
        let g = messages(&HubModel::Gait2392, SETTINGS).unwrap();
        assert!(
            matches!(g.as_slice(), [Message::Config(c)] if c.model == ModelId::Gait2392 && c.anthropometry.is_none())
        );
    }

    #[test]
    fn too_many_knots_are_an_error_naming_the_spline() {
        let mut g = Gait2392Geometry::generic();
        g.left.knee_ty.n = 13;
        let err = subject_parts(&g, 1).unwrap_err();
        assert!(matches!(err, HubConfigError::Parts(_)), "{err:?}");
        // The cause, which the CLI prints after the error (`{:#}`).
        assert!(
            format!("{:#}", anyhow::Error::from(err)).contains("left knee_ty"),
            "the cause names the spline"
        );
    }
}
