//! Small numeric helpers shared by the modules (f32, `libm` based).

/// Wraps an angle in degrees into `[0, 360)`; non-finite input gives 0.
pub(crate) fn wrap_360(deg: f32) -> f32 {
    if !deg.is_finite() {
        return 0.0;
    }
    if (0.0..360.0).contains(&deg) {
        return deg;
    }
    if (-360.0..0.0).contains(&deg) {
        // No `%` here: it is a call to `fmodf`, and this is the common case.
        let r = deg + 360.0;
        return if r < 360.0 { r } else { 0.0 };
    }
    let r = libm::fmodf(deg, 360.0);
    if r < 0.0 {
        r + 360.0
    } else {
        r
    }
}

/// Smallest absolute difference between two headings in degrees, in `[0, 180]`.
pub(crate) fn heading_diff(a: f32, b: f32) -> f32 {
    let d = wrap_360(a - b);
    if d > 180.0 {
        360.0 - d
    } else {
        d
    }
}

/// Bearing in degrees clockwise from north of the vector (dx east, dy north).
pub(crate) fn bearing_deg(dx: f32, dy: f32) -> f32 {
    wrap_360(libm::atan2f(dx, dy).to_degrees())
}

/// `v` if finite, else `fallback`.
pub(crate) fn finite_or(v: f32, fallback: f32) -> f32 {
    if v.is_finite() {
        v
    } else {
        fallback
    }
}

/// Standard normal cumulative distribution function.
pub(crate) fn normal_cdf(z: f32) -> f32 {
    0.5 * (1.0 + libm::erff(z * core::f32::consts::FRAC_1_SQRT_2))
}

/// Clamps `v` into `[lo, hi]`, mapping NaN to `lo`.
pub(crate) fn clamp(v: f32, lo: f32, hi: f32) -> f32 {
    if v.is_nan() {
        lo
    } else {
        v.max(lo).min(hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps_and_diffs() {
        assert_eq!(wrap_360(-10.0), 350.0);
        assert_eq!(wrap_360(f32::NAN), 0.0);
        assert!((heading_diff(350.0, 10.0) - 20.0).abs() < 1e-4);
        assert!((bearing_deg(1.0, 0.0) - 90.0).abs() < 1e-4);
        assert!((bearing_deg(0.0, -1.0) - 180.0).abs() < 1e-4);
        assert!((normal_cdf(0.0) - 0.5).abs() < 1e-6);
        assert_eq!(clamp(f32::NAN, 0.0, 1.0), 0.0);
    }
}

/// Sorts a short slice in place by `cmp` (insertion sort, stable): the lists sorted in the
/// core hold at most a few tens of items, and `sort_unstable_by` costs the firmware
/// kilobytes of flash per element type (`nm --size-sort` on the firmware image shows them).
pub(crate) fn sort_small_by<T>(v: &mut [T], mut cmp: impl FnMut(&T, &T) -> core::cmp::Ordering) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && cmp(&v[j - 1], &v[j]) == core::cmp::Ordering::Greater {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}

#[cfg(test)]
mod sort_tests {
    use super::sort_small_by;

    #[test]
    fn sorts_like_the_standard_sort() {
        let mut seed = 12345u32;
        for n in 0..40 {
            let mut v: std::vec::Vec<(u8, u32)> = (0..n)
                .map(|i| {
                    seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                    ((seed >> 24) as u8 % 7, i)
                })
                .collect();
            let mut want = v.clone();
            want.sort_by_key(|x| x.0);
            sort_small_by(&mut v, |a, b| a.0.cmp(&b.0));
            assert_eq!(v, want, "stable, like sort_by");
        }
    }
}
