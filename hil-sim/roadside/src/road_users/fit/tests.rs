use super::*;

fn moved(ring: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let (out, n) = rounded_out(ring);
    out[..n].to_vec()
}

#[test]
fn an_axis_aligned_outline_keeps_its_edges() {
    // Along a row or a column every pixel-edge point shares one rounding: none on average.
    let square = [[10.0, 10.0], [30.0, 10.0], [30.0, 40.0], [10.0, 40.0]];
    assert_eq!(moved(&square), square.to_vec());
}

#[test]
fn a_slanted_outline_stands_out_by_half_a_pixel_times_its_normal() {
    // A diamond's edges cross 10 px both ways: each moves out by 0.5 * cos 45 deg, in
    // either orientation.
    let diamond = [[20.0, 10.0], [30.0, 20.0], [20.0, 30.0], [10.0, 20.0]];
    let mut reversed = diamond;
    reversed.reverse();
    let expected = 0.5 * std::f64::consts::FRAC_1_SQRT_2;
    for ring in [diamond, reversed] {
        let out = moved(&ring);
        for (p, q) in ring.iter().zip(&out) {
            // Each vertex moves along its diagonal by the edge's offset over cos 45 deg.
            let d = (q[0] - p[0]).hypot(q[1] - p[1]);
            assert!(
                (d - expected * std::f64::consts::SQRT_2).abs() < 1e-9,
                "{p:?} -> {q:?}"
            );
            let centre = [20.0, 20.0];
            let r = |a: &[f64; 2]| (a[0] - centre[0]).hypot(a[1] - centre[1]);
            assert!(r(q) > r(p), "{p:?} -> {q:?} moves out");
        }
    }
}

#[test]
fn an_edge_crossing_less_than_a_pixel_moves_less() {
    // A rectangle tilted by 0.2 px over its 40 px top: its top edge moves out by a fifth of
    // what a fully slanted one would.
    let ring = [[0.0, 0.0], [40.0, 0.2], [40.0, 20.2], [0.0, 20.0]];
    let out = moved(&ring);
    let (a, b) = (out[0], out[1]);
    // The top edge's line y = 0.005 x moved up (outward, y decreasing) by about 0.1 px.
    let shift = (0.005 * a[0] - a[1]) / (1.0f64 + 0.005 * 0.005).sqrt();
    assert!((shift - 0.1).abs() < 0.01, "{shift}");
    let shift_b = (0.005 * b[0] - b[1]) / (1.0f64 + 0.005 * 0.005).sqrt();
    assert!((shift_b - 0.1).abs() < 0.01, "{shift_b}");
}
