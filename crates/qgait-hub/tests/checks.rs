//! Runs every scenario check of `qgait-hub-checks` on the host (the firmware's on-target tests
//! run each of them too, under QEMU), reporting every failure, not just the first.

#[test]
fn every_shared_check_passes_on_the_host() {
    let mut failures = Vec::new();
    for (name, check) in qgait_hub_checks::ALL {
        match check() {
            Ok(()) => eprintln!("check {name} ... ok"),
            Err(f) => failures.push(format!(
                "{name}: `{}` failed at qgait-hub-checks/src/{}:{}",
                f.what,
                if qgait_hub_checks::imu::CHECKS.contains(name) {
                    "imu.rs"
                } else {
                    "lib.rs"
                },
                f.line
            )),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} checks failed:\n{}",
        failures.len(),
        qgait_hub_checks::ALL.len(),
        failures.join("\n")
    );
}
