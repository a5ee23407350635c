//! Tests of `parse`.

use super::*;
use crate::transfer::ScalarMode;
use std::f32::consts::{PI, TAU};

#[test]
fn triples_dims_and_spacing() {
    assert_eq!(parse_triple::<i32>("1, -2 ,3"), Ok([1, -2, 3]));
    assert_eq!(parse_dims("256x256x128"), Ok([256, 256, 128]));
    assert_eq!(parse_dims("256,256,128"), Ok([256, 256, 128]));
    assert!(parse_dims("256,256").unwrap_err().contains("three values"));
    assert!(parse_dims("1,2,-3")
        .unwrap_err()
        .contains("'-3' is not a valid number"));
    assert_eq!(parse_spacing("0.5,1,2"), Ok([0.5, 1.0, 2.0]));
    for bad in ["0,1,1", "-1,1,1", "1,inf,1", "1,NaN,1"] {
        assert!(
            parse_spacing(bad).unwrap_err().contains("must be positive"),
            "{bad}"
        );
    }
}

#[test]
fn sizes() {
    assert_eq!(parse_size("1280x720"), Ok((1280, 720)));
    assert_eq!(parse_size("16384X1"), Ok((16384, 1)));
    assert!(parse_size("1280").unwrap_err().contains("expected WxH"));
    assert!(parse_size("ax720").unwrap_err().contains("bad width"));
    assert!(parse_size("720x-1").unwrap_err().contains("bad height"));
    for bad in ["0x10", "16385x10"] {
        assert!(parse_size(bad).unwrap_err().contains("1..=16384"), "{bad}");
    }
}

#[test]
fn scalar_ranges() {
    assert_eq!(parse_range("-300,200"), Ok((-300.0, 200.0)));
    assert_eq!(parse_range(" -1.5 , -0.5 "), Ok((-1.5, -0.5)));
    assert!(parse_range("1").unwrap_err().contains("expected LO,HI"));
    assert!(parse_range("2,1")
        .unwrap_err()
        .contains("HI must exceed LO"));
    assert!(parse_range("1,1")
        .unwrap_err()
        .contains("HI must exceed LO"));
    assert!(parse_range("0,inf")
        .unwrap_err()
        .contains("'inf' is not a finite number"));
}

#[test]
fn colours() {
    assert_eq!(parse_colour("0.5, 2, 0"), Ok([0.5, 2.0, 0.0]));
    assert!(parse_colour("1,2")
        .unwrap_err()
        .contains("three non-negative"));
    assert!(parse_colour("1,-2,3")
        .unwrap_err()
        .contains("three non-negative"));
    assert!(parse_colour("1,2,x")
        .unwrap_err()
        .contains("expected R,G,B"));
}

#[test]
fn parameter_ranges() {
    assert_eq!(parse_param_range("0,2pi"), Ok([0.0, TAU]));
    assert_eq!(parse_param_range("-pi,tau"), Ok([-PI, TAU]));
    assert_eq!(parse_param_range("-1.5,0.5*pi"), Ok([-1.5, PI / 2.0]));
    assert!(parse_param_range("0")
        .unwrap_err()
        .contains("expected FROM,TO"));
    assert!(parse_param_range("0,x")
        .unwrap_err()
        .contains("'x' is not a number"));
}

#[test]
fn names() {
    assert_eq!(
        parse_basis("tournier07-legacy"),
        Ok(ShBasis::Tournier07 { legacy: true })
    );
    assert_eq!(
        parse_basis("descoteaux07"),
        Ok(ShBasis::Descoteaux07 { legacy: false })
    );
    assert!(parse_basis("dipy").unwrap_err().contains("'dipy'"));
    assert_eq!(parse_endian("big"), Ok(Endian::Big));
    assert!(parse_endian("middle").is_err());
    assert_eq!(
        parse_integrand("mip"),
        Ok(IntegrandChoice::Scalar(ScalarMode::Maximum))
    );
    assert!(parse_integrand("x").unwrap_err().contains("choose auto"));
}
