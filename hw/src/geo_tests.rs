//! Tests of the WGS-84 conversions against published worked examples, and of the
//! round trip at field scale, at the equator and near a pole.

use super::*;

/// Degrees, minutes and seconds to degrees.
fn dms(deg: f64, min: f64, sec: f64) -> f64 {
    deg + min / 60.0 + sec / 3600.0
}

/// Metres per degree of latitude, roughly: turns angle errors into distances.
const M_PER_DEG: f64 = 111_320.0;

// IOGP Publication 373-7-2 (EPSG Guidance Note 7-2), worked example for method 9602
// (geographic/geocentric conversions), WGS 84: 53°48'33.820"N 2°07'46.380"E, h 73.0 m
// is X 3771793.968 m, Y 140253.342 m, Z 5124304.349 m.
const EPSG_9602_XYZ_M: [f64; 3] = [3_771_793.968, 140_253.342, 5_124_304.349];

fn epsg_9602_point() -> Geodetic {
    Geodetic {
        lat_deg: dms(53.0, 48.0, 33.820),
        lon_deg: dms(2.0, 7.0, 46.380),
        height_m: 73.0,
    }
}

#[test]
fn geodetic_to_ecef_matches_the_epsg_worked_example() {
    let ecef = geodetic_to_ecef(epsg_9602_point());
    let got = [ecef.x_m, ecef.y_m, ecef.z_m];
    for (g, want) in got.iter().zip(EPSG_9602_XYZ_M) {
        // Published to the millimetre.
        assert!((g - want).abs() <= 0.0006, "{got:?} vs {EPSG_9602_XYZ_M:?}");
    }
}

#[test]
fn ecef_to_geodetic_matches_the_epsg_worked_example() {
    let [x_m, y_m, z_m] = EPSG_9602_XYZ_M;
    let back = ecef_to_geodetic(Ecef { x_m, y_m, z_m });
    let want = epsg_9602_point();
    // The published X, Y, Z are rounded to 0.5 mm: allow 1 mm.
    assert!(
        (back.lat_deg - want.lat_deg).abs() * M_PER_DEG < 1e-3,
        "{back:?}"
    );
    assert!(
        (back.lon_deg - want.lon_deg).abs() * M_PER_DEG < 1e-3,
        "{back:?}"
    );
    assert!((back.height_m - want.height_m).abs() < 1e-3, "{back:?}");
}

#[test]
fn enu_matches_the_epsg_topocentric_worked_example() {
    // Same publication, method 9836 (geocentric/topocentric): origin X 3652755.3058,
    // Y 319574.6799, Z 5201547.3536 m, which is latitude 0.9599310885 rad and
    // longitude 0.0872664625 rad; the 9602 point is then U -189013.869,
    // V -128642.040, W -4220.171 m.
    let origin = ecef_to_geodetic(Ecef {
        x_m: 3652755.3058,
        y_m: 319574.6799,
        z_m: 5201547.3536,
    });
    // Published cut (not rounded) to ten decimals: 5 deg is 0.08726646259971...
    assert!(
        (origin.lat_deg.to_radians() - 0.959_931_088_5).abs() < 2e-10,
        "{origin:?}"
    );
    assert!(
        (origin.lon_deg.to_radians() - 0.087_266_462_5).abs() < 2e-10,
        "{origin:?}"
    );
    let frame = LocalFrame::new(origin);
    let enu = frame.to_enu(epsg_9602_point());
    let want = [-189_013.869, -128_642.040, -4_220.171];
    let got = [enu.east_m, enu.north_m, enu.up_m];
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 2e-3, "{got:?} vs {want:?}");
    }
}

fn round_trip_error_m(origin: Geodetic, enu: Enu) -> f64 {
    let frame = LocalFrame::new(origin);
    let back = frame.to_enu(frame.to_geodetic(enu));
    ((back.east_m - enu.east_m).powi(2)
        + (back.north_m - enu.north_m).powi(2)
        + (back.up_m - enu.up_m).powi(2))
    .sqrt()
}

#[test]
fn round_trip_at_a_kilometre_keeps_well_under_a_millimetre() {
    let field = Geodetic {
        lat_deg: 52.52,
        lon_deg: 13.40,
        height_m: 34.0,
    };
    let equator = Geodetic {
        lat_deg: 0.0,
        lon_deg: -78.5,
        height_m: 2_800.0,
    };
    let near_pole = Geodetic {
        lat_deg: 89.99,
        lon_deg: 45.0,
        height_m: 0.0,
    };
    let south = Geodetic {
        lat_deg: -33.9,
        lon_deg: 151.2,
        height_m: 20.0,
    };
    for origin in [field, equator, near_pole, south] {
        for (east_m, north_m, up_m) in [
            (1000.0, 0.0, 0.0),
            (0.0, -1000.0, 5.0),
            (707.1, 707.1, -3.0),
        ] {
            let error_m = round_trip_error_m(
                origin,
                Enu {
                    east_m,
                    north_m,
                    up_m,
                },
            );
            assert!(
                error_m < 1e-6,
                "{origin:?} ({east_m}, {north_m}): {error_m} m"
            );
        }
    }
}

#[test]
fn a_point_north_of_the_origin_is_on_the_north_axis() {
    let origin = Geodetic {
        lat_deg: 48.1,
        lon_deg: 11.5,
        height_m: 500.0,
    };
    let frame = LocalFrame::new(origin);
    // 100 m north along the meridian at the origin's height: the arc length is
    // (M + h) dlat, M the meridian radius of curvature a(1-e^2)/(1-e^2 sin^2 lat)^1.5.
    let s2 = origin.lat_deg.to_radians().sin().powi(2);
    let radius_m = WGS84_A_M * (1.0 - E2) / (1.0 - E2 * s2).powf(1.5) + origin.height_m;
    let north = Geodetic {
        lat_deg: origin.lat_deg + (100.0 / radius_m).to_degrees(),
        ..origin
    };
    let enu = frame.to_enu(north);
    assert!(enu.east_m.abs() < 1e-6, "{enu:?}");
    assert!((enu.north_m - 100.0).abs() < 3e-3, "{enu:?}");
    // The tangent plane leaves the ellipsoid by d^2 / 2R: 0.8 mm at 100 m.
    assert!((-1.5e-3..0.0).contains(&enu.up_m), "{enu:?}");
}

#[test]
fn the_poles_and_the_equator_are_exact() {
    let b_m = WGS84_A_M * (1.0 - WGS84_F);
    let pole = ecef_to_geodetic(Ecef {
        x_m: 0.0,
        y_m: 0.0,
        z_m: b_m + 10.0,
    });
    assert_eq!(pole.lat_deg, 90.0);
    assert!((pole.height_m - 10.0).abs() < 1e-6, "{pole:?}");
    let equator = geodetic_to_ecef(Geodetic {
        lat_deg: 0.0,
        lon_deg: 90.0,
        height_m: 0.0,
    });
    assert!(
        equator.x_m.abs() < 1e-6 && (equator.y_m - WGS84_A_M).abs() < 1e-6,
        "{equator:?}"
    );
    assert_eq!(equator.z_m, 0.0);
}

#[test]
fn nonsense_in_gives_nan_out_not_a_panic() {
    let frame = LocalFrame::new(Geodetic {
        lat_deg: f64::NAN,
        lon_deg: 0.0,
        height_m: 0.0,
    });
    let g = frame.to_geodetic(Enu {
        east_m: f64::INFINITY,
        north_m: 0.0,
        up_m: 0.0,
    });
    assert!(g.lat_deg.is_nan());
    let centre = ecef_to_geodetic(Ecef {
        x_m: 0.0,
        y_m: 0.0,
        z_m: 0.0,
    });
    assert!(centre.height_m < -6e6, "{centre:?}");
}
