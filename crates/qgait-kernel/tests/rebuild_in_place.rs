//! Models rebuilt where they live (`rebuild`, what a device does on a model switch) are the
//! models `new` builds; a refused description leaves the model as it was; `check` agrees with
//! `rebuild`; the empty slot evaluates without panicking.

use qgait_kernel::models::gait2392::Knots;
use qgait_kernel::{
    Anthropometry, Gait2392, Gait2392Geometry, Limb, ModelError, Phak, PhakAngles, Vec3,
};

fn angles(k: usize) -> PhakAngles<f32> {
    let a = |i: usize| (((k * 8 + i) as f32) * 0.37).sin() * 0.8;
    PhakAngles::from_array(core::array::from_fn(a))
}

fn subject() -> Anthropometry<f32> {
    Anthropometry {
        right: Limb {
            pelvis_half_width: 0.09,
            femur: 0.43,
            tibia: 0.41,
            foot: 0.17,
        },
        left: Limb {
            pelvis_half_width: 0.08,
            femur: 0.42,
            tibia: 0.40,
            foot: 0.16,
        },
    }
}

#[test]
fn phak_rebuilt_in_place_is_phak_built_new() {
    let mut slot = Phak::<f32>::EMPTY;
    slot.rebuild(&Anthropometry::gait2392()).unwrap();
    assert_eq!(slot, Phak::new(&Anthropometry::gait2392()).unwrap());
    slot.rebuild(&subject()).unwrap();
    let fresh = Phak::new(&subject()).unwrap();
    assert_eq!(slot, fresh);
    for k in 0..20 {
        assert_eq!(slot.fk(&angles(k)), fresh.fk(&angles(k)));
    }
}

#[test]
fn a_refused_phak_leaves_the_model_unchanged() {
    let mut model = Phak::new(&subject()).unwrap();
    let before = model;
    // Valid right leg pieces (written first by a builder that wrote as it went), then a bad
    // left tibia.
    let mut bad = subject();
    bad.right.femur = 0.5;
    bad.left.tibia = f32::NAN;
    assert_eq!(Phak::check(&bad), Err(ModelError::BadLength));
    assert_eq!(model.rebuild(&bad), Err(ModelError::BadLength));
    assert_eq!(model, before);
    assert_eq!(Phak::check(&subject()), Ok(()));
}

#[test]
fn gait2392_rebuilt_in_place_is_gait2392_from_geometry() {
    let generic = Gait2392Geometry::generic().to_f32();
    // A PHAK-sized history does not matter: the slot starts empty, then holds another subject.
    let mut slot = Gait2392::<f32>::EMPTY;
    let mut longer = generic;
    longer.right.ankle_in_tibia[1] *= 1.1;
    slot.rebuild(&longer).unwrap();
    slot.rebuild(&generic).unwrap();
    assert_eq!(slot, Gait2392::from_geometry(&generic).unwrap());
}

#[test]
fn a_refused_gait2392_leaves_the_model_unchanged() {
    let generic = Gait2392Geometry::generic().to_f32();
    let mut model = Gait2392::from_geometry(&generic).unwrap();
    let before = model;

    // Valid pieces that differ from the model's (a longer right shank), then a bad one.
    let mut longer = generic;
    longer.right.ankle_in_tibia[1] *= 1.1;
    let mut zero_axis = longer;
    zero_axis.left.mtp_axis = [0.0; 3];
    assert_eq!(
        Gait2392::check(&zero_axis),
        Err(ModelError::BadAxis { joint: 10 })
    );
    assert_eq!(
        model.rebuild(&zero_axis),
        Err(ModelError::BadAxis { joint: 10 })
    );
    assert_eq!(model, before);

    // The knots are checked before anything is written too (the splines come last).
    let mut knots_out_of_order = longer;
    knots_out_of_order.left.knee_ty = Knots::new(&[0.0, -1.0, 1.0], &[0.0, 0.1, 0.2]);
    assert_eq!(
        Gait2392::check(&knots_out_of_order),
        Err(ModelError::SplineKnots)
    );
    assert_eq!(
        model.rebuild(&knots_out_of_order),
        Err(ModelError::SplineKnots)
    );
    assert_eq!(model, before);
    assert_eq!(Gait2392::check(&generic), Ok(()));
}

#[test]
fn the_empty_slots_map_every_input_to_the_origin() {
    let pose = Phak::<f32>::EMPTY.fk(&angles(3));
    assert!(pose.points().iter().all(|p| *p == Vec3::zero()));
    let q: [f32; 17] = core::array::from_fn(|i| i as f32 * 0.1);
    let pose = Gait2392::<f32>::EMPTY.fk(&q);
    assert!(pose.points.iter().all(|p| *p == Vec3::zero()));
}
