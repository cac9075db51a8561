//! WGS-84 positions in a local east-north-up frame: geodetic latitude, longitude and
//! ellipsoidal height to earth-centred earth-fixed (ECEF) coordinates and on to metres
//! east, north and up of a reference point in the field, and back.
//!
//! Through ECEF rather than a flat-earth approximation, so a field several hundred
//! metres across keeps millimetres; the inverse serves the simulated receiver (which
//! moves in metres and must report degrees) and row maps drawn in metres.
//!
//! Non-finite inputs give non-finite outputs; nothing here panics.

/// WGS-84 semi-major axis, m (NIMA TR8350.2).
pub(crate) const WGS84_A_M: f64 = 6_378_137.0;
/// WGS-84 flattening (NIMA TR8350.2).
pub(crate) const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// First eccentricity squared, 2f - f^2.
const E2: f64 = WGS84_F * (2.0 - WGS84_F);
/// Latitude iteration stops below this change, rad (about 6 nm on the ground).
const LAT_TOLERANCE_RAD: f64 = 1e-15;
/// The iteration gains about a factor e^2 per round; far more than ever needed.
const MAX_ROUNDS: usize = 10;

/// A point on or near the WGS-84 ellipsoid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geodetic {
    pub lat_deg: f64,
    pub lon_deg: f64,
    /// Above the ellipsoid (not mean sea level: GGA's altitude plus geoid separation).
    pub height_m: f64,
}

/// Earth-centred, earth-fixed Cartesian coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Ecef {
    pub x_m: f64,
    pub y_m: f64,
    pub z_m: f64,
}

/// Metres east, north and up of a frame's origin, along its tangent plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Enu {
    pub east_m: f64,
    pub north_m: f64,
    pub up_m: f64,
}

/// Radius of curvature in the prime vertical, m.
fn prime_vertical_radius_m(sin_lat: f64) -> f64 {
    WGS84_A_M / (1.0 - E2 * sin_lat * sin_lat).sqrt()
}

pub(crate) fn geodetic_to_ecef(point: Geodetic) -> Ecef {
    let (sin_lat, cos_lat) = point.lat_deg.to_radians().sin_cos();
    let (sin_lon, cos_lon) = point.lon_deg.to_radians().sin_cos();
    let n_m = prime_vertical_radius_m(sin_lat);
    Ecef {
        x_m: (n_m + point.height_m) * cos_lat * cos_lon,
        y_m: (n_m + point.height_m) * cos_lat * sin_lon,
        z_m: (n_m * (1.0 - E2) + point.height_m) * sin_lat,
    }
}

/// The inverse, by fixed-point iteration on latitude. The height is taken along the
/// normal in a form that stays exact at the poles, where the usual p / cos(lat) - N
/// divides by nearly zero.
pub(crate) fn ecef_to_geodetic(point: Ecef) -> Geodetic {
    let p_m = point.x_m.hypot(point.y_m);
    let lon_rad = point.y_m.atan2(point.x_m);
    let mut lat_rad = point.z_m.atan2(p_m * (1.0 - E2));
    for _ in 0..MAX_ROUNDS {
        let sin_lat = lat_rad.sin();
        let n_m = prime_vertical_radius_m(sin_lat);
        let next_rad = (point.z_m + E2 * n_m * sin_lat).atan2(p_m);
        let change_rad = (next_rad - lat_rad).abs();
        lat_rad = next_rad;
        // NaN (from non-finite input) would never compare small: stop on it too.
        if change_rad.is_nan() || change_rad <= LAT_TOLERANCE_RAD {
            break;
        }
    }
    let (sin_lat, cos_lat) = lat_rad.sin_cos();
    let height_m =
        p_m * cos_lat + point.z_m * sin_lat - WGS84_A_M * (1.0 - E2 * sin_lat * sin_lat).sqrt();
    Geodetic {
        lat_deg: lat_rad.to_degrees(),
        lon_deg: lon_rad.to_degrees(),
        height_m,
    }
}

/// A tangent-plane frame at a reference point, e.g. a corner of the field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalFrame {
    origin: Geodetic,
    origin_ecef: Ecef,
    sin_lat: f64,
    cos_lat: f64,
    sin_lon: f64,
    cos_lon: f64,
}

impl LocalFrame {
    pub fn new(origin: Geodetic) -> LocalFrame {
        let (sin_lat, cos_lat) = origin.lat_deg.to_radians().sin_cos();
        let (sin_lon, cos_lon) = origin.lon_deg.to_radians().sin_cos();
        LocalFrame {
            origin,
            origin_ecef: geodetic_to_ecef(origin),
            sin_lat,
            cos_lat,
            sin_lon,
            cos_lon,
        }
    }

    pub fn origin(&self) -> Geodetic {
        self.origin
    }

    pub fn to_enu(&self, point: Geodetic) -> Enu {
        let ecef = geodetic_to_ecef(point);
        let dx_m = ecef.x_m - self.origin_ecef.x_m;
        let dy_m = ecef.y_m - self.origin_ecef.y_m;
        let dz_m = ecef.z_m - self.origin_ecef.z_m;
        Enu {
            east_m: -self.sin_lon * dx_m + self.cos_lon * dy_m,
            north_m: -self.sin_lat * self.cos_lon * dx_m - self.sin_lat * self.sin_lon * dy_m
                + self.cos_lat * dz_m,
            up_m: self.cos_lat * self.cos_lon * dx_m
                + self.cos_lat * self.sin_lon * dy_m
                + self.sin_lat * dz_m,
        }
    }

    pub fn to_geodetic(&self, point: Enu) -> Geodetic {
        // The transpose of `to_enu`'s rotation: it is orthonormal.
        let (e_m, n_m, u_m) = (point.east_m, point.north_m, point.up_m);
        ecef_to_geodetic(Ecef {
            x_m: self.origin_ecef.x_m - self.sin_lon * e_m - self.sin_lat * self.cos_lon * n_m
                + self.cos_lat * self.cos_lon * u_m,
            y_m: self.origin_ecef.y_m + self.cos_lon * e_m - self.sin_lat * self.sin_lon * n_m
                + self.cos_lat * self.sin_lon * u_m,
            z_m: self.origin_ecef.z_m + self.cos_lat * n_m + self.sin_lat * u_m,
        })
    }
}

#[cfg(test)]
#[path = "geo_tests.rs"]
mod tests;
