//! `a * P + b * Q` on P-256 in variable time, for signature verification (every input is
//! public there): interleaved width-5 NAF (Straus), one shared chain of doublings and about
//! one addition per six bits of each scalar.
//!
//! For keys used again and again (the generator, cached signer certificates), [`Multiples`]
//! keeps the odd multiples of `2^(k L) P` for `PARTS` parts of `L = 256 / PARTS` bits: the
//! chain of doublings is then `L` long instead of 256 (65 instead of 257 with 4 parts, at
//! 3 KiB per key). The firmware profile (`firmware-capacities`) keeps only the point (96 B)
//! and uses the plain interleaved chain: its RAM is worth more than the few percent of a
//! verification a table of one part would save.
//!
//! Hand-written because `p256` 0.13's `lincomb` is two separate constant-time
//! multiplications (a 16-entry table scanned in full at every 4-bit window, and two chains
//! of doublings): right for secret scalars, twice the work a verifier needs
//! (`cargo bench -p obu --bench verify` measures the whole check).
//!
//! No function in this module panics on any input.

// Point arithmetic is modular (on the curve); scalar digit arithmetic stays within i8/u64
// by construction (|digit| < 16, limbs shifted right).
#![allow(clippy::arithmetic_side_effects)]

use p256::elliptic_curve::group::Group;
use p256::elliptic_curve::PrimeField;
use p256::{ProjectivePoint, Scalar};

/// NAF width.
const WIDTH: u32 = 5;
/// Odd multiples kept per point: P, 3P, ..., 15P.
const ODD: usize = 1 << (WIDTH - 2);
/// Digits of a 256-bit scalar in width-w NAF (one more than its bits).
const DIGITS: usize = 257;

/// `[P, 3P, 5P, ..., 15P]`.
fn odd_multiples(p: &ProjectivePoint) -> [ProjectivePoint; ODD] {
    let twice = p.double();
    let mut out = [*p; ODD];
    let mut previous = *p;
    for slot in out.iter_mut().skip(1) {
        previous += twice;
        *slot = previous;
    }
    out
}

/// The width-5 NAF digits of `k` (least significant first): each digit is zero or odd with
/// `|d| < 16`, and a non-zero digit is followed by at least four zeros.
fn wnaf(k: &Scalar) -> [i8; DIGITS] {
    let repr = k.to_repr(); // big-endian
    let mut limbs = [0u64; 5];
    for (i, chunk) in repr.rchunks_exact(8).enumerate() {
        let mut word = [0u8; 8];
        word.copy_from_slice(chunk);
        if let Some(limb) = limbs.get_mut(i) {
            *limb = u64::from_be_bytes(word);
        }
    }
    let mut digits = [0i8; DIGITS];
    for digit in digits.iter_mut() {
        if limbs.iter().all(|&l| l == 0) {
            break;
        }
        let low = limbs.first().copied().unwrap_or_default();
        if low & 1 == 1 {
            let window = (low & ((1 << WIDTH) - 1)) as i64;
            let d = if window >= 1 << (WIDTH - 1) {
                window - (1 << WIDTH)
            } else {
                window
            };
            *digit = d as i8;
            if d > 0 {
                sub_small(&mut limbs, d as u64);
            } else {
                add_small(&mut limbs, (-d) as u64);
            }
        }
        shift_right_one(&mut limbs);
    }
    digits
}

fn sub_small(limbs: &mut [u64; 5], v: u64) {
    let mut borrow = v;
    for limb in limbs.iter_mut() {
        let (r, under) = limb.overflowing_sub(borrow);
        *limb = r;
        borrow = u64::from(under);
        if borrow == 0 {
            break;
        }
    }
}

fn add_small(limbs: &mut [u64; 5], v: u64) {
    let mut carry = v;
    for limb in limbs.iter_mut() {
        let (r, over) = limb.overflowing_add(carry);
        *limb = r;
        carry = u64::from(over);
        if carry == 0 {
            break;
        }
    }
}

fn shift_right_one(limbs: &mut [u64; 5]) {
    let mut high = 0;
    for limb in limbs.iter_mut().rev() {
        let low = *limb & 1;
        *limb = (*limb >> 1) | (high << 63);
        high = low;
    }
}

/// Parts of a scalar with their own multiples (64-bit parts).
#[cfg(not(feature = "firmware-capacities"))]
const PARTS: usize = 4;
/// Bits per part.
#[cfg(not(feature = "firmware-capacities"))]
const PART_BITS: usize = 256 / PARTS;

/// For each part `k`, the odd multiples of `2^(k * PART_BITS) P`.
#[cfg(not(feature = "firmware-capacities"))]
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Multiples {
    parts: [[ProjectivePoint; ODD]; PARTS],
}

/// The firmware profile: the point only.
#[cfg(feature = "firmware-capacities")]
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Multiples {
    point: ProjectivePoint,
}

#[cfg(feature = "firmware-capacities")]
impl Multiples {
    /// Keeps `p`.
    pub(super) fn new(p: &ProjectivePoint) -> Self {
        Self { point: *p }
    }
}

/// `a * P + b * Q` from their [`Multiples`], in variable time (public inputs only).
#[cfg(feature = "firmware-capacities")]
pub(super) fn mul_add_with(
    a: &Scalar,
    ta: &Multiples,
    b: &Scalar,
    tb: &Multiples,
) -> ProjectivePoint {
    mul_add_vartime(a, &ta.point, b, &tb.point)
}

#[cfg(not(feature = "firmware-capacities"))]
impl Multiples {
    /// The multiples of `p` (about `8 * PARTS + 256` point operations: once per key).
    pub(super) fn new(p: &ProjectivePoint) -> Self {
        let mut base = *p;
        let parts = core::array::from_fn(|_| {
            let table = odd_multiples(&base);
            for _ in 0..PART_BITS {
                base = base.double();
            }
            table
        });
        Self { parts }
    }
}

/// `a * P + b * Q` from their [`Multiples`], in variable time (public inputs only).
#[cfg(not(feature = "firmware-capacities"))]
pub(super) fn mul_add_with(
    a: &Scalar,
    ta: &Multiples,
    b: &Scalar,
    tb: &Multiples,
) -> ProjectivePoint {
    let (da, db) = (wnaf(a), wnaf(b));
    // Digit i = k * PART_BITS + j belongs to part k at position j; the last part also takes
    // digit 256 (j = PART_BITS).
    let digit = |d: &[i8; DIGITS], part: usize, j: usize| -> i8 {
        if j == PART_BITS && part + 1 != PARTS {
            return 0;
        }
        d.get(part * PART_BITS + j).copied().unwrap_or(0)
    };
    let busy = |j: usize| (0..PARTS).any(|k| digit(&da, k, j) != 0 || digit(&db, k, j) != 0);
    let mut acc = ProjectivePoint::IDENTITY;
    let Some(top) = (0..=PART_BITS).rev().find(|&j| busy(j)) else {
        return acc;
    };
    for j in (0..=top).rev() {
        acc = acc.double();
        for (k, (pa, pb)) in ta.parts.iter().zip(tb.parts.iter()).enumerate() {
            add_digit(&mut acc, pa, digit(&da, k, j));
            add_digit(&mut acc, pb, digit(&db, k, j));
        }
    }
    acc
}

/// Adds `digit * P` (from P's odd multiples) to `acc`.
fn add_digit(acc: &mut ProjectivePoint, table: &[ProjectivePoint; ODD], digit: i8) {
    let index = usize::from(digit.unsigned_abs() / 2);
    if let Some(point) = table.get(index) {
        if digit > 0 {
            *acc += point;
        } else if digit < 0 {
            *acc -= point;
        }
    }
}

/// `a * p + b * q`, in variable time (public inputs only).
pub(super) fn mul_add_vartime(
    a: &Scalar,
    p: &ProjectivePoint,
    b: &Scalar,
    q: &ProjectivePoint,
) -> ProjectivePoint {
    let (da, db) = (wnaf(a), wnaf(b));
    let (tp, tq) = (odd_multiples(p), odd_multiples(q));
    let top = da
        .iter()
        .zip(db.iter())
        .rposition(|(x, y)| *x != 0 || *y != 0);
    let mut acc = ProjectivePoint::IDENTITY;
    let Some(top) = top else {
        return acc;
    };
    for (x, y) in da.iter().zip(db.iter()).take(top + 1).rev() {
        acc = acc.double();
        add_digit(&mut acc, &tp, *x);
        add_digit(&mut acc, &tq, *y);
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;
    use p256::elliptic_curve::ops::Reduce;
    use p256::U256;

    fn scalar(seed: u8) -> Scalar {
        let bytes = [seed.wrapping_mul(151).wrapping_add(7); 32];
        <Scalar as Reduce<U256>>::reduce_bytes(&bytes.into())
    }

    #[test]
    fn matches_the_constant_time_multiplication() {
        let g = ProjectivePoint::GENERATOR;
        let q = g * scalar(99);
        for seed in 0..24u8 {
            let (a, b) = (scalar(seed), scalar(seed.wrapping_add(101)));
            assert_eq!(
                mul_add_vartime(&a, &g, &b, &q),
                g * a + q * b,
                "seed {seed}"
            );
        }
        let zero = Scalar::ZERO;
        assert_eq!(
            mul_add_vartime(&zero, &g, &zero, &q),
            ProjectivePoint::IDENTITY
        );
        let minus_one = -Scalar::ONE;
        assert_eq!(
            mul_add_vartime(&minus_one, &g, &Scalar::ONE, &g),
            ProjectivePoint::IDENTITY
        );
    }

    #[test]
    fn tables_give_the_same_sums() {
        let g = ProjectivePoint::GENERATOR;
        let q = g * scalar(42);
        let (tg, tq) = (Multiples::new(&g), Multiples::new(&q));
        for seed in 0..24u8 {
            let (a, b) = (scalar(seed), scalar(seed.wrapping_add(77)));
            assert_eq!(mul_add_with(&a, &tg, &b, &tq), g * a + q * b, "seed {seed}");
        }
        let top = -Scalar::ONE; // n - 1: every part and digit 256 in use
        assert_eq!(mul_add_with(&top, &tg, &top, &tq), -(g + q));
        let zero = Scalar::ZERO;
        assert_eq!(
            mul_add_with(&zero, &tg, &zero, &tq),
            ProjectivePoint::IDENTITY
        );
    }

    #[test]
    fn naf_digits_rebuild_the_scalar() {
        for seed in 0..16u8 {
            let k = scalar(seed);
            let digits = wnaf(&k);
            let mut back = Scalar::ZERO;
            for &d in digits.iter().rev() {
                back = back.double();
                let small = Scalar::from(u64::from(d.unsigned_abs()));
                back += if d < 0 { -small } else { small };
                assert!(d == 0 || (d % 2 != 0 && d.unsigned_abs() < 16));
            }
            assert_eq!(back, k);
        }
    }
}
