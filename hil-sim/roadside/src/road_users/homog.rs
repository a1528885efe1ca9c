//! Homogeneous 2-D geometry of the image plane: points and lines as 3-vectors, joined and
//! met by cross products, so that a vanishing point at infinity needs no special case.

/// A homogeneous point `(x, y, w)` (pixel `(x/w, y/w)`, at infinity when `w` is 0) or line
/// `(a, b, c)` (`a x + b y + c = 0`).
pub type H3 = [f64; 3];

/// Cross product: the line through two points, or the point where two lines meet.
pub fn cross(a: H3, b: H3) -> H3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Dot product.
pub fn dot(a: H3, b: H3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a` scaled to unit length; `None` for a zero or non-finite vector.
pub fn unit(a: H3) -> Option<H3> {
    let n = dot(a, a).sqrt();
    (n.is_finite() && n > 0.0).then(|| a.map(|v| v / n))
}

/// The homogeneous point of a pixel.
pub fn point(p: [f64; 2]) -> H3 {
    [p[0], p[1], 1.0]
}

/// The pixel of a homogeneous point; `None` at (or numerically near) infinity.
pub fn pixel(p: H3) -> Option<[f64; 2]> {
    let scale = p[0].abs().max(p[1].abs());
    if p[2].abs() <= 1e-12 * scale || p[2] == 0.0 {
        return None;
    }
    let out = [p[0] / p[2], p[1] / p[2]];
    (out[0].is_finite() && out[1].is_finite()).then_some(out)
}

/// A line scaled so that `a² + b² = 1` (its value at a pixel is then the signed distance);
/// `None` for the line at infinity or a non-finite one.
pub fn normal_line(l: H3) -> Option<H3> {
    let n = l[0].hypot(l[1]);
    (n.is_finite() && n > 0.0).then(|| l.map(|v| v / n))
}

/// Signed distance of a pixel from a line (positive on the side its normal `(a, b)` points
/// to); `None` for the line at infinity.
pub fn signed_distance(line: H3, p: [f64; 2]) -> Option<f64> {
    normal_line(line).map(|l| l[0] * p[0] + l[1] * p[1] + l[2])
}

/// The direction from pixel `p` towards the homogeneous point `v` (towards or away: the sign
/// is that of `w`), not normalised; zero when `p` is `v`.
pub fn towards(p: [f64; 2], v: H3) -> [f64; 2] {
    [v[0] - p[0] * v[2], v[1] - p[1] * v[2]]
}

/// A 3x3 matrix (row-major) times a homogeneous vector.
pub fn apply(m: &[[f64; 3]; 3], v: H3) -> H3 {
    m.map(|row| dot(row, v))
}

/// The unit direction `m` maps a vanishing point `v` to (a point at infinity of the
/// plane, sign arbitrary); `None` when it comes out degenerate.
pub fn apply_direction(m: &[[f64; 3]; 3], v: H3) -> Option<[f64; 2]> {
    let d = apply(m, v);
    let n = d[0].hypot(d[1]);
    (n.is_finite() && n > 0.0).then(|| [d[0] / n, d[1] / n])
}

/// The transpose of a 3x3 matrix.
pub fn transpose(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|r| [m[0][r], m[1][r], m[2][r]])
}

/// The inverse of a 3x3 matrix; `None` when (nearly) singular.
pub fn inverse(m: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let [a, b, c] = *m;
    let (r0, r1, r2) = (cross(b, c), cross(c, a), cross(a, b));
    let det = dot(a, r0);
    let scale = [a, b, c].iter().map(|r| dot(*r, *r)).fold(0.0, f64::max);
    if !(det.is_finite() && det.abs() > 1e-14 * scale.powf(1.5)) {
        return None;
    }
    Some(transpose(&[r0, r1, r2]).map(|row| row.map(|v| v / det)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_meet_at_points_and_at_infinity() {
        // y = x and y = 2 - x meet at (1, 1).
        let l1 = cross(point([0.0, 0.0]), point([2.0, 2.0]));
        let l2 = cross(point([0.0, 2.0]), point([2.0, 0.0]));
        let p = pixel(cross(l1, l2)).unwrap();
        assert!((p[0] - 1.0).abs() < 1e-12 && (p[1] - 1.0).abs() < 1e-12);
        // Parallel lines meet at infinity, in their direction.
        let l3 = cross(point([0.0, 1.0]), point([2.0, 3.0]));
        let inf = cross(l1, l3);
        assert_eq!(pixel(inf), None);
        assert!((inf[0] - inf[1]).abs() < 1e-12 && inf[0] != 0.0);
        assert!((signed_distance(l1, [0.0, 1.0]).unwrap().abs() - 0.5f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn inverts_and_refuses_singular() {
        let m = [[2.0, 0.0, 1.0], [0.0, 3.0, 0.0], [1.0, 0.0, 1.0]];
        let inv = inverse(&m).unwrap();
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let columns = transpose(&inv);
        for (row, want) in m.iter().zip(identity) {
            let got = columns.map(|col| dot(*row, col));
            assert!(
                got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-12),
                "{got:?}"
            );
        }
        assert_eq!(
            inverse(&[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]),
            None
        );
    }
}
