//! The benches' fixed terrain: seven Gaussian hills over a 100 m square, 6-25 m tall.

/// Height at `(x, y)` of the seven hills, each of standard deviation `sigma` metres.
pub(crate) fn height(x: f64, y: f64, sigma: f64) -> f64 {
    const HILLS: [(f64, f64, f64); 7] = [
        (20.0, 30.0, 18.0),
        (75.0, 20.0, 9.0),
        (50.0, 55.0, 25.0),
        (85.0, 80.0, 14.0),
        (15.0, 85.0, 6.0),
        (60.0, 90.0, 11.0),
        (35.0, 10.0, 21.0),
    ];
    HILLS.iter().map(|&(cx, cy, h)| h * (-((x - cx).powi(2) + (y - cy).powi(2)) / (2.0 * sigma * sigma)).exp()).sum()
}
