//! The frame checksum: CRC-32C (Castagnoli), as catalogued by the `crc` crate (`CRC_32_ISCSI`).

/// The CRC algorithm of every frame: CRC-32C (Castagnoli), also known as CRC-32/ISCSI.
///
/// Polynomial 0x1EDC6F41 (reflected 0x82F63B78), init 0xFFFFFFFF, input and output reflected,
/// xorout 0xFFFFFFFF, check value (CRC of the ASCII bytes `123456789`) 0xE3069283.
pub const FRAME_CRC: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISCSI);

/// The check value of [`FRAME_CRC`]: its CRC of the ASCII bytes `123456789`.
pub const FRAME_CRC_CHECK: u32 = 0xE306_9283;

/// CRC-32C of `bytes`.
pub fn crc32c(bytes: &[u8]) -> u32 {
    FRAME_CRC.checksum(bytes)
}
