//! Checks shared by the fuzz targets.

use lookup::Law;

/// A law that parsed must write back to a file that reads as the same law
/// and writes back identically (the input itself may differ where the format
/// leaves freedom: metadata key order, comments, empty lines), and must
/// evaluate without panicking at points derived from its own axes.
pub fn exercise(law: &Law) {
    let again = law.to_bytes();
    let back = Law::from_bytes(&again).expect("written law reads back");
    assert_eq!(&back, law);
    assert_eq!(back.to_bytes(), again, "writing is not idempotent");
    let a = law.axes();
    let (p, h, t) = (a.pressure[0], a.flux[0], a.contact_temperature[0]);
    for (dp, dh, dt) in [
        (1.0, 1.0, 1.0),
        (0.5, 0.5, 0.9),
        (3.0, 2.0, 1.1),
        (1.7, 1.3, 1.0),
    ] {
        if let Ok(v) = law.eval(p * dp, h * dh, t * dt) {
            assert!(v.jump.is_finite() && v.conductance.is_finite());
            assert!(v.d_conductance_dp.is_finite() && v.d_conductance_dh.is_finite());
        }
        if let Ok(w) = law.eval_at_jump(p * dp, dh, t * dt) {
            assert!(w.flux.is_finite() && w.conductance.is_finite());
        }
    }
}
