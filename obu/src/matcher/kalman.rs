//! The constant-rate Kalman filter both tracks of the lane filter use (across the road:
//! offset and lateral rate; along it: station and speed): a position, its rate, and their
//! covariance `[pxx, pxv, pvv]`.

/// Prediction over `dt` seconds with white acceleration of 1-sigma `accel`.
pub(super) fn predict(x: &mut f32, v: &mut f32, p: &mut [f32; 3], dt: f32, accel: f32) {
    let q = accel * accel;
    let [pxx, pxv, pvv] = *p;
    *x += *v * dt;
    *p = [
        pxx + 2.0 * dt * pxv + dt * dt * pvv + q * dt * dt * dt * dt / 4.0,
        pxv + dt * pvv + q * dt * dt * dt / 2.0,
        pvv + q * dt * dt,
    ];
}

/// Update with a measurement `z` of variance `r` of the position (`k` 0) or the rate
/// (`k` 1).
pub(super) fn update(x: &mut f32, v: &mut f32, p: &mut [f32; 3], k: usize, z: f32, r: f32) {
    let [pxx, pxv, pvv] = *p;
    let (pkk, pk_x, pk_v) = if k == 0 {
        (pxx, pxx, pxv)
    } else {
        (pvv, pxv, pvv)
    };
    let s = pkk + r;
    if s <= 0.0 {
        return;
    }
    let nu = z - if k == 0 { *x } else { *v };
    let (gx, gv) = (pk_x / s, pk_v / s);
    *x += gx * nu;
    *v += gv * nu;
    *p = [pxx - gx * pk_x, pxv - gx * pk_v, pvv - gv * pk_v];
}
