//! The Kalman filter's arithmetic for a state `[x, y, vx, vy]` with a position
//! measurement: constant-velocity prediction, the innovation and the update (Joseph form),
//! and the measurement's log-likelihood that weighs one motion model against another
//! ([`super::modes`]).

use crate::ellipse::Cov2;

/// A 4x4 matrix (the state's covariance).
pub(super) type M4 = [[f64; 4]; 4];

/// 4x4 matrix product.
pub(super) fn mul(a: &M4, b: &M4) -> M4 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..4).map(|k| a[i][k] * b[k][j]).sum()))
}

/// The transpose of `a`.
pub(super) fn transpose(a: &M4) -> M4 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

fn identity() -> M4 {
    std::array::from_fn(|i| std::array::from_fn(|j| f64::from(u8::from(i == j))))
}

/// Constant-velocity prediction with discrete white-noise acceleration of
/// variance `q`: per axis `Q = q [[dt^4/4, dt^3/2], [dt^3/2, dt^2]]`.
pub(super) fn predict(x: &mut [f64; 4], p: &mut M4, dt: f64, q: f64) {
    if dt <= 0.0 {
        return;
    }
    x[0] += dt * x[2];
    x[1] += dt * x[3];
    let mut f = identity();
    (f[0][2], f[1][3]) = (dt, dt);
    let mut np = mul(&mul(&f, p), &transpose(&f));
    let (a, b, c) = (dt.powi(4) / 4.0 * q, dt.powi(3) / 2.0 * q, dt * dt * q);
    for i in 0..2 {
        np[i][i] += a;
        np[i][i + 2] += b;
        np[i + 2][i] += b;
        np[i + 2][i + 2] += c;
    }
    *p = np;
}

/// A position measurement's innovation against a state.
#[derive(Debug, Clone, Copy)]
pub(super) struct Innovation {
    /// Measured minus predicted position, metres.
    pub nu: [f64; 2],
    /// The inverse of the innovation covariance `S = P_pos + R`.
    pub s_inv: [[f64; 2]; 2],
    /// The determinant of `S`, m⁴.
    pub s_det: f64,
    /// The squared Mahalanobis distance `nu' S^-1 nu`.
    pub d2: f64,
}

impl Innovation {
    /// The measurement's log-likelihood under the state, up to a constant shared by every
    /// state it is compared with: `-(d2 + ln det S) / 2`.
    pub(super) fn log_likelihood(&self) -> f64 {
        -0.5 * (self.d2 + self.s_det.ln())
    }
}

/// The innovation of a measured `position` with covariance `r` against the state `(x, p)`;
/// `None` when `S` is singular or anything is not finite.
pub(super) fn innovation(x: &[f64; 4], p: &M4, position: [f64; 2], r: &Cov2) -> Option<Innovation> {
    let (s00, s01, s10, s11) = (
        p[0][0] + r[0][0],
        p[0][1] + r[0][1],
        p[1][0] + r[1][0],
        p[1][1] + r[1][1],
    );
    let det = s00 * s11 - s01 * s10;
    if !(det.is_finite() && det > 0.0) {
        return None;
    }
    let s_inv = [[s11 / det, -s01 / det], [-s10 / det, s00 / det]];
    let nu = [position[0] - x[0], position[1] - x[1]];
    let d2 = nu[0] * (s_inv[0][0] * nu[0] + s_inv[0][1] * nu[1])
        + nu[1] * (s_inv[1][0] * nu[0] + s_inv[1][1] * nu[1]);
    d2.is_finite().then_some(Innovation {
        nu,
        s_inv,
        s_det: det,
        d2,
    })
}

/// The measurement update of `(x, p)` by a measured `position` with covariance `r` (Joseph
/// form, symmetrized); the innovation it took, `None` (and the state unchanged) when it has
/// none.
pub(super) fn update(
    x: &mut [f64; 4],
    p: &mut M4,
    position: [f64; 2],
    r: &Cov2,
) -> Option<Innovation> {
    let inn = innovation(x, p, position, r)?;
    let (nu, si) = (inn.nu, inn.s_inv);
    let k: [[f64; 2]; 4] =
        std::array::from_fn(|i| std::array::from_fn(|j| p[i][0] * si[0][j] + p[i][1] * si[1][j]));
    for (xi, ki) in x.iter_mut().zip(&k) {
        *xi += ki[0] * nu[0] + ki[1] * nu[1];
    }
    // Joseph form: P = A P A' + K R K' with A = I - K H, then symmetrized.
    let a: M4 = std::array::from_fn(|i| {
        std::array::from_fn(|j| f64::from(u8::from(i == j)) - if j < 2 { k[i][j] } else { 0.0 })
    });
    let ap = mul(&mul(&a, p), &transpose(&a));
    *p = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let krk: f64 = (0..2)
                .flat_map(|a| (0..2).map(move |b| (a, b)))
                .map(|(a, b)| k[i][a] * r[a][b] * k[j][b])
                .sum();
            0.5 * (ap[i][j] + ap[j][i]) + krk
        })
    });
    Some(inn)
}

/// The position block of a state's covariance, m².
pub(super) fn position_block(p: &M4) -> Cov2 {
    [[p[0][0], p[0][1]], [p[1][0], p[1][1]]]
}

/// `p` with its position block replaced by `block`.
pub(super) fn set_position_block(p: &mut M4, block: &Cov2) {
    for (row, new) in p.iter_mut().zip(block) {
        row[..2].copy_from_slice(new);
    }
}

/// Restarts the position of `(x, p)` at a measured `position` with covariance `r`: the
/// position and its covariance are the measurement's, the velocity and its covariance are
/// kept, and the two are no longer correlated.
pub(super) fn restart_position(x: &mut [f64; 4], p: &mut M4, position: [f64; 2], r: &Cov2) {
    x[..2].copy_from_slice(&position);
    for (i, row) in p.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            if (i < 2) != (j < 2) {
                *v = 0.0;
            }
        }
    }
    set_position_block(p, r);
}
