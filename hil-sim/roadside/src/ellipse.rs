//! A road position's error as an ellipse: a camera measures a road user well across its
//! line of sight and poorly along it (a box's depth trades against its size), so one radius
//! either overstates the error across or understates it along. J2735's
//! `PositionalAccuracy` carries the ellipse (semi-major, semi-minor, orientation from north).

/// A 2x2 covariance in the local road frame (east, north), m².
pub type Cov2 = [[f64; 2]; 2];

/// `sigma_m²` in every direction.
pub fn circle(sigma_m: f64) -> Cov2 {
    let v = sigma_m * sigma_m;
    [[v, 0.0], [0.0, v]]
}

/// The symmetric part of `c` (its mean with its transpose).
pub fn symmetric(c: &Cov2) -> Cov2 {
    let b = 0.5 * (c[0][1] + c[1][0]);
    [[c[0][0], b], [b, c[1][1]]]
}

/// Eigenvalues (larger first) and the unit eigenvector of the larger of the symmetric part
/// of `c`.
fn eigen(c: &Cov2) -> (f64, f64, [f64; 2]) {
    let [[a, b], [_, d]] = symmetric(c);
    let mid = 0.5 * (a + d);
    let half = (0.25 * (a - d) * (a - d) + b * b).sqrt();
    let (big, small) = (mid + half, mid - half);
    // (big - d, b) and (b, big - a) are both eigenvectors of `big`; the one whose first
    // difference does not cancel (big - d >= a - d when a >= d) keeps its precision.
    let v = if a >= d { [big - d, b] } else { [b, big - a] };
    let n = v[0].hypot(v[1]);
    let v = if n > 0.0 && n.is_finite() {
        [v[0] / n, v[1] / n]
    } else if a > d {
        [1.0, 0.0]
    } else {
        // A circle (or nothing known): north, as `ErrorEllipse::circle`.
        [0.0, 1.0]
    };
    (big, small, v)
}

/// 1-sigma along the worst direction of `c` (the square root of its larger eigenvalue; zero
/// if that is negative, NaN if `c` holds a NaN).
pub fn worst_sigma(c: &Cov2) -> f64 {
    root(eigen(c).0)
}

/// The square root of a variance: zero if it is negative, NaN if it is NaN.
fn root(v: f64) -> f64 {
    if v.is_nan() {
        f64::NAN
    } else {
        v.max(0.0).sqrt()
    }
}

/// `c` with each eigenvalue raised to at least `floor_m²`: never better than `floor_m` in
/// any direction, unchanged where it already is worse.
pub fn floored(c: &Cov2, floor_m: f64) -> Cov2 {
    floored_by(c, &circle(floor_m))
}

/// `c` never better than `floor` along its own axes: each eigenvalue of `c` raised to at
/// least `floor`'s variance along that eigenvector. A floor long where `c` is long and
/// narrow where it is narrow keeps `c` narrow.
pub fn floored_by(c: &Cov2, floor: &Cov2) -> Cov2 {
    let (big, small, [x, y]) = eigen(c);
    let f = symmetric(floor);
    let (l1, l2) = (
        big.max(variance_along(&f, [x, y])),
        small.max(variance_along(&f, [-y, x])),
    );
    with_axes(l1, l2, [x, y])
}

/// The variance of `c` along the unit vector `u`, m².
pub fn variance_along(c: &Cov2, u: [f64; 2]) -> f64 {
    u[0] * u[0] * c[0][0] + u[0] * u[1] * (c[0][1] + c[1][0]) + u[1] * u[1] * c[1][1]
}

/// The covariance with variance `along` along the unit vector `u` and `across` across it:
/// `V diag(along, across) V'` with `V = [u, u turned a quarter]`.
pub fn with_axes(along: f64, across: f64, u: [f64; 2]) -> Cov2 {
    let [x, y] = u;
    [
        [along * x * x + across * y * y, (along - across) * x * y],
        [(along - across) * x * y, along * y * y + across * x * x],
    ]
}

/// Is `c` a covariance: finite, symmetric (to rounding), with no negative variance, and
/// (`definite`) positive definite? Written so that tiny variances do not underflow.
pub fn is_covariance(c: &Cov2, definite: bool) -> bool {
    let [[a, b], [b2, d]] = *c;
    if ![a, b, b2, d].iter().all(|v| v.is_finite()) || a < 0.0 || d < 0.0 {
        return false;
    }
    let scale = a.max(d);
    if (b - b2).abs() > 1e-9 * scale {
        return false;
    }
    let b = 0.5 * (b + b2);
    if definite {
        // b² < a d, as (b / a) b < d.
        a > 0.0 && d > 0.0 && (b / a) * b < d
    } else if a == 0.0 {
        b == 0.0
    } else {
        (b / a) * b <= d + 1e-12 * scale
    }
}

/// `d' c⁻¹ d`, the squared Mahalanobis distance of the offset `d` (metres) under `c`;
/// infinite when `c` is singular or not positive definite.
pub fn mahalanobis2(c: &Cov2, d: [f64; 2]) -> f64 {
    let [[a, b], [_, e]] = symmetric(c);
    let det = a * e - b * b;
    if !(det > 0.0 && a > 0.0 && det.is_finite()) {
        return f64::INFINITY;
    }
    (e * d[0] * d[0] - 2.0 * b * d[0] * d[1] + a * d[1] * d[1]) / det
}

/// A position's 1-sigma error ellipse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorEllipse {
    /// 1-sigma along the worst direction, metres.
    pub semi_major_m: f64,
    /// 1-sigma across it, metres.
    pub semi_minor_m: f64,
    /// Direction of the semi-major axis, degrees clockwise from north in [0, 180) (0 for a
    /// circle).
    pub orientation_deg: f64,
}

impl ErrorEllipse {
    /// The same error `sigma_m` in every direction (orientation 0).
    pub fn circle(sigma_m: f64) -> Self {
        Self {
            semi_major_m: sigma_m,
            semi_minor_m: sigma_m,
            orientation_deg: 0.0,
        }
    }

    /// The ellipse of the covariance `c` (east, north), m² (NaN axes, not known, where `c`
    /// holds a NaN).
    pub fn of(c: &Cov2) -> Self {
        let (big, small, [x, y]) = eigen(c);
        // Clockwise from north: atan2(east, north), folded into a half turn.
        let mut orientation_deg = x.atan2(y).to_degrees().rem_euclid(180.0);
        if orientation_deg >= 180.0 {
            orientation_deg = 0.0;
        }
        Self {
            semi_major_m: root(big),
            semi_minor_m: root(small),
            orientation_deg,
        }
    }

    /// The covariance the ellipse stands for (east, north), m².
    pub fn covariance(&self) -> Cov2 {
        let (s, c) = self.orientation_deg.to_radians().sin_cos();
        // The major axis is (east, north) = (sin, cos).
        let (l1, l2) = (self.semi_major_m.powi(2), self.semi_minor_m.powi(2));
        [
            [l1 * s * s + l2 * c * c, (l1 - l2) * s * c],
            [(l1 - l2) * s * c, l1 * c * c + l2 * s * s],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn an_ellipse_along_north_east_is_at_45_degrees() {
        // Variance 0.05 along (1, 1)/sqrt2, 0.01 across: [[0.03, 0.02], [0.02, 0.03]].
        let e = ErrorEllipse::of(&[[0.03, 0.02], [0.02, 0.03]]);
        assert!(close(e.semi_major_m, 0.05f64.sqrt()), "{e:?}");
        assert!(close(e.semi_minor_m, 0.1), "{e:?}");
        assert!(close(e.orientation_deg, 45.0), "{e:?}");
        let back = e.covariance();
        for (row, want) in back.iter().zip([[0.03, 0.02], [0.02, 0.03]]) {
            assert!(close(row[0], want[0]) && close(row[1], want[1]), "{back:?}");
        }
    }

    #[test]
    fn axis_aligned_ellipses_point_north_or_east() {
        let north = ErrorEllipse::of(&[[0.01, 0.0], [0.0, 0.04]]);
        assert!(close(north.orientation_deg, 0.0) && close(north.semi_major_m, 0.2));
        let east = ErrorEllipse::of(&[[0.04, 0.0], [0.0, 0.01]]);
        assert!(close(east.orientation_deg, 90.0) && close(east.semi_minor_m, 0.1));
        // North-west / south-east: 135 degrees.
        let nw = ErrorEllipse::of(&[[0.03, -0.02], [-0.02, 0.03]]);
        assert!(close(nw.orientation_deg, 135.0), "{nw:?}");
    }

    #[test]
    fn the_floor_raises_only_the_directions_below_it() {
        let c = [[0.04, 0.0], [0.0, 0.0001]];
        let f = floored(&c, 0.05);
        assert!(close(f[0][0], 0.04) && close(f[1][1], 0.0025) && close(f[0][1], 0.0));
        let same = floored(&c, 0.001);
        assert!(close(same[0][0], 0.04) && close(same[1][1], 0.0001) && close(same[0][1], 0.0));
        assert!(close(worst_sigma(&floored(&c, 0.5)), 0.5));
    }

    #[test]
    fn a_floor_along_the_long_axis_keeps_the_ellipse_narrow() {
        // Long north, narrow east; the floor long north too: the east axis stays 1 cm.
        let c = [[0.0001, 0.0], [0.0, 0.01]];
        let f = floored_by(&c, &[[0.0, 0.0], [0.0, 0.04]]);
        assert!(close(f[0][0], 0.0001) && close(f[1][1], 0.04) && close(f[0][1], 0.0));
    }

    #[test]
    fn a_nearly_diagonal_covariance_keeps_its_axes() {
        // A cross term far below the diagonal's precision: the axes are east and north.
        for b in [1e-18, -1e-17, 3e-17, 0.0] {
            let e = ErrorEllipse::of(&[[0.586, b], [b, 0.417]]);
            assert!((e.orientation_deg - 90.0).abs() < 1e-6, "{b}: {e:?}");
            let f = floored(&[[0.586, b], [b, 0.417]], 0.001);
            assert!(close(f[0][0], 0.586) && close(f[1][1], 0.417), "{b}: {f:?}");
            let n = ErrorEllipse::of(&[[0.417, b], [b, 0.586]]);
            assert!(n.orientation_deg.abs() < 1e-6 || (n.orientation_deg - 180.0).abs() < 1e-6);
        }
        assert_eq!(ErrorEllipse::of(&circle(0.1)).orientation_deg, 0.0);
        let unknown = ErrorEllipse::of(&[[f64::NAN, 0.0], [0.0, 0.01]]);
        assert!(
            unknown.semi_major_m.is_nan() && worst_sigma(&[[f64::NAN, 0.0], [0.0, 1.0]]).is_nan()
        );
    }

    #[test]
    fn mahalanobis_distance_counts_sigmas_along_each_axis() {
        let c = [[0.04, 0.0], [0.0, 0.01]];
        assert!(close(mahalanobis2(&c, [0.2, 0.0]), 1.0));
        assert!(close(mahalanobis2(&c, [0.0, 0.2]), 4.0));
        assert!(mahalanobis2(&[[0.0, 0.0], [0.0, 1.0]], [0.0, 0.0]).is_infinite());
    }
}
