//! Usable values and axis spans: the numbers every figure filters and fits its axes to.

/// `v` if it is a usable coordinate (finite and not absurdly large).
pub(super) fn ok(v: f64) -> Option<f64> {
    (v.is_finite() && v.abs() < 1e9).then_some(v)
}

/// The point if both coordinates are usable.
pub(super) fn ok_point(p: [f64; 2]) -> Option<[f64; 2]> {
    Some([ok(p[0])?, ok(p[1])?])
}

/// A closed interval of one axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Span {
    pub(super) lo: f64,
    pub(super) hi: f64,
}

impl Span {
    /// The smallest span holding the usable values, `None` when there are none.
    pub(super) fn of(values: impl IntoIterator<Item = f64>) -> Option<Span> {
        values.into_iter().filter_map(ok).fold(None, |span, v| {
            Some(span.map_or(Span { lo: v, hi: v }, |s: Span| s.include(v)))
        })
    }

    pub(super) fn include(self, v: f64) -> Span {
        Span {
            lo: self.lo.min(v),
            hi: self.hi.max(v),
        }
    }

    pub(super) fn union(self, other: Option<Span>) -> Span {
        other.map_or(self, |o| self.include(o.lo).include(o.hi))
    }

    pub(super) fn len(self) -> f64 {
        self.hi - self.lo
    }

    /// Widens each side by `frac` of the length, and by at least `min`.
    pub(super) fn pad(self, frac: f64, min: f64) -> Span {
        let d = (self.len() * frac).max(min);
        Span {
            lo: self.lo - d,
            hi: self.hi + d,
        }
    }

    /// The span of length `len` with the same centre.
    pub(super) fn centred(self, len: f64) -> Span {
        let c = 0.5 * (self.lo + self.hi);
        Span {
            lo: c - 0.5 * len,
            hi: c + 0.5 * len,
        }
    }

    /// The plotting range; a broken span (non-finite or empty) becomes 0..1.
    pub(super) fn range(self) -> std::ops::Range<f64> {
        if self.lo.is_finite() && self.hi.is_finite() && self.hi > self.lo {
            self.lo..self.hi
        } else {
            0.0..1.0
        }
    }
}
