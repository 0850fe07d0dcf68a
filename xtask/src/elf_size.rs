//! Flash and static RAM of a firmware ELF, from its section headers.

use anyhow::anyhow;
use object::elf::SHF_ALLOC;
use object::{Object, ObjectSection, SectionFlags, SectionKind};

/// Start of RAM on both boards (0x2000_0000); everything allocated below it is flash.
const RAM_START: u64 = 0x2000_0000;

/// Footprint of one ELF (bytes).
#[derive(Debug, Clone, Copy, Default)]
pub struct Footprint {
    /// Stored in flash: code, read-only data, and the initial values of `.data`.
    pub flash: u64,
    /// RAM taken by statics: `.data`, `.bss`, `.uninit`.
    pub static_ram: u64,
}

/// Sums the allocated sections of `elf`.
pub fn footprint(elf: &[u8]) -> anyhow::Result<Footprint> {
    let file = object::File::parse(elf).map_err(|e| anyhow!("parsing the ELF: {e}"))?;
    let mut f = Footprint::default();
    for section in file.sections() {
        let SectionFlags::Elf { sh_flags } = section.flags() else {
            continue;
        };
        if sh_flags & u64::from(SHF_ALLOC) == 0 {
            continue;
        }
        // NOBITS sections (.bss, .uninit) have no bytes in the image.
        let stored = !matches!(
            section.kind(),
            SectionKind::UninitializedData | SectionKind::UninitializedTls
        );
        if stored {
            f.flash += section.size();
        }
        if section.address() >= RAM_START {
            f.static_ram += section.size();
        }
    }
    Ok(f)
}
