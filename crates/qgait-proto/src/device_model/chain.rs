//! Imported lower-limb chains as they travel: [`ChainUpload::of_chain`] packs a kernel chain
//! (the host's `LowerLimb<f64>`) into the hub's table ([`DeviceChain`], numbers rounded to
//! `f32`) and cuts its image into [`ChainTable`] parts; the hub writes them into its slot
//! ([`Kinematics::write_chain`](crate::Kinematics::write_chain)) and checks them against the
//! [`ChainTableConfig`] ([`table_crc`]); [`chain_pose`] is the host's chain's pose from a
//! sample's angles (the hub's is `Kinematics`').

use qgait_kernel::models::packed::PackedChain;
use qgait_kernel::models::ranges::KneeFlexion;
use qgait_kernel::{BilateralPose, Gait2392Pose, Real};

use crate::device_model::error::ConfigError;
use crate::{
    ChainTable, ChainTableConfig, JointId, MissingPolicy, CHAIN_BODIES, MAX_CHAIN_DRIVES,
    MAX_CHAIN_SPLINES, MAX_CHAIN_TABLE_BYTES, MAX_CHAIN_WORDS,
};

/// Output points of a chain: per side (right first) hip, knee, ankle, subtalar and MTP centres,
/// then the toe tip (the kernel's `gait2392::POINTS` order).
pub const CHAIN_POINTS: usize = 12;

/// The chain a hub computes with: the kernel's packed table on the 17 coordinates in
/// [`JointId`] order, [`CHAIN_BODIES`] bodies, [`CHAIN_POINTS`] points, up to
/// [`MAX_CHAIN_SPLINES`] splines, no polynomials, up to [`MAX_CHAIN_DRIVES`] moving axes and
/// [`MAX_CHAIN_WORDS`] numbers, in `f32`.
pub type DeviceChain = PackedChain<
    f32,
    { JointId::COUNT },
    CHAIN_BODIES,
    CHAIN_POINTS,
    MAX_CHAIN_SPLINES,
    0,
    MAX_CHAIN_DRIVES,
    MAX_CHAIN_WORDS,
>;

/// Bytes of a [`DeviceChain`]'s image: its codes, then its numbers.
pub const CHAIN_IMAGE_LEN: usize = DeviceChain::IMAGE_LEN;

/// A lower-limb chain of any size (the host's `LowerLimb` is `S = 12`, `K = 16`, `Q = 12`).
pub type LowerLimbChain<T, const S: usize, const K: usize, const Q: usize> =
    qgait_kernel::models::CustomChain<T, { JointId::COUNT }, CHAIN_BODIES, CHAIN_POINTS, S, K, Q>;

/// The pose of a chain from a sample's angles (indexed by [`JointId::index`], the chain's
/// coordinate order): hip, knee, ankle and toe tip of each leg.
#[inline(always)]
pub fn chain_pose<T: Real, const S: usize, const K: usize, const Q: usize>(
    chain: &LowerLimbChain<T, S, K, Q>,
    angles: &[T; JointId::COUNT],
) -> BilateralPose<T> {
    Gait2392Pose {
        points: chain.forward(angles),
    }
    .bilateral()
}

/// The CRC-32C of the first `len` bytes of `table`'s image (what a [`ChainTableConfig`]
/// carries).
pub fn table_crc(table: &DeviceChain, len: usize) -> u32 {
    let mut register = crate::crc::INIT;
    let mut left = len;
    for section in table.code_sections() {
        let n = section.len().min(left);
        register = update(register, &section[..n]);
        left -= n;
    }
    for w in table.words() {
        let n = left.min(4);
        register = update(register, &w.to_le_bytes()[..n]);
        left -= n;
    }
    !register
}

/// The CRC register through `bytes`: one copy for [`table_crc`]'s two loops (a hub runs it once
/// an upload, the frames' CRC has its own, inlined where speed counts).
#[inline(never)]
fn update(register: u32, bytes: &[u8]) -> u32 {
    crate::crc::update(register, bytes)
}

/// A chain packed for a hub, and its image's length and CRC: the parts and the config that
/// upload it.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainUpload {
    /// The upload id.
    pub upload: u8,
    /// The table the hub will hold.
    pub table: DeviceChain,
    /// Bytes of the image sent: the codes and the numbers in use.
    pub len: usize,
    /// Their CRC-32C.
    pub crc: u32,
    /// Which sign of `knee_angle` flexes the chain's knee (its forward kinematics says).
    pub knee: KneeFlexion,
}

impl ChainUpload {
    /// `chain` packed for a hub (numbers rounded to `f32`) under `upload`. Fails if it has
    /// polynomials ([`ConfigError::ChainPolynomial`]: the hub's table holds none) or more
    /// splines, moving axes or numbers than a hub holds ([`ConfigError::ChainTooLarge`]).
    pub fn of_chain<T: Real, const S: usize, const K: usize, const Q: usize>(
        chain: &LowerLimbChain<T, S, K, Q>,
        upload: u8,
    ) -> Result<ChainUpload, ConfigError> {
        if !chain.polynomials().is_empty() {
            return Err(ConfigError::ChainPolynomial);
        }
        let table: DeviceChain = chain.packed().map_err(|_| ConfigError::ChainTooLarge)?;
        let len = DeviceChain::CODES_LEN + 4 * table.used();
        Ok(ChainUpload {
            upload,
            crc: table_crc(&table, len),
            knee: KneeFlexion::of(|q| chain.forward(q)),
            table,
            len,
        })
    }

    /// The [`ChainTable`] parts of the image's first [`len`](Self::len) bytes, in order.
    pub fn parts(&self) -> impl Iterator<Item = ChainTable> + '_ {
        (0..self.len).step_by(MAX_CHAIN_TABLE_BYTES).map(|at| {
            let mut bytes = heapless::Vec::new();
            let n = MAX_CHAIN_TABLE_BYTES.min(self.len - at);
            // `n` fits the part's capacity.
            let _ = bytes.resize(n, 0);
            self.table.read_image(at, &mut bytes);
            ChainTable {
                upload: self.upload,
                at: at as u16,
                bytes,
            }
        })
    }

    /// The [`ChainTableConfig`] that switches a hub to this chain, with these settings.
    pub fn config(
        &self,
        missing_policy: MissingPolicy,
        reorder_window: u8,
        request_status: bool,
    ) -> ChainTableConfig {
        ChainTableConfig {
            upload: self.upload,
            len: self.len as u16,
            crc: self.crc,
            knee_flexes_positive: self.knee == KneeFlexion::Positive,
            missing_policy,
            reorder_window,
            request_status,
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::{decode_message, encode_message, Message, MAX_MESSAGE_LEN};
    use qgait_kernel::models::fixtures::walker_chain;

    /// Every part through its wire bytes, written into an empty table.
    pub(crate) fn received(upload: &ChainUpload) -> DeviceChain {
        let mut table = DeviceChain::EMPTY;
        let mut buf = [0u8; MAX_MESSAGE_LEN];
        for part in upload.parts() {
            let bytes = encode_message(&part.clone().into(), &mut buf).unwrap();
            let Message::ChainTable(part) = decode_message(bytes).unwrap() else {
                panic!()
            };
            table.write_image(usize::from(part.at), &part.bytes);
        }
        table
    }

    #[test]
    fn hub_chain_is_the_hosts_within_micrometres() {
        let host = walker_chain();
        let upload = ChainUpload::of_chain(&host, 3).unwrap();
        assert!(upload.parts().count() >= 2);
        let hub = received(&upload);
        assert_eq!(table_crc(&hub, upload.len), upload.crc);
        let mut worst = 0.0f64;
        for k in 0..200 {
            let q: [f64; 17] = core::array::from_fn(|i| {
                let t = 0.37 * (k * 17 + i) as f64;
                0.8 * Real::sin_cos(t).0 + if i == 6 || i == 13 { 1.0 } else { 0.0 }
            });
            let want = host.forward(&q);
            let got = hub.forward(&q.map(|a| a as f32));
            for (a, b) in want.iter().zip(&got) {
                worst = worst.max(a.max_abs_diff(b.cast()));
            }
        }
        assert!(worst < 2e-6, "{worst}");
        assert!(worst > 0.0);
    }

    #[test]
    fn a_part_lost_or_changed_changes_the_crc() {
        let upload = ChainUpload::of_chain(&walker_chain(), 3).unwrap();
        let whole = received(&upload);
        for skip in 0..upload.parts().count() {
            let mut table = DeviceChain::EMPTY;
            for (k, part) in upload.parts().enumerate() {
                if k != skip {
                    table.write_image(usize::from(part.at), &part.bytes);
                }
            }
            assert_ne!(
                table_crc(&table, upload.len),
                upload.crc,
                "part {skip} lost"
            );
        }
        let mut changed = whole;
        changed.write_image(upload.len - 1, &[0x5a]);
        assert_ne!(table_crc(&changed, upload.len), upload.crc);
    }
}
