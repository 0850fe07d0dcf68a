//! [`PROTOCOL_VERSION`], in a module of its own: every message that carries a version reads it.

/// The protocol version written in every message that carries one ([`JointAngle`](crate::JointAngle),
/// [`SampleHeader`](crate::SampleHeader)). See `docs/protocol.md` for the versioning rules.
pub const PROTOCOL_VERSION: u8 = 3;
