//! `Chain::new` refuses tables the evaluator cannot run: parents after their children, more
//! than one root, coordinates and bodies out of range.

use qgait_kernel::{Chain, JointSpec, ModelError, PointSpec, Vec3};

fn z() -> Vec3<f64> {
    Vec3::new(0.0, 0.0, 1.0)
}

fn joint(parent: Option<usize>, coordinate: usize) -> JointSpec<f64> {
    JointSpec::new(parent, Vec3::new(0.0, -0.4, 0.0), &[(z(), coordinate)])
}

fn point(body: usize) -> PointSpec<f64> {
    PointSpec {
        body,
        offset: Vec3::zero(),
    }
}

#[test]
fn a_chain_with_one_root_and_earlier_parents_is_accepted() {
    let joints = [joint(None, 0), joint(Some(0), 1), joint(Some(0), 0)];
    let chain: Result<Chain<f64, 2, 3, 1, 0>, _> = Chain::new(joints, [point(2)], []);
    assert!(chain.is_ok());
}

#[test]
fn a_second_root_is_refused() {
    let joints = [joint(None, 0), joint(Some(0), 1), joint(None, 0)];
    let chain: Result<Chain<f64, 2, 3, 1, 0>, _> = Chain::new(joints, [point(2)], []);
    assert_eq!(chain.unwrap_err(), ModelError::ParentOrder { joint: 2 });
}

#[test]
fn a_parent_that_is_not_earlier_is_refused() {
    let joints = [joint(None, 0), joint(Some(1), 1)];
    let chain: Result<Chain<f64, 2, 2, 1, 0>, _> = Chain::new(joints, [point(1)], []);
    assert_eq!(chain.unwrap_err(), ModelError::ParentOrder { joint: 1 });
}

#[test]
fn coordinates_and_bodies_out_of_range_are_refused() {
    let joints = [joint(None, 0), joint(Some(0), 2)];
    let chain: Result<Chain<f64, 2, 2, 1, 0>, _> = Chain::new(joints, [point(1)], []);
    assert_eq!(
        chain.unwrap_err(),
        ModelError::CoordinateOutOfRange { joint: 1 }
    );
    let joints = [joint(None, 0), joint(Some(0), 1)];
    let chain: Result<Chain<f64, 2, 2, 1, 0>, _> = Chain::new(joints, [point(2)], []);
    assert_eq!(chain.unwrap_err(), ModelError::BodyOutOfRange { index: 0 });
}
