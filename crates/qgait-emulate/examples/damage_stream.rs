//! Damages a clean packet stream (from `qgait packets`) as a radio link does
//! ([`FaultPlan::radio_link`]: 4 % of packets with a bit flipped, 4 % dropped, 2 % of samples
//! with two packets swapped, after 1 % of packets a burst of 1-40 non-zero bytes), to try
//! `qgait emulate --stream`, `decode` or `verify` on it, and says what a hub must count:
//!
//! ```text
//! cargo run -p qgait-emulate --example damage_stream -- CLEAN.bin DAMAGED.bin [SEED]
//! ```

use std::process::ExitCode;

use anyhow::{anyhow, bail};

use qgait_emulate::faults::{damage, samples_of_stream, Fate, FaultPlan};

fn run(args: &[String]) -> anyhow::Result<()> {
    let (input, output, seed) = match args {
        [i, o] => (i, o, 1),
        [i, o, seed] => (
            i,
            o,
            seed.parse()
                .map_err(|_| anyhow!("SEED `{seed}`: expected a whole number"))?,
        ),
        _ => bail!("usage: damage_stream CLEAN.bin DAMAGED.bin [SEED]"),
    };
    let bytes = std::fs::read(input).map_err(|e| anyhow!("{input}: cannot read: {e}"))?;
    let samples = samples_of_stream(&bytes).map_err(|e| anyhow!("{input}: {e}"))?;
    let d = damage(&samples, &FaultPlan::radio_link(seed, 4));
    std::fs::write(output, &d.stream).map_err(|e| anyhow!("{output}: cannot write: {e}"))?;
    let a = d.accounting();
    eprintln!(
        "wrote {} bytes to {output}: of {} packets, {} delivered, {} dropped, {} damaged ({} bursts of noise, {} samples with two packets swapped)",
        d.stream.len(),
        d.packets.len(),
        d.count(Fate::Delivered),
        a.dropped,
        a.damaged,
        d.bursts,
        d.swapped
    );
    eprintln!(
        "a hub must count: packets_accepted {}, decode errors {}, samples_completed {}, samples_incomplete {} ({} samples lost every packet)",
        a.delivered, a.bad_runs, a.complete, a.incomplete, a.vanished
    );
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
