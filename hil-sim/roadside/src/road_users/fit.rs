//! A road user's box fitted to what the camera sees of it: position, length, width and
//! height that make the projected box's outline match the mask's, with a size prior (the
//! class's, or the road user's track's belief, [`super::size`]) deciding what the view does
//! not measure.
//!
//! The tangent construction ([`super::boxes`]) reads the box from six lines, and needs all
//! six: seen end-on or side-on, one far corner is hidden and the construction stops; partly
//! hidden behind another road user or cut by the image border, its lines are wrong. The fit
//! asks less of the view. A vertex of a mask's outline lies on the road user's true outline,
//! except along a touching mask, where the outline may be the other road user's edge (then
//! it lies inside). So the fit minimises, by Levenberg-Marquardt over `[x, y, length, width,
//! height]`:
//! - each outline vertex's signed distance to the projected box's outline, moved out by the
//!   rounding the mask's outline keeps ([`super::outline`]: up to half a pixel along a
//!   slanted edge, none on average along an axis-aligned one; see `rounded_out`) (only its distance
//!   outside along a touching mask; all vertices together worth six corners, as they sample
//!   a few noisy edges);
//! - each projected box corner's distance to the mask's outline (a corner on the box's
//!   outline) or outside it (a corner inside), except corners that may be hidden (inside a
//!   touching mask or off the image);
//! - the sides' distance from the prior's mean, in the prior's sigmas (its square-root
//!   information: a track's belief may tie length and height together).
//!
//! The position's covariance is the inverse of the normal matrix of the measuring rows
//! (not those that only bound the box) at the solution: large
//! when little is seen, so a partly hidden road user is reported with its real accuracy
//! instead of being dropped. The same matrix, the prior taken out and the position
//! marginalised out, is what the mask alone says of the size ([`BoxFit::size_evidence`]),
//! which the track adds to its belief.

use super::calibrate::GroundCamera;
use super::class::{Extent, RoadUserClass};
use super::polygon::{signed_area, signed_distance_convex};
use super::size::{mat_vec, SizeBelief, SizeEvidence, M3};
use crate::ellipse::{floored, worst_sigma};

/// Weight of all the outline's vertices together, in box corners.
const OUTLINE_WEIGHT: f64 = 6.0;
/// A corner closer than this to a touching mask or the image border may be hidden, pixels.
const HIDDEN_MARGIN_PX: f64 = 2.0;
/// Outline vertices this close to the image border are not the road user's, pixels.
const BORDER_PX: f64 = 1.0;
const MAX_ITERATIONS: usize = 12;
/// Most outline vertices a fit compares.
const MAX_OUTLINE_VERTICES: usize = 16;
/// The fit stops when a step moves the box less than this, metres.
const CONVERGED_M: f64 = 1e-3;
/// Finite-difference step, metres.
const STEP_M: f64 = 1e-4;
/// Smallest side, metres.
const MIN_SIDE_M: f64 = 0.05;

/// What the fit is given.
#[derive(Debug, Clone, Copy)]
pub struct FitInput<'a> {
    /// The detection's class.
    pub class: RoadUserClass,
    /// The mask's convex hull, pixels.
    pub hull: &'a [[f64; 2]],
    /// Hulls of the masks touching it (any of them may hide part of it).
    pub touching: &'a [&'a [[f64; 2]]],
    /// Image `[width, height]`, pixels: corners beyond it are hidden.
    pub image_size: [f64; 2],
    /// Unit vector of the road's direction on the road (east, north): the box's length.
    pub axis: [f64; 2],
    /// Starting position, local metres.
    pub start: [f64; 2],
    /// What is known of its size: the class's prior ([`SizeBelief::prior`]), or its
    /// track's belief.
    pub size: SizeBelief,
    /// 1-sigma noise of the mask's outline, pixels (its camera's, [`super::noise`]): what
    /// the outline is weighed by against the size prior.
    pub outline_sigma_px: f64,
}

/// A fitted box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxFit {
    /// Centre of the footprint, local metres.
    pub centre: [f64; 2],
    /// Length, width and height, metres.
    pub extent: Extent,
    /// Covariance of the centre, m².
    pub covariance: [[f64; 2]; 2],
    /// Root mean square of the outline vertices' distances to the fitted box's outline
    /// (those along a touching mask count only their distance outside it), pixels.
    pub rms_px: f64,
    /// How many of the box's eight corners were checked against the mask (not hidden).
    pub corners_seen: usize,
    /// The sum of squared weighted residuals at the solution (outline, corners, prior).
    pub cost: f64,
    /// What the mask alone says of the size (the prior taken out, the position
    /// marginalised out), for the track's belief; `None` when it says nothing.
    pub size_evidence: Option<SizeEvidence>,
    /// The part of the position's covariance that comes from what is not known of the size
    /// (the prior's share: it repeats from frame to frame), m²; mostly along the line of
    /// sight.
    pub size_covariance: [[f64; 2]; 2],
}

impl BoxFit {
    /// 1-sigma along the centre's worst direction, metres.
    pub fn sigma_m(&self) -> f64 {
        worst_sigma(&self.covariance)
    }
}

/// Why no box was fitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FitFailure {
    /// The hull has fewer than three points.
    TooFewPoints,
    /// The box leaves the camera's field (a corner behind it) at the start.
    OffCamera,
    /// The normal matrix is singular (nothing is measured).
    Singular,
}

type P5 = [f64; 5];

/// A convex polygon ready for many signed distances (its orientation and bounding box
/// found once): the fit asks tens of thousands of them a frame.
struct Convex<'a> {
    vertices: &'a [[f64; 2]],
    sign: f64,
    lo: [f64; 2],
    hi: [f64; 2],
}

impl<'a> Convex<'a> {
    fn new(vertices: &'a [[f64; 2]]) -> Self {
        let sign = signed_area(vertices).signum();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for v in vertices {
            lo = [lo[0].min(v[0]), lo[1].min(v[1])];
            hi = [hi[0].max(v[0]), hi[1].max(v[1])];
        }
        Self {
            vertices,
            sign,
            lo,
            hi,
        }
    }

    /// Is `p` farther than `margin` outside the bounding box (so surely outside)?
    fn far_from(&self, p: [f64; 2], margin: f64) -> bool {
        p[0] < self.lo[0] - margin
            || p[1] < self.lo[1] - margin
            || p[0] > self.hi[0] + margin
            || p[1] > self.hi[1] + margin
    }

    /// Positive outside, negative inside (as [`signed_distance_convex`]).
    fn signed_distance(&self, p: [f64; 2]) -> f64 {
        let v = self.vertices;
        let n = v.len();
        if n < 3 {
            return f64::INFINITY;
        }
        let (mut inside, mut best) = (true, f64::INFINITY);
        for i in 0..n {
            let (a, b) = (v[i], v[(i + 1) % n]);
            let ab = [b[0] - a[0], b[1] - a[1]];
            let ap = [p[0] - a[0], p[1] - a[1]];
            if (ab[0] * ap[1] - ab[1] * ap[0]) * self.sign < 0.0 {
                inside = false;
            }
            let len2 = ab[0] * ab[0] + ab[1] * ab[1];
            let t = if len2 > 0.0 {
                ((ap[0] * ab[0] + ap[1] * ab[1]) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            best = best.min((ap[0] - t * ab[0]).powi(2) + (ap[1] - t * ab[1]).powi(2));
        }
        if inside {
            -best.sqrt()
        } else {
            best.sqrt()
        }
    }
}

/// The convex hull of eight points (monotone chain, no allocation): the points and count.
fn hull8(points: &[[f64; 2]; 8]) -> ([[f64; 2]; 16], usize) {
    let mut pts = *points;
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let turn = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let mut out = [[0.0; 2]; 16];
    let mut n = 0;
    for pass in 0..2 {
        let start = n;
        for k in 0..8 {
            let p = if pass == 0 { pts[k] } else { pts[7 - k] };
            while n >= start + 2 && turn(out[n - 2], out[n - 1], p) <= 0.0 {
                n -= 1;
            }
            out[n] = p;
            n += 1;
        }
        n -= 1;
    }
    (out, n)
}

/// Largest outward move of a vertex of [`rounded_out`], pixels (a sharp corner's mitre).
const MAX_ROUNDING_MOVE_PX: f64 = 2.0;

/// Where a mask's outline ([`super::outline`]) lies for a convex silhouette `ring`
/// (either orientation): each edge moved out by the rounding its hull keeps. The hull
/// rests on the outermost of the pixel-edge points along an edge; their offsets from a
/// slanted edge spread over half a pixel either way (times the normal's larger component)
/// once the edge crosses a whole pixel across its main axis, and less for an edge that
/// crosses less (an axis-aligned edge's points all share one rounding, on average none). So
/// the edge with extents `dx, dy` stands out by `0.5 max(|nx|, |ny|) min(1, |dx|, |dy|)`.
/// Returns the moved vertices (as many as `ring`'s, in order).
fn rounded_out(ring: &[[f64; 2]]) -> ([[f64; 2]; 16], usize) {
    let n = ring.len().min(16);
    let mut out = [[0.0; 2]; 16];
    if n < 3 {
        out[..n].copy_from_slice(&ring[..n]);
        return (out, n);
    }
    let orientation = signed_area(&ring[..n]).signum();
    // Each edge's outward unit normal and how far it moves.
    let edge = |i: usize| {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        if len < 1e-9 {
            return ([0.0, 0.0], 0.0);
        }
        let normal = [orientation * dy / len, -orientation * dx / len];
        let spread = dx.abs().min(dy.abs()).min(1.0);
        let excess = 0.5 * normal[0].abs().max(normal[1].abs()) * spread;
        (normal, excess)
    };
    for (i, o) in out[..n].iter_mut().enumerate() {
        let ((n1, d1), (n2, d2)) = (edge((i + n - 1) % n), edge(i));
        // x with x . n1 = d1 and x . n2 = d2.
        let det = n1[0] * n2[1] - n1[1] * n2[0];
        let mut x = if det.abs() > 1e-6 {
            [
                (d1 * n2[1] - d2 * n1[1]) / det,
                (n1[0] * d2 - n2[0] * d1) / det,
            ]
        } else {
            [n2[0] * d2, n2[1] * d2]
        };
        let len = x[0].hypot(x[1]);
        if len > MAX_ROUNDING_MOVE_PX {
            x = x.map(|v| v * MAX_ROUNDING_MOVE_PX / len);
        }
        *o = [ring[i][0] + x[0], ring[i][1] + x[1]];
    }
    (out, n)
}

struct Problem<'a> {
    input: FitInput<'a>,
    hull: Convex<'a>,
    touching: Vec<Convex<'a>>,
    cam: &'a GroundCamera,
    prior_mean: P5,
    /// `U` of the size belief: the prior's residuals are `U (size - mean)`.
    prior_root: M3,
    /// The mask's outline vertices, each with whether it lies along a touching mask (where
    /// the outline may be the other road user's edge: then it is only inside the box's).
    outline: Vec<([f64; 2], bool)>,
    outline_weight: f64,
    /// The outline's 1-sigma noise, pixels.
    sigma_px: f64,
}

impl<'a> Problem<'a> {
    fn new(input: FitInput<'a>, cam: &'a GroundCamera) -> Self {
        let belief = input
            .size
            .root()
            .map_or_else(|| SizeBelief::prior(input.class), |_| input.size);
        let [l, wd, ht] = belief.mean;
        let [w, h] = input.image_size;
        let b = BORDER_PX;
        // Every vertex of a long outline adds little (they sample a few edges): at most
        // MAX_OUTLINE_VERTICES, evenly spread, keep the fit's cost per mask bounded.
        let every = input.hull.len().div_ceil(MAX_OUTLINE_VERTICES).max(1);
        let outline: Vec<([f64; 2], bool)> = input
            .hull
            .iter()
            .step_by(every)
            .copied()
            .filter(|p| p[0] > b && p[1] > b && p[0] < w - b && p[1] < h - b)
            .map(|p| {
                let cut = input
                    .touching
                    .iter()
                    .any(|o| signed_distance_convex(p, o) < HIDDEN_MARGIN_PX);
                (p, cut)
            })
            .collect();
        Self {
            outline_weight: (OUTLINE_WEIGHT / outline.len().max(1) as f64).sqrt(),
            // A guard for any caller (the learnt noise is kept within its own range): a
            // noise under a tenth of a pixel would make the outline rows swamp the prior's
            // and the fit's steps; not finite, the default.
            sigma_px: if input.outline_sigma_px.is_finite() {
                input.outline_sigma_px.max(0.1)
            } else {
                super::noise::DEFAULT_PX
            },
            outline,
            hull: Convex::new(input.hull),
            touching: input.touching.iter().map(|t| Convex::new(t)).collect(),
            input,
            cam,
            prior_mean: [0.0, 0.0, l, wd, ht],
            prior_root: belief.root().unwrap_or([[0.0; 3]; 3]),
        }
    }

    fn corners(&self, t: &P5) -> Option<[[f64; 2]; 8]> {
        let [ux, uy] = self.input.axis;
        let (vx, vy) = (-uy, ux);
        let (hl, hw) = (t[2] / 2.0, t[3] / 2.0);
        let mut out = [[0.0; 2]; 8];
        let signs = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        for (k, (a, b)) in signs.iter().enumerate() {
            let g = [
                t[0] + a * hl * ux + b * hw * vx,
                t[1] + a * hl * uy + b * hw * vy,
            ];
            out[k] = self.cam.project([g[0], g[1], 0.0])?;
            out[k + 4] = self.cam.project([g[0], g[1], t[4]])?;
        }
        Some(out)
    }

    fn hidden(&self, p: [f64; 2]) -> bool {
        let [w, h] = self.input.image_size;
        let m = HIDDEN_MARGIN_PX;
        p[0] < m
            || p[1] < m
            || p[0] > w - m
            || p[1] > h - m
            || self
                .touching
                .iter()
                .any(|o| !o.far_from(p, m) && o.signed_distance(p) < m)
    }

    /// Which of the box's corners `px` may be hidden, which lie on its outline `ring`, and
    /// how far the mask's outline stands out at each of those.
    /// `grown` is `ring` moved out by [`rounded_out`], vertex for vertex.
    fn roles(&self, px: &[[f64; 2]; 8], ring: &[[f64; 2]], grown: &[[f64; 2]]) -> CornerRoles {
        let rounding = px.map(|p| {
            ring.iter()
                .position(|q| *q == p)
                .map_or([0.0, 0.0], |j| [grown[j][0] - p[0], grown[j][1] - p[1]])
        });
        CornerRoles {
            hidden: px.map(|p| self.hidden(p)),
            on_outline: px.map(|p| ring.contains(&p)),
            rounding,
        }
    }

    /// The corners' roles of the box at `t`.
    fn corner_roles(&self, t: &P5) -> Option<CornerRoles> {
        let px = self.corners(t)?;
        let (ring, n) = hull8(&px);
        let (grown, m) = rounded_out(&ring[..n]);
        Some(self.roles(&px, &ring[..n], &grown[..m]))
    }

    /// The weighted residuals (outline vertices, corners, prior), or `None` off camera, with
    /// each corner's role from `roles` (those of `t` itself when `None`: a derivative taken
    /// by moving the box a little keeps the roles of where it is taken, or a corner crossing
    /// a role's edge in the step would give a slope of its whole distance over the step).
    /// With `measured_only`, the one-sided rows (outline vertices along a touching mask,
    /// corners inside the box's outline) are zero: what bounds the box without measuring it
    /// does not make its covariance smaller.
    fn residuals(
        &self,
        t: &P5,
        out: &mut Vec<f64>,
        measured_only: bool,
        roles: Option<&CornerRoles>,
    ) -> Option<usize> {
        out.clear();
        let px = self.corners(t)?;
        let (ring, n) = hull8(&px);
        let (grown, m) = rounded_out(&ring[..n]);
        let outline = Convex::new(&grown[..m]);
        let own;
        let roles = match roles {
            Some(r) => r,
            None => {
                own = self.roles(&px, &ring[..n], &grown[..m]);
                &own
            }
        };
        let w = self.outline_weight / self.sigma_px;
        out.extend(self.outline.iter().map(|(o, cut)| {
            let d = outline.signed_distance(*o);
            match (*cut, measured_only) {
                (false, _) => w * d,
                (true, false) => w * d.max(0.0),
                (true, true) => 0.0,
            }
        }));
        let mut seen = 0;
        for (k, p) in px.into_iter().enumerate() {
            if roles.hidden[k] {
                out.push(0.0);
                continue;
            }
            seen += 1;
            // A corner on the box's outline lies on the mask's; one inside it only inside.
            // The mask's outline stands out of the box by its rounding: compared where the
            // outline would be.
            let [ox, oy] = roles.rounding[k];
            let d = self.hull.signed_distance([p[0] + ox, p[1] + oy]);
            let r = match (roles.on_outline[k], measured_only) {
                (true, _) => d,
                (false, false) => d.max(0.0),
                (false, true) => 0.0,
            };
            out.push(r / self.sigma_px);
        }
        let d: [f64; 3] = std::array::from_fn(|k| t[k + 2] - self.prior_mean[k + 2]);
        out.extend(mat_vec(&self.prior_root, &d));
        Some(seen)
    }
}

/// The roles of a box's eight corners at one place.
struct CornerRoles {
    /// May be hidden (inside a touching mask or off the image): not checked.
    hidden: [bool; 8],
    /// On the box's outline: on the mask's outline too.
    on_outline: [bool; 8],
    /// How far the mask's outline stands out at each corner on the box's outline (its
    /// rounding, [`rounded_out`]), pixels; zero for the others. Kept with the roles, so a
    /// corner joining or leaving the outline within a derivative's step does not jump.
    rounding: [[f64; 2]; 8],
}

fn norm2(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Solves `a x = b` (5x5, Gaussian elimination with partial pivoting).
fn solve(mut a: [P5; 5], mut b: P5) -> Option<P5> {
    for c in 0..5 {
        let p = (c..5).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() < 1e-12 {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        let pivot = a[c];
        for r in c + 1..5 {
            let f = a[r][c] / pivot[c];
            for (v, pv) in a[r][c..].iter_mut().zip(&pivot[c..]) {
                *v -= f * pv;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; 5];
    for c in (0..5).rev() {
        let s: f64 = (c + 1..5).map(|k| a[c][k] * x[k]).sum();
        x[c] = (b[c] - s) / a[c][c];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The normal matrix `J'J` and gradient `J'r` at `t` (forward differences).
fn normal_equations(p: &Problem<'_>, t: &P5, r: &[f64], measured_only: bool) -> ([P5; 5], P5) {
    let roles = p.corner_roles(t);
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(5);
    let mut moved = Vec::with_capacity(r.len());
    for k in 0..5 {
        let mut tk = *t;
        tk[k] += STEP_M;
        let col = match p.residuals(&tk, &mut moved, measured_only, roles.as_ref()) {
            Some(_) => moved.iter().zip(r).map(|(a, b)| (a - b) / STEP_M).collect(),
            None => vec![0.0; r.len()],
        };
        cols.push(col);
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let a = std::array::from_fn(|i| std::array::from_fn(|j| dot(&cols[i], &cols[j])));
    let g = std::array::from_fn(|i| dot(&cols[i], r));
    (a, g)
}

/// Fits the box of one detection (see the module's documentation).
pub fn fit(input: FitInput<'_>, cam: &GroundCamera) -> Result<BoxFit, FitFailure> {
    if input.hull.len() < 3 {
        return Err(FitFailure::TooFewPoints);
    }
    let problem = Problem::new(input, cam);
    let mut t = problem.prior_mean;
    (t[0], t[1]) = (input.start[0], input.start[1]);
    let mut r = Vec::new();
    problem
        .residuals(&t, &mut r, false, None)
        .ok_or(FitFailure::OffCamera)?;
    let mut cost = norm2(&r);
    let mut lambda = 1e-3;
    let mut trial = Vec::with_capacity(r.len());
    for _ in 0..MAX_ITERATIONS {
        let (a, g) = normal_equations(&problem, &t, &r, false);
        let mut step_taken = None;
        while lambda < 1e8 {
            let damped = std::array::from_fn(|i| {
                std::array::from_fn(|j| {
                    a[i][j] + if i == j { lambda * a[i][i] + 1e-9 } else { 0.0 }
                })
            });
            let Some(d) = solve(damped, g.map(|v| -v)) else {
                lambda *= 10.0;
                continue;
            };
            let mut next = t;
            for k in 0..5 {
                next[k] += d[k];
            }
            for v in &mut next[2..] {
                *v = v.max(MIN_SIDE_M);
            }
            if problem.residuals(&next, &mut trial, false, None).is_some() && norm2(&trial) < cost {
                let gain = (cost - norm2(&trial)) / cost.max(1e-12);
                // A step that moves the box by a millimetre or gains nothing ends the fit.
                let size = d.iter().map(|v| v * v).sum::<f64>().sqrt().min(gain * 10.0);
                t = next;
                std::mem::swap(&mut r, &mut trial);
                cost = norm2(&r);
                lambda = (lambda / 4.0).max(1e-7);
                step_taken = Some(size);
                break;
            }
            lambda *= 4.0;
        }
        match step_taken {
            Some(size) if size > CONVERGED_M => {}
            _ => break,
        }
    }
    finish(&problem, &t, &r)
}

/// The fitted box at `t` with its covariance.
fn finish(problem: &Problem<'_>, t: &P5, r: &[f64]) -> Result<BoxFit, FitFailure> {
    let mut measured = Vec::new();
    problem
        .residuals(t, &mut measured, true, None)
        .ok_or(FitFailure::OffCamera)?;
    let (a, g) = normal_equations(problem, t, &measured, true);
    let mut cov = [[0.0; 2]; 2];
    for (j, col) in cov.iter_mut().enumerate() {
        let mut e = [0.0; 5];
        e[j] = 1.0;
        let x = solve(a, e).ok_or(FitFailure::Singular)?;
        *col = [x[0], x[1]];
    }
    let known = inverse2([[a[0][0], a[0][1]], [a[1][0], a[1][1]]]);
    let mut scratch = Vec::new();
    let corners_seen = problem
        .residuals(t, &mut scratch, false, None)
        .ok_or(FitFailure::OffCamera)?;
    let n = problem.outline.len();
    let rms_px = if n == 0 {
        0.0
    } else {
        (norm2(&r[..n]) / n as f64).sqrt() / problem.outline_weight * problem.sigma_px
    };
    Ok(BoxFit {
        centre: [t[0], t[1]],
        extent: Extent {
            length_m: t[2],
            width_m: t[3],
            height_m: t[4],
        },
        covariance: cov,
        rms_px,
        corners_seen,
        cost: norm2(r),
        size_covariance: known.map_or([[0.0; 2]; 2], |k| size_share(&cov, &k)),
        size_evidence: known.and_then(|k| size_evidence(problem, &a, &g, &k, t)),
    })
}

/// The inverse of a 2x2 matrix, `None` when it is singular.
fn inverse2(m: [[f64; 2]; 2]) -> Option<[[f64; 2]; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    (det.abs() > 1e-12 && det.is_finite()).then(|| {
        [
            [m[1][1] / det, -m[0][1] / det],
            [-m[1][0] / det, m[0][0] / det],
        ]
    })
}

/// The part of the position's error that comes from what is not known of the size: the
/// position's covariance `cov` less the one it would have were the size known exactly
/// (`known`, the inverse of the position block), symmetric and with no negative variance
/// (rounding), m².
fn size_share(cov: &[[f64; 2]; 2], known: &[[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let d = |i: usize, j: usize| cov[i][j] - known[i][j];
    floored(&[[d(0, 0), d(0, 1)], [d(1, 0), d(1, 1)]], 0.0)
}

/// What the mask alone says of the size at `t`, from the normal matrix `a` and gradient `g`
/// of the measuring rows and the prior (`inv` the inverse of `a`'s position block): the
/// prior's information `U'U` taken out of the size block and its gradient `U'U (s - mean)`
/// out of the size gradient, the position marginalised out. `S` is the Schur complement;
/// the size the mask says, `s_mask`, is one Gauss-Newton step from `s` on the mask's rows
/// alone, so `S s_mask = S s - (g_s - A_sp inv g_p)` whether or not the fit stopped at its
/// exact optimum. `None` when the mask says nothing of the size.
#[allow(clippy::needless_range_loop)] // matrix arithmetic reads as its formulas with indices
fn size_evidence(
    problem: &Problem<'_>,
    a: &[P5; 5],
    g: &P5,
    inv: &[[f64; 2]; 2],
    t: &P5,
) -> Option<SizeEvidence> {
    let u = &problem.prior_root;
    let prior: M3 =
        std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| u[k][i] * u[k][j]).sum()));
    let mut s: M3 = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let cross: f64 = (0..2)
                .flat_map(|p| (0..2).map(move |q| (p, q)))
                .map(|(p, q)| a[i + 2][p] * inv[p][q] * a[q][j + 2])
                .sum();
            a[i + 2][j + 2] - prior[i][j] - cross
        })
    });
    // Symmetric, and no side with negative information (rounding of a side not measured).
    for i in 0..3 {
        for j in 0..i {
            let m = 0.5 * (s[i][j] + s[j][i]);
            (s[i][j], s[j][i]) = (m, m);
        }
        if s[i][i] <= 0.0 {
            for j in 0..3 {
                (s[i][j], s[j][i]) = (0.0, 0.0);
            }
        }
    }
    let size = [t[2], t[3], t[4]];
    let off: [f64; 3] = std::array::from_fn(|k| size[k] - problem.prior_mean[k + 2]);
    let prior_pull = mat_vec(&prior, &off);
    let ss = mat_vec(&s, &size);
    // The mask's own gradient on the size, the position marginalised out.
    let through: [f64; 2] = std::array::from_fn(|p| (0..2).map(|q| inv[p][q] * g[q]).sum());
    let mut vector: [f64; 3] = std::array::from_fn(|i| {
        let across: f64 = (0..2).map(|p| a[i + 2][p] * through[p]).sum();
        ss[i] - (g[i + 2] - prior_pull[i] - across)
    });
    // A side with no information has no vector either.
    for (v, row) in vector.iter_mut().zip(&s) {
        if row.iter().all(|x| *x == 0.0) {
            *v = 0.0;
        }
    }
    let e = SizeEvidence {
        information: s,
        vector,
    };
    let trace: f64 = (0..3).map(|k| e.information[k][k]).sum();
    (e.is_finite() && trace > 0.0).then_some(e)
}

#[cfg(test)]
mod tests;
