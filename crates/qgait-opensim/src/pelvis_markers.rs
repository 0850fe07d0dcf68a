//! A model's pelvis landmarks from its markers: the anterior and posterior superior iliac
//! spines (ASIS, PSIS) or the sacrum, as the Conventional Gait Model defines the pelvis by.
//! Scaled subject models carry them (OpenSim's gait2354 marker set: `R.ASIS`, `L.ASIS`,
//! `V.Sacral`; Plug-in Gait's `RASI`, `LASI`, `RPSI`, `LPSI`, `SACR`); generic models do not.

use roxmltree::Document;

/// The pelvis landmarks in the pelvis body frame (metres).
#[derive(Clone, Debug, PartialEq)]
pub struct PelvisLandmarks {
    /// The mid-point of the two ASIS markers.
    pub mid_asis: [f64; 3],
    /// The mid-point of the two PSIS markers, else the sacral marker.
    pub posterior: [f64; 3],
    /// The markers used, as the model names them.
    pub names: Vec<String>,
}

/// What a marker name stands for, by its letters alone (case, dots and underscores ignored).
fn landmark(name: &str) -> Option<&'static str> {
    let key: String = name
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .map(|c| c.to_ascii_uppercase())
        .collect();
    Some(match key.as_str() {
        "RASI" | "RASIS" => "RASIS",
        "LASI" | "LASIS" => "LASIS",
        "RPSI" | "RPSIS" => "RPSIS",
        "LPSI" | "LPSIS" => "LPSIS",
        "SACR" | "SACRUM" | "SACRAL" | "VSACRAL" | "S2" => "SACRUM",
        _ => return None,
    })
}

/// The landmarks of the markers on body `pelvis` in an `.osim` model's text; `None` when it
/// lacks both ASIS, or both PSIS and a sacral marker, or is not XML.
pub fn pelvis_landmarks(text: &str) -> Option<PelvisLandmarks> {
    let doc = Document::parse(text).ok()?;
    let mut found: Vec<(&'static str, String, [f64; 3])> = Vec::new();
    for m in doc.descendants().filter(|n| n.has_tag_name("Marker")) {
        let Some(name) = m.attribute("name") else {
            continue;
        };
        let Some(kind) = landmark(name) else { continue };
        let text_of = |tag: &str| {
            m.children()
                .find(|c| c.has_tag_name(tag))
                .and_then(|c| c.text())
                .map(str::trim)
        };
        let body = text_of("socket_parent_frame").or_else(|| text_of("body"))?;
        if body.rsplit('/').next() != Some("pelvis") {
            continue;
        }
        let v: Vec<f64> = text_of("location")?
            .split_whitespace()
            .filter_map(|x| x.parse().ok())
            .collect();
        let Ok(location) = <[f64; 3]>::try_from(v.as_slice()) else {
            continue;
        };
        if !found.iter().any(|f| f.0 == kind) {
            found.push((kind, name.to_string(), location));
        }
    }
    let get = |k: &str| found.iter().find(|f| f.0 == k);
    let mid = |a: &[f64; 3], b: &[f64; 3]| [0, 1, 2].map(|i| (a[i] + b[i]) / 2.0);
    let (ra, la) = (get("RASIS")?, get("LASIS")?);
    let (posterior, back) = match (get("RPSIS"), get("LPSIS"), get("SACRUM")) {
        (Some(r), Some(l), _) => (mid(&r.2, &l.2), vec![r.1.clone(), l.1.clone()]),
        (_, _, Some(s)) => (s.2, vec![s.1.clone()]),
        _ => return None,
    };
    let mut names = vec![ra.1.clone(), la.1.clone()];
    names.extend(back);
    Some(PelvisLandmarks {
        mid_asis: mid(&ra.2, &la.2),
        posterior,
        names,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn marker(name: &str, body: &str, at: &str) -> String {
        format!("<Marker name=\"{name}\"><socket_parent_frame>/bodyset/{body}</socket_parent_frame><location>{at}</location></Marker>")
    }

    #[test]
    fn asis_and_psis_or_the_sacrum_by_any_usual_name() {
        let doc = |m: &[String]| {
            format!(
                "<OpenSimDocument><MarkerSet>{}</MarkerSet></OpenSimDocument>",
                m.concat()
            )
        };
        let asis = [
            marker("R.ASIS", "pelvis", "0.02 0.03 0.13"),
            marker("LASI", "pelvis", "0.04 0.01 -0.13"),
        ];
        let sacrum = marker("V.Sacral", "pelvis", "-0.17 0.04 0");
        let l =
            pelvis_landmarks(&doc(&[asis[0].clone(), asis[1].clone(), sacrum.clone()])).unwrap();
        assert_eq!(l.mid_asis, [0.03, 0.02, 0.0]);
        assert_eq!(l.posterior, [-0.17, 0.04, 0.0]);
        assert_eq!(l.names, ["R.ASIS", "LASI", "V.Sacral"]);
        // Both PSIS come before the sacrum.
        let psis = [
            marker("r_psis", "pelvis", "-0.15 0.05 0.04"),
            marker("L.PSIS", "pelvis", "-0.15 0.03 -0.04"),
        ];
        let all = [asis.to_vec(), psis.to_vec(), vec![sacrum]].concat();
        let l = pelvis_landmarks(&doc(&all)).unwrap();
        assert_eq!(l.posterior, [-0.15, 0.04, 0.0]);
        // A missing ASIS, or markers on another body, give none.
        assert!(
            pelvis_landmarks(&doc(&[asis[0].clone(), psis[0].clone(), psis[1].clone()])).is_none()
        );
        let femur = [
            marker("R.ASIS", "femur_r", "0 0 0"),
            marker("L.ASIS", "pelvis", "0 0 0"),
            marker("SACR", "pelvis", "0 0 0"),
        ];
        assert!(pelvis_landmarks(&doc(&femur)).is_none());
        assert!(pelvis_landmarks("not xml").is_none());
    }
}
