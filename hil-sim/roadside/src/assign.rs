//! One-to-one assignment of two sets by cost, cheapest pairs first (greedy): what a tracker
//! uses to give each detection at most one track and each track at most one detection.

/// Pairs `(cost, left, right)` taken cheapest first, each left index and each right index
/// at most once; per left index (of `lefts`), its right index and the pair's cost. Costs
/// compare by `total_cmp` (a NaN sorts last); indices at or past `lefts` or `rights` are
/// skipped.
pub fn cheapest_first(
    mut pairs: Vec<(f64, usize, usize)>,
    lefts: usize,
    rights: usize,
) -> Vec<Option<(usize, f64)>> {
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut of_left = vec![None; lefts];
    let mut right_taken = vec![false; rights];
    for (cost, l, r) in pairs {
        if l < lefts && r < rights && of_left[l].is_none() && !right_taken[r] {
            of_left[l] = Some((r, cost));
            right_taken[r] = true;
        }
    }
    of_left
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cheapest_pairs_win_and_each_side_is_taken_once() {
        // Left 0 is nearest right 0 (1.0), but left 1 is nearer it still (0.5): left 0
        // falls back to right 1; left 2 has only right 0, taken.
        let pairs = vec![
            (1.0, 0, 0),
            (2.0, 0, 1),
            (0.5, 1, 0),
            (3.0, 2, 0),
            (f64::NAN, 2, 1),
            (0.1, 7, 0),
        ];
        let got = cheapest_first(pairs, 3, 2);
        assert_eq!(got[0], Some((1, 2.0)));
        assert_eq!(got[1], Some((0, 0.5)));
        assert_eq!(got[2], None);
    }
}
