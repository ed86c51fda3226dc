//! The view's colours: a diverging scale for the actuator forces (blue pulls, grey idles, red
//! pushes) and one warning colour outside it, for what crosses a limit.

/// The colour of a leg or joint past one of the robot file's `[limits]`; not on the scale.
pub const WARNING: &str = "#ff00ff";
/// A joint within its limits.
pub const JOINT: &str = "#303030";
/// The platform and the base.
pub const PLATFORM: &str = "#7f9bbf";
pub const BASE: &str = "#b8b8b8";
/// The platform frame's axes x, y, z.
pub const AXES: [&str; 3] = ["#e41a1c", "#1b9e3e", "#1f5fd6"];

/// The force scale's stops, from `-scale` (0) to `+scale` (1).
/// ColorBrewer's RdBu with a mid grey that shows on white; red minus blue grows along it, so
/// a warmer colour always means a larger force.
const STOPS: [(f64, [u8; 3]); 5] = [
    (0.0, [0x05, 0x71, 0xb0]),
    (0.25, [0x92, 0xc5, 0xde]),
    (0.5, [0x8c, 0x8c, 0x8c]),
    (0.75, [0xf4, 0xa5, 0x82]),
    (1.0, [0xca, 0x00, 0x20]),
];

fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// The colour of a force `gamma` (N) on the scale `±scale`, clamped at its ends; the same
/// colours the colour bar of [`force_scale`] shows.
pub fn force_colour(gamma: f64, scale: f64) -> String {
    let s = if scale > 0.0 {
        (0.5 + 0.5 * gamma / scale).clamp(0.0, 1.0)
    } else {
        0.5
    };
    let s = if s.is_nan() { 0.5 } else { s };
    let k = STOPS
        .iter()
        .position(|&(at, _)| at >= s)
        .unwrap_or(4)
        .max(1);
    let ((a, ca), (b, cb)) = (STOPS[k - 1], STOPS[k]);
    let w = (s - a) / (b - a);
    hex(core::array::from_fn(|c| {
        (f64::from(ca[c]) + w * (f64::from(cb[c]) - f64::from(ca[c]))).round() as u8
    }))
}

/// The force scale as a plotly.js colour scale (`[[position, colour], ...]`), for the colour
/// bar.
pub fn force_scale() -> serde_json::Value {
    STOPS
        .iter()
        .map(|&(at, c)| serde_json::json!([at, hex(c)]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_runs_from_blue_through_grey_to_red() {
        assert_eq!(force_colour(-10.0, 10.0), "#0571b0");
        assert_eq!(force_colour(0.0, 10.0), "#8c8c8c");
        assert_eq!(force_colour(10.0, 10.0), "#ca0020");
        assert_eq!(force_colour(99.0, 10.0), "#ca0020");
        assert_eq!(force_colour(f64::NAN, 10.0), "#8c8c8c");
        // Halfway between the stops at 0.75 and 1.
        let mid = force_colour(7.5, 10.0);
        assert_eq!(mid, hex([0xdf, 0x53, 0x51]));
        assert_ne!(force_colour(1.0, 10.0), WARNING);
    }
}
