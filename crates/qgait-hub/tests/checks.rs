//! Runs every shared scenario check of `qgait_hub::checks` on the host (the firmware runs the
//! same list on the target under QEMU).

#![cfg(feature = "checks")]

#[test]
fn every_shared_check_passes_on_the_host() {
    let mut failures = Vec::new();
    for (name, check) in qgait_hub::checks::ALL {
        match check() {
            Ok(()) => eprintln!("check {name} ... ok"),
            Err(f) => failures.push(format!(
                "{name}: `{}` failed at checks.rs:{}",
                f.what, f.line
            )),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} checks failed:\n{}",
        failures.len(),
        qgait_hub::checks::ALL.len(),
        failures.join("\n")
    );
}
