//! Decoding the firmware's defmt stream (semihosting output on QEMU's stdout) with the ELF's
//! defmt table, in-process: no `defmt-print` to install. Used by `qgait emulate` and by the
//! xtask runner.

use std::io::Read;

use defmt_decoder::{DecodeError, Table};

use crate::EmulateError;

/// The defmt table of an ELF (`name` names it in errors).
pub fn table(name: &str, elf: &[u8]) -> Result<Table, EmulateError> {
    let problem = match Table::parse(elf) {
        Ok(Some(table)) => return Ok(table),
        Ok(None) => "the ELF has no defmt table (.defmt section)".to_string(),
        Err(e) => format!("reading the defmt table: {e}"),
    };
    Err(EmulateError::DefmtTable {
        elf: name.to_string(),
        problem,
    })
}

/// Reads `input` to its end, decoding log frames; each decoded line goes to `on_line`:
/// `println!` frames as they are (e.g. the test summary `N passed, M failed`), level frames as
/// `LEVEL message`. Returns the number of undecodable stretches (each also reported to
/// `on_line` as `defmt: malformed frame`).
pub fn decode_stream(table: &Table, mut input: impl Read, mut on_line: impl FnMut(&str)) -> u32 {
    let mut decoder = table.new_stream_decoder();
    let mut buf = [0u8; 4096];
    let mut malformed = 0;
    loop {
        let n = match input.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => n,
        };
        decoder.received(&buf[..n]);
        loop {
            match decoder.decode() {
                Ok(frame) => {
                    let message = frame.display_message().to_string();
                    let line = match frame.level() {
                        Some(level) => format!("{:<5} {message}", level.as_str().to_uppercase()),
                        None => message,
                    };
                    on_line(&line);
                }
                Err(DecodeError::UnexpectedEof) => break,
                Err(DecodeError::Malformed) => {
                    malformed += 1;
                    on_line("defmt: malformed frame");
                    if !table.encoding().can_recover() {
                        return malformed;
                    }
                }
            }
        }
    }
    malformed
}
