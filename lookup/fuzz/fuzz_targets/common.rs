//! Checks shared by the fuzz targets.

use lookup::Law;

/// A law that parsed must round-trip bit-identically and evaluate without
/// panicking at points derived from its own axes.
pub fn exercise(law: &Law, bytes: &[u8]) {
    let again = law.to_bytes();
    assert_eq!(again, bytes, "a parsed law does not write back identically");
    assert_eq!(
        &Law::from_bytes(&again).expect("written law reads back"),
        law
    );
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
