//! Numbers formatted for reading on a page.

use brdf_analysis::html::format::*;

#[test]
fn targets_read_short_with_their_distance_from_the_best_known() {
    let b = 0.09954231141444939;
    assert_eq!(target(0.10053773452859387, Some(b), 4), "0.1005 (+1%)");
    assert_eq!(target(0.10451942698517, Some(b), 4), "0.1045 (+5%)");
    assert_eq!(target(0.102, Some(b), 4), "0.102 (+2.5%)");
    assert_eq!(target(0.11, None, 4), "0.11");
    assert_eq!(target(0.02, Some(2e-18), 4), "0.02");
    assert_eq!(target_digits(&[0.10053, 0.10054]), 5);
    assert_eq!(target_digits(&[0.102, 0.105]), 4);
}

#[test]
fn significant_digits_and_exponents() {
    assert_eq!(significant(0.123456789, 6), "0.123457");
    assert_eq!(significant(12345678.9, 6), "1.23457e7");
    assert_eq!(significant(0.0000123456789, 6), "1.23457e-5");
    assert_eq!(significant(-45.0, 6), "-45");
}

#[test]
fn p_values_are_floored_and_short() {
    assert_eq!(p_value(Some(7.4e-300)), "&lt; 1e-16");
    assert_eq!(p_value(Some(0.0)), "&lt; 1e-16");
    assert_eq!(p_value(Some(2.34e-7)), "2.3e-7");
    assert_eq!(p_value(Some(0.01234)), "0.0123");
    assert_eq!(p_value(None), "-");
}

#[test]
fn ratios_and_rates() {
    assert_eq!(ratio(4.2812), "&times;4.28");
    assert_eq!(ratio(107.9), "&times;108");
    assert_eq!(ratio(12345.0), "&times;1.2e4");
    assert_eq!(rate(1.0), "100%");
    assert_eq!(rate(0.95), "95%");
    assert_eq!(rate(0.025), "2.5%");
    assert_eq!(rate(0.0), "0%");
}
