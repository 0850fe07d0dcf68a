//! The Gait Profile Score, the Gait Variable Scores and the Movement Analysis Profile as
//! Baker et al. (2009, Gait & Posture 30:265-269) define them: each GVS is the root mean square
//! difference between the subject's mean curve and the reference mean over the 51 points
//! 0, 2, ..., 100 % of the cycle; a side's GPS is the root mean square of its nine GVS (the
//! pelvis included); the overall GPS is the root mean square of fifteen GVS: the six hip, knee,
//! ankle and foot variables of each side and the three pelvic ones once, from the left side
//! (Baker's choice: the pelvis is one segment, and its left-cycle curves stand for it). A
//! model's scores are over the variables it can move only ([`scores_over`],
//! [`crate::angles::Seen`]): a planar model's sagittal ones.

use crate::angles::Variable;

/// Points of the cycle the scores use (every 2 %).
pub const POINTS: usize = 51;

/// The subject's and the reference's curves at the 51 points, per side and variable; `None`
/// where either has no curve.
pub type Curves = [[Option<Vec<f64>>; 9]; 2];

/// The scores.
#[derive(Clone, Debug, PartialEq)]
pub struct Scores {
    /// GVS per side and variable (degrees), [`Variable::ALL`] order; `None` for a variable
    /// not scored.
    pub gvs: [[Option<f64>; 9]; 2],
    /// GPS per side (degrees), when the GVS of every variable scored are known.
    pub gps: [Option<f64>; 2],
    /// Overall GPS (degrees), when every GVS it takes is known.
    pub overall: Option<f64>,
    /// The variables scored, [`Variable::ALL`] order: all nine, or those the model can move
    /// ([`crate::angles::Seen::variables`]; a planar model's sagittal four).
    pub variables: Vec<Variable>,
}

/// The 51 points of a curve at 0, 1, ..., 100 % (101 points): every other one.
pub fn every_2_percent(curve: &[f64]) -> Vec<f64> {
    curve.iter().step_by(2).copied().collect()
}

/// One GVS: the root mean square difference of two curves of [`POINTS`] points.
pub fn gvs(subject: &[f64], reference: &[f64]) -> f64 {
    assert_eq!(subject.len(), POINTS, "a GVS needs {POINTS} points");
    assert_eq!(reference.len(), POINTS, "a GVS needs {POINTS} points");
    let ss: f64 = subject
        .iter()
        .zip(reference)
        .map(|(a, b)| (a - b).powi(2))
        .sum();
    (ss / POINTS as f64).sqrt()
}

/// Root mean square of values.
fn rms(values: &[f64]) -> f64 {
    (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt()
}

/// The scores of `subject` against `reference` (both 51-point curves) over all nine variables.
pub fn scores(subject: &Curves, reference: &Curves) -> Scores {
    scores_over(subject, reference, &Variable::ALL)
}

/// The scores of `subject` against `reference` over `variables` only: each side's GPS is the
/// RMS of their GVS, the overall GPS of each side's and, for a pelvic one, the left side's
/// alone (a planar model's: pelvic tilt, hip flexion, knee flexion, ankle dorsiflexion, so
/// seven GVS overall).
pub fn scores_over(subject: &Curves, reference: &Curves, variables: &[Variable]) -> Scores {
    let mut gvs_all = [[None; 9]; 2];
    for s in 0..2 {
        for v in indices(variables) {
            if let (Some(a), Some(b)) = (&subject[s][v], &reference[s][v]) {
                gvs_all[s][v] = Some(gvs(a, b));
            }
        }
    }
    from_gvs(gvs_all, variables)
}

/// The [`Variable::ALL`] indices of `variables`.
fn indices(variables: &[Variable]) -> impl Iterator<Item = usize> + '_ {
    variables
        .iter()
        .filter_map(|v| Variable::ALL.iter().position(|x| x == v))
}

/// The scores a subject drawn from the reference population has, the MAP's normal reference:
/// each GVS is the root mean square over the 51 points of the reference's SD (`sd`, per side
/// and variable; `None` where the reference has no curve). The normative SD at a point is the
/// spread of the control subjects' mean curves about the group mean, so its mean square over
/// the cycle is the expected square of a control's GVS; the GPS follow from these GVS by the
/// same rules as a subject's. With another recording as the reference, its SD is its own
/// stride-to-stride spread, and these are the scores of one of its strides.
pub fn normal_scores(sd: &Curves) -> Scores {
    normal_scores_over(sd, &Variable::ALL)
}

/// [`normal_scores`] over `variables` only, as [`scores_over`].
pub fn normal_scores_over(sd: &Curves, variables: &[Variable]) -> Scores {
    let mut gvs_all = [[None; 9]; 2];
    for s in 0..2 {
        for v in indices(variables) {
            gvs_all[s][v] = sd[s][v].as_ref().map(|sd| rms(sd));
        }
    }
    from_gvs(gvs_all, variables)
}

/// The GPS of each side and overall from the GVS of `variables` of each side
/// ([`Variable::ALL`] order).
fn from_gvs(gvs_all: [[Option<f64>; 9]; 2], variables: &[Variable]) -> Scores {
    let side_gps = |s: usize| -> Option<f64> {
        let all: Option<Vec<f64>> = indices(variables).map(|v| gvs_all[s][v]).collect();
        all.filter(|v| !v.is_empty()).map(|v| rms(&v))
    };
    let mut overall = Vec::with_capacity(15);
    for v in indices(variables) {
        if Variable::ALL[v].is_pelvis() {
            overall.push(gvs_all[1][v]);
        } else {
            overall.push(gvs_all[0][v]);
            overall.push(gvs_all[1][v]);
        }
    }
    let overall: Option<Vec<f64>> = overall.into_iter().collect();
    Scores {
        gvs: gvs_all,
        gps: [side_gps(0), side_gps(1)],
        overall: overall.filter(|v| !v.is_empty()).map(|v| rms(&v)),
        variables: variables.to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::angles::Seen;

    fn curves(f: impl Fn(usize, usize, usize) -> f64) -> Curves {
        std::array::from_fn(|s| {
            std::array::from_fn(|v| Some((0..POINTS).map(|p| f(s, v, p)).collect()))
        })
    }

    fn shape(s: usize, v: usize, p: usize) -> f64 {
        (p as f64 * 0.2 + v as f64).sin() * 20.0 + s as f64
    }

    #[test]
    fn a_constant_offset_in_one_variable_is_its_gvs() {
        let reference = curves(shape);
        // Knee flexion of the right side 5 degrees more at every point.
        let knee = 6;
        let subject =
            curves(|s, v, p| shape(s, v, p) + if s == 0 && v == knee { 5.0 } else { 0.0 });
        let sc = scores(&subject, &reference);
        assert_eq!(sc.gvs[0][knee], Some(5.0));
        assert_eq!(sc.gvs[1][knee], Some(0.0));
        // GPS right: sqrt(25 / 9); overall: sqrt(25 / 15).
        assert!((sc.gps[0].unwrap() - (25.0f64 / 9.0).sqrt()).abs() < 1e-12);
        assert_eq!(sc.gps[1], Some(0.0));
        assert!((sc.overall.unwrap() - (25.0f64 / 15.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_recording_against_itself_scores_zero() {
        let c = curves(shape);
        let sc = scores(&c, &c);
        assert_eq!(sc.gps, [Some(0.0), Some(0.0)]);
        assert_eq!(sc.overall, Some(0.0));
    }

    #[test]
    fn the_pelvis_counts_once_from_the_left() {
        let reference = curves(shape);
        // Pelvic tilt off by 3 on the right only, then on the left only.
        let right = curves(|s, v, p| shape(s, v, p) + if s == 0 && v == 0 { 3.0 } else { 0.0 });
        let left = curves(|s, v, p| shape(s, v, p) + if s == 1 && v == 0 { 3.0 } else { 0.0 });
        assert_eq!(scores(&right, &reference).overall, Some(0.0));
        let o = scores(&left, &reference).overall.unwrap();
        assert!((o - (9.0f64 / 15.0).sqrt()).abs() < 1e-12, "{o}");
    }

    /// The normal reference is the RMS of the SD: exactly for a constant SD, and, for a
    /// population of curves spread about a mean, the root mean square of its members' GVS
    /// against that mean (simulated: 4000 members, a deterministic generator).
    #[test]
    fn the_normal_scores_are_what_a_member_of_the_reference_scores() {
        let flat = normal_scores(&curves(|s, _, _| 2.0 + s as f64));
        assert!(flat.gvs[0].iter().all(|g| *g == Some(2.0)));
        assert_eq!(flat.gps, [Some(2.0), Some(3.0)]);
        // Overall: 3 pelvic GVS from the left (3) and 6 of each side.
        let want = ((3.0 * 9.0 + 6.0 * 4.0 + 6.0 * 9.0) / 15.0f64).sqrt();
        assert!((flat.overall.unwrap() - want).abs() < 1e-12);
        // Members: mean + z1 * sd1(p) + z2 * sd2(p), z1 and z2 independent standard normal,
        // so the population's SD at p is sqrt(sd1² + sd2²).
        let (sd1, sd2) = (
            |p: usize| 3.0 + (p as f64 * 0.3).sin(),
            |p: usize| 1.0 + (p as f64 * 0.1).cos().abs(),
        );
        let mut seed = 12345u64;
        let mut uniform = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let mut normal = move || {
            let (a, b) = (uniform(), uniform());
            (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
        };
        let mean = vec![0.0; POINTS];
        let n = 4000;
        let mut sum_sq = 0.0;
        for _ in 0..n {
            let (z1, z2) = (normal(), normal());
            let member: Vec<f64> = (0..POINTS).map(|p| z1 * sd1(p) + z2 * sd2(p)).collect();
            sum_sq += gvs(&member, &mean).powi(2);
        }
        let simulated = (sum_sq / n as f64).sqrt();
        let sd: Vec<f64> = (0..POINTS).map(|p| sd1(p).hypot(sd2(p))).collect();
        let mut population: Curves = Default::default();
        population[0][6] = Some(sd);
        let expected = normal_scores(&population).gvs[0][6].unwrap();
        assert!(
            (simulated / expected - 1.0).abs() < 0.03,
            "{simulated} vs {expected}"
        );
        assert_eq!(normal_scores(&population).gps[0], None);
    }

    /// A planar model's scores: only the sagittal four variables have a GVS, whatever curves
    /// the others have; each side's GPS is the RMS of its four, the overall of seven (the
    /// pelvic tilt once, from the left); the normal scores likewise.
    #[test]
    fn a_planar_model_is_scored_on_the_sagittal_angles_only() {
        let sagittal = Seen::SAGITTAL.variables();
        assert_eq!(
            sagittal,
            [
                Variable::PelvicTilt,
                Variable::HipFlexion,
                Variable::KneeFlexion,
                Variable::AnkleDorsiflexion
            ]
        );
        assert_eq!(Seen::ALL.variables(), Variable::ALL);
        let reference = curves(shape);
        // Every variable off by its index + 1 on the right, + 11 on the left.
        let subject = curves(|s, v, p| shape(s, v, p) + (v + 1 + 10 * s) as f64);
        let sc = scores_over(&subject, &reference, &sagittal);
        assert_eq!(sc.variables, sagittal);
        for (v, var) in Variable::ALL.iter().enumerate() {
            for s in 0..2 {
                let want = sagittal.contains(var).then(|| (v + 1 + 10 * s) as f64);
                let got = sc.gvs[s][v];
                assert!(
                    got.zip(want)
                        .map_or(got.is_none() && want.is_none(), |(g, w)| (g - w).abs()
                            < 1e-12),
                    "{var:?} {s}: {got:?}"
                );
            }
        }
        // Right: 1, 4, 7, 8; left: 11, 14, 17, 18; overall: the left tilt (11) and the six others.
        let rms_of = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
        assert!((sc.gps[0].unwrap() - rms_of(&[1.0, 4.0, 7.0, 8.0])).abs() < 1e-12);
        assert!((sc.gps[1].unwrap() - rms_of(&[11.0, 14.0, 17.0, 18.0])).abs() < 1e-12);
        let seven = [11.0, 4.0, 14.0, 7.0, 17.0, 8.0, 18.0];
        assert!((sc.overall.unwrap() - rms_of(&seven)).abs() < 1e-12);
        // All nine: the full sets.
        let all = scores(&subject, &reference);
        assert!(all.gvs[0].iter().all(Option::is_some));
        assert_eq!(all.variables, Variable::ALL);
        let n = normal_scores_over(&curves(|s, _, _| 2.0 + s as f64), &sagittal);
        assert_eq!(n.gvs[0][1], None);
        assert_eq!(n.gps, [Some(2.0), Some(3.0)]);
        let want = ((9.0 + 3.0 * 4.0 + 3.0 * 9.0) / 7.0f64).sqrt();
        assert!((n.overall.unwrap() - want).abs() < 1e-12);
    }

    #[test]
    fn a_hand_computed_gvs() {
        // Differences 0, 1, 2, ..., 50: RMS = sqrt(sum k^2 / 51) = sqrt(50 * 51 * 101 / 6 / 51).
        let a: Vec<f64> = (0..POINTS).map(|k| k as f64).collect();
        let b = vec![0.0; POINTS];
        let want = (50.0 * 101.0 / 6.0f64).sqrt();
        assert!((gvs(&a, &b) - want).abs() < 1e-12);
        assert_eq!(
            every_2_percent(&(0..101).map(f64::from).collect::<Vec<_>>()).len(),
            51
        );
    }
}
