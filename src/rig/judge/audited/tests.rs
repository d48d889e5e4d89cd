use super::*;

#[test]
fn an_implausible_scale_names_the_likely_unit() {
    // 7.5 file units: centimetres (75 mm); 75: millimetres; 3 units: inches
    // (76.2 mm), not centimetres (30 mm is further from 75 mm).
    assert!(scale_warning(&[0.075, 0.08, 0.06]).is_none());
    let w = scale_warning(&[7.5, 8.0, 6.0]).unwrap();
    assert!(w.contains("likely in centimetres (75.0 mm fingers)"), "{w}");
    let w = scale_warning(&[75.0, 80.0]).unwrap();
    assert!(w.contains("likely in millimetres"), "{w}");
    let w = scale_warning(&[3.0]).unwrap();
    assert!(w.contains("likely in inches (76.2 mm"), "{w}");
    let w = scale_warning(&[1e6]).unwrap();
    assert!(w.contains("or in any common unit"), "{w}");
    assert!(scale_warning(&[]).is_none());
}
