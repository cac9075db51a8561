//! The simulated field's own row map: the row's line as a planting machine's RTK record
//! gives it, a point every 25 cm in latitude and longitude. The machine's own RTK error
//! puts the planted line slightly off where the map says it is: the map's points are off
//! the true row sideways by a slowly changing error ([sim] gnss_map_error_sd_m over
//! gnss_map_error_length_m), so that GNSS alone cannot follow the row perfectly either.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use super::field::Field;
use super::gauss_markov::GaussMarkov;
use super::params::SimParams;
use crate::geo::{Enu, Geodetic, LocalFrame};

/// Distance between the map's points along the row, m.
pub(crate) const MAP_SPACING_M: f64 = 0.25;

/// The row's map line, from its start to 5 m past its end (as far as the field's line
/// goes). `params` must be sanitized.
pub fn planted_map(field: &Field, params: &SimParams) -> Vec<Geodetic> {
    let g = &params.gnss;
    let mut rng = ChaCha8Rng::seed_from_u64(params.seed.wrapping_add(super::SEED_MAP));
    let mut error = GaussMarkov::new(
        g.map_error_sd_m,
        g.map_error_length_m,
        rng.sample(StandardNormal),
    );
    let frame = LocalFrame::new(Geodetic {
        lat_deg: g.origin_lat_deg,
        lon_deg: g.origin_lon_deg,
        height_m: 0.0,
    });
    // The field's line goes on 5 m past the row's end.
    let total_m = field.length_m() + 5.0;
    let count = (total_m / MAP_SPACING_M).floor() as usize + 1;
    (0..count)
        .map(|k| {
            let s_m = k as f64 * MAP_SPACING_M;
            let left_m = if k == 0 {
                error.value_m()
            } else {
                error.step(MAP_SPACING_M, rng.sample(StandardNormal))
            };
            let (x_m, y_m, heading_rad) = field.point_at(s_m);
            frame.to_geodetic(Enu {
                east_m: x_m - left_m * heading_rad.sin(),
                north_m: y_m + left_m * heading_rad.cos(),
                up_m: 0.0,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::params::RowShape;

    #[test]
    fn the_map_follows_the_row_within_the_planting_error_and_wanders_slowly() {
        let params = SimParams {
            row: RowShape::Arc,
            row_length_m: 200.0,
            ..SimParams::default()
        }
        .sanitized();
        let field = Field::new(&params);
        let map = planted_map(&field, &params);
        assert_eq!(map.len(), 821, "a point every 25 cm over 205 m");
        let origin = LocalFrame::new(Geodetic {
            lat_deg: params.gnss.origin_lat_deg,
            lon_deg: params.gnss.origin_lon_deg,
            height_m: 0.0,
        });
        let mut hint = 0;
        let offsets_m: Vec<f64> = map
            .iter()
            .map(|p| {
                let e = origin.to_enu(*p);
                field
                    .project(e.east_m, e.north_m, &mut hint)
                    .signed_offset_m
            })
            .collect();
        let n = offsets_m.len() as f64;
        let sd_m = (offsets_m.iter().map(|o| o * o).sum::<f64>() / n).sqrt();
        assert!((0.003..0.02).contains(&sd_m), "map error s.d. {sd_m} m");
        let worst_step_m = offsets_m
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        // A step of 25 cm changes it by 1.6 mm s.d.; white noise would by 14 mm.
        assert!(
            worst_step_m < 0.007,
            "the error jumps {worst_step_m} m in 25 cm"
        );
        // Another seed plants another error.
        let other = planted_map(
            &field,
            &SimParams {
                seed: 2,
                ..params.clone()
            },
        );
        assert_ne!(other[100], map[100]);
    }
}
