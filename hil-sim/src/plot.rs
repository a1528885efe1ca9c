//! Report plots of a hardware-in-the-loop drive, written as SVG and PNG.
//!
//! [`write_plots`] draws three figures from the recorded drive joined with the simulated truth:
//!
//! - `speed_alert`: the speed the OBU shows and the limit it shows (a step line) against the true
//!   distance before the zone start, with the zone state as coloured bands, the primary alert as
//!   coloured dots, and vertical lines at the zone start and the warning distance.
//! - `trajectory`: the lane map (bands with edges, ids labelled), the closed-lane pieces in red
//!   and the true trajectory coloured by zone state, in metres with equal axis scales. When the
//!   drive is long and narrow it is drawn along the road against the lateral offset instead, with
//!   the lateral scale exaggerated (the axis labels say so).
//! - `lanes`: the lane the OBU matched and the true lane over time, with the spans where the OBU
//!   had no lane shaded.
//!
//! Text in the PNGs needs a TrueType font: the file named by [`FONT_ENV`], else the first of
//! [`FONT_PATHS`] that exists, is loaded once per process and kept for its lifetime. Without one
//! the PNGs are still written, without any text ([`png_text_available`]). SVG text names the
//! `sans-serif` family and needs no font file.
//!
//! Panic contract: no input makes these functions panic. Non-finite (or absurdly large) values
//! and missing distances are skipped, and a figure with nothing to draw says "no data".

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One recorded state of the drive, joined with the simulated truth.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrackPoint {
    /// Seconds since the drive started.
    pub t_s: f64,
    /// True position, east/north metres in the road's local frame.
    pub true_point: [f64; 2],
    /// Lane the car really drives in.
    pub true_lane: u8,
    /// True distance along the road to the (first) zone start, negative inside the zone.
    pub true_distance_m: Option<f64>,
    /// Speed the OBU shows (m/s).
    pub speed_mps: Option<f64>,
    /// Limit the OBU shows (m/s).
    pub limit_mps: Option<f64>,
    /// Zone state the OBU shows: "None", "Approaching", "Warning", "InZone" or "Leaving".
    pub zone_state: String,
    /// Primary alert kind, e.g. "ReducedSpeedAhead", "LaneClosedOwn", "Overspeed", "GnssStale".
    pub primary: Option<String>,
    /// Lane the OBU matched, `None` when it had none.
    pub matched_lane: Option<u8>,
}

/// A lane of the map: id, centreline (east/north m), width (m).
#[derive(Debug, Clone, PartialEq)]
pub struct PlotLane {
    /// Lane id as in the MAP.
    pub id: u8,
    /// Centreline points, east/north metres in the road's local frame.
    pub centre: Vec<[f64; 2]>,
    /// Lane width in metres.
    pub width_m: f64,
}

/// What to draw.
#[derive(Debug, Clone, Copy)]
pub struct PlotInput<'a> {
    /// Title put above every figure.
    pub title: &'a str,
    /// The drive, in time order.
    pub track: &'a [TrackPoint],
    /// The lane map.
    pub lanes: &'a [PlotLane],
    /// Closed-lane centreline pieces, east/north metres.
    pub zones: &'a [Vec<[f64; 2]>],
    /// Distance before the zone start at which the OBU should warn, if known.
    pub warning_distance_m: Option<f64>,
}

/// Environment variable naming a TTF/OTF file to use for text in PNGs (tried first).
pub const FONT_ENV: &str = "HIL_SIM_PLOT_FONT";

/// Font files tried, in order, for text in PNGs.
pub const FONT_PATHS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/liberation2/LiberationSans-Regular.ttf",
    "/usr/share/fonts/liberation-sans/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/freefont/FreeSans.ttf",
    "/usr/share/fonts/noto/NotoSans-Regular.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// Writes `speed_alert`, `trajectory` and `lanes`, each as `.svg` and `.png`, into `dir`
/// (created if missing) and returns the paths written.
///
/// The PNGs carry no text when no font was found (see [`png_text_available`]).
pub fn write_plots(dir: &Path, input: &PlotInput<'_>) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let png_ink = Ink::png();
    let mut written = Vec::with_capacity(6);
    for figure in [Figure::Speed, Figure::Trajectory, Figure::Lanes] {
        let svg = dir.join(format!("{}.svg", figure.stem()));
        write_svg(&svg, figure, input)?;
        written.push(svg);
        let png = dir.join(format!("{}.png", figure.stem()));
        write_png(&png, figure, input, png_ink)?;
        written.push(png);
    }
    Ok(written)
}

fn write_svg(path: &Path, figure: Figure, input: &PlotInput<'_>) -> Result<(), String> {
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    render(&root, figure, input, Ink::svg()).map_err(|e| format!("{}: {e}", path.display()))
}

fn write_png(path: &Path, figure: Figure, input: &PlotInput<'_>, ink: Ink) -> Result<(), String> {
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    render(&root, figure, input, ink).map_err(|e| format!("{}: {e}", path.display()))
}

/// Whether a font for the text in PNGs was found (loaded on the first call, once per process).
pub fn png_text_available() -> bool {
    static LOADED: OnceLock<bool> = OnceLock::new();
    *LOADED.get_or_init(load_font)
}

fn load_font() -> bool {
    let from_env = std::env::var_os(FONT_ENV).map(PathBuf::from);
    let candidates = from_env
        .into_iter()
        .chain(FONT_PATHS.iter().map(PathBuf::from));
    candidates.into_iter().any(|path| register(&path))
}

/// Registers the font file at `path` as `sans-serif`. The bytes are leaked on purpose: the
/// font table needs them for the rest of the process, and this runs at most once per file.
fn register(path: &Path) -> bool {
    let Ok(bytes) = std::fs::read(path) else {
        return false;
    };
    let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    plotters::style::register_font(FONT_FAMILY, FontStyle::Normal, bytes).is_ok()
}

// ---------------------------------------------------------------------------------------------
// Layout, text and colours

const SIZE: (u32, u32) = (1200, 700);
const LEGEND_W: u32 = 250;
const TITLE_H: u32 = 44;
const PAD: u32 = 16;
const X_LABEL_H: u32 = 56;
const Y_LABEL_W: u32 = 80;
const FONT_FAMILY: &str = "sans-serif";
/// Ratio of the drive's length to its width above which the trajectory is drawn along the road.
const EXTREME_ASPECT: f64 = 6.0;

type DrawResult<T, DB> = Result<T, DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;
type Xy = (f64, f64);
/// The chart column and the legend column of a figure.
type Columns<DB> = (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>);

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Figure {
    Speed,
    Trajectory,
    Lanes,
}

impl Figure {
    fn stem(self) -> &'static str {
        match self {
            Figure::Speed => "speed_alert",
            Figure::Trajectory => "trajectory",
            Figure::Lanes => "lanes",
        }
    }
}

/// How text is drawn on one backend: the font family, and whether text is drawn at all.
/// Without text every style is transparent, which both backends skip before any font lookup.
#[derive(Debug, Clone, Copy)]
struct Ink {
    family: &'static str,
    text: bool,
}

impl Ink {
    fn svg() -> Self {
        Ink {
            family: FONT_FAMILY,
            text: true,
        }
    }

    fn png() -> Self {
        Ink {
            family: FONT_FAMILY,
            text: png_text_available(),
        }
    }

    fn style(self, size: u32, color: RGBColor) -> TextStyle<'static> {
        let font = FontDesc::new(self.family.into(), f64::from(size), FontStyle::Normal);
        if self.text {
            font.color(&color)
        } else {
            font.color(&TRANSPARENT)
        }
    }

    fn at(self, size: u32, h: HPos, v: VPos) -> TextStyle<'static> {
        self.style(size, BLACK).pos(Pos::new(h, v))
    }
}

fn render<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figure: Figure,
    input: &PlotInput<'_>,
    ink: Ink,
) -> DrawResult<(), DB> {
    root.fill(&WHITE)?;
    match figure {
        Figure::Speed => draw_speed(root, input, ink)?,
        Figure::Trajectory => draw_trajectory(root, input, ink)?,
        Figure::Lanes => draw_lanes(root, input, ink)?,
    }
    root.present()
}

/// "title: what", or just "what" without a title.
fn heading(title: &str, what: &str) -> String {
    if title.trim().is_empty() {
        what.to_string()
    } else {
        format!("{title}: {what}")
    }
}

/// Draws the title and splits the rest into the chart column and the legend column.
fn layout<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    ink: Ink,
    title: &str,
) -> DrawResult<Columns<DB>, DB> {
    let (w, _) = root.dim_in_pixel();
    let style = ink.at(22, HPos::Center, VPos::Top);
    root.draw_text(title, &style, (w as i32 / 2, 12))?;
    let body = root.margin(TITLE_H, 0, 0, 0);
    Ok(body.split_horizontally(w.saturating_sub(LEGEND_W)))
}

/// Pixel size of the plotting area that [`chart`] builds in `area`.
fn plot_pixels<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>) -> Xy {
    let (w, h) = area.dim_in_pixel();
    let w = w.saturating_sub(2 * PAD + Y_LABEL_W).max(1);
    let h = h.saturating_sub(2 * PAD + X_LABEL_H).max(1);
    (f64::from(w), f64::from(h))
}

fn chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    x: Span,
    y: Span,
) -> DrawResult<Chart<'a, DB>, DB> {
    ChartBuilder::on(area)
        .margin(PAD)
        .x_label_area_size(X_LABEL_H)
        .y_label_area_size(Y_LABEL_W)
        .build_cartesian_2d(x.range(), y.range())
}

fn mesh<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    ink: Ink,
    desc: (&str, &str),
    x_fmt: &dyn Fn(&f64) -> String,
) -> DrawResult<(), DB> {
    chart
        .configure_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .label_style(ink.style(13, BLACK))
        .axis_desc_style(ink.style(16, BLACK))
        .x_desc(desc.0)
        .y_desc(desc.1)
        .x_label_formatter(x_fmt)
        .y_label_formatter(&|v| number(*v))
        .draw()
}

fn no_data<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, ink: Ink) -> DrawResult<(), DB> {
    let (w, h) = area.dim_in_pixel();
    let style = ink.at(20, HPos::Center, VPos::Center);
    area.draw_text("no data", &style, (w as i32 / 2, h as i32 / 2))
}

/// An axis label for a number of metres, seconds or km/h, without "-0".
fn number(v: f64) -> String {
    let text = if v.abs() >= 10.0 || v.fract() == 0.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.1}")
    };
    match text.as_str() {
        "-0" | "-0.0" => "0".to_string(),
        _ => text,
    }
}

const ZONE_STATES: [&str; 5] = ["None", "Approaching", "Warning", "InZone", "Leaving"];
const START_RED: RGBColor = RGBColor(214, 39, 40);
const WARN_AMBER: RGBColor = RGBColor(255, 170, 0);
const LIMIT_PURPLE: RGBColor = RGBColor(118, 42, 131);
const KIND_COLORS: [RGBColor; 8] = [
    RGBColor(204, 0, 204),
    RGBColor(140, 86, 75),
    RGBColor(0, 128, 128),
    RGBColor(23, 43, 110),
    RGBColor(128, 128, 0),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
    RGBColor(200, 82, 0),
];

fn state_color(state: &str) -> RGBColor {
    match state {
        "None" => RGBColor(150, 150, 150),
        "Approaching" => RGBColor(31, 119, 180),
        "Warning" => WARN_AMBER,
        "InZone" => START_RED,
        "Leaving" => RGBColor(44, 160, 44),
        _ => RGBColor(148, 103, 189),
    }
}

/// The zone states to list in a legend: the five known ones, then any other seen in the track.
fn legend_states(track: &[TrackPoint]) -> Vec<&str> {
    let mut states = ZONE_STATES.to_vec();
    for p in track {
        if !states.contains(&p.zone_state.as_str()) {
            states.push(&p.zone_state);
        }
    }
    states
}

// ---------------------------------------------------------------------------------------------
// Legend

enum Swatch {
    Heading,
    Line(RGBColor),
    Dashed(RGBColor),
    Band(RGBAColor),
    Dot(RGBColor),
}

struct Entry {
    swatch: Swatch,
    label: String,
}

impl Entry {
    fn new(swatch: Swatch, label: impl Into<String>) -> Self {
        Entry {
            swatch,
            label: label.into(),
        }
    }
}

fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    ink: Ink,
    entries: &[Entry],
) -> DrawResult<(), DB> {
    let style = ink.at(14, HPos::Left, VPos::Center);
    for (i, entry) in entries.iter().enumerate() {
        let y = 30 + 22 * i as i32;
        draw_swatch(area, &entry.swatch, y)?;
        let x = if matches!(entry.swatch, Swatch::Heading) {
            6
        } else {
            40
        };
        area.draw_text(&entry.label, &style, (x, y))?;
    }
    Ok(())
}

fn draw_swatch<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    swatch: &Swatch,
    y: i32,
) -> DrawResult<(), DB> {
    match swatch {
        Swatch::Heading => Ok(()),
        Swatch::Line(c) => area.draw(&PathElement::new(vec![(8, y), (32, y)], c.stroke_width(3))),
        Swatch::Dashed(c) => {
            let dashes = [(8, 14), (19, 25), (30, 32)].map(|(a, b)| vec![(a, y), (b, y)]);
            dashes
                .into_iter()
                .try_for_each(|d| area.draw(&PathElement::new(d, c.stroke_width(2))))
        }
        Swatch::Band(c) => area.draw(&Rectangle::new([(8, y - 7), (32, y + 7)], c.filled())),
        Swatch::Dot(c) => area.draw(&Circle::new((20, y), 5, c.filled())),
    }
}

// ---------------------------------------------------------------------------------------------
// Numbers, spans and runs

/// `v` if it is a usable coordinate (finite and not absurdly large).
fn ok(v: f64) -> Option<f64> {
    (v.is_finite() && v.abs() < 1e9).then_some(v)
}

fn ok_point(p: [f64; 2]) -> Option<[f64; 2]> {
    Some([ok(p[0])?, ok(p[1])?])
}

/// A closed interval of one axis.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Span {
    lo: f64,
    hi: f64,
}

impl Span {
    /// The smallest span holding the usable values, `None` when there are none.
    fn of(values: impl IntoIterator<Item = f64>) -> Option<Span> {
        values.into_iter().filter_map(ok).fold(None, |span, v| {
            Some(span.map_or(Span { lo: v, hi: v }, |s: Span| s.include(v)))
        })
    }

    fn include(self, v: f64) -> Span {
        Span {
            lo: self.lo.min(v),
            hi: self.hi.max(v),
        }
    }

    fn union(self, other: Option<Span>) -> Span {
        other.map_or(self, |o| self.include(o.lo).include(o.hi))
    }

    fn len(self) -> f64 {
        self.hi - self.lo
    }

    /// Widens each side by `frac` of the length, and by at least `min`.
    fn pad(self, frac: f64, min: f64) -> Span {
        let d = (self.len() * frac).max(min);
        Span {
            lo: self.lo - d,
            hi: self.hi + d,
        }
    }

    /// The span of length `len` with the same centre.
    fn centred(self, len: f64) -> Span {
        let c = 0.5 * (self.lo + self.hi);
        Span {
            lo: c - 0.5 * len,
            hi: c + 0.5 * len,
        }
    }

    /// The plotting range; a broken span (non-finite or empty) becomes 0..1.
    fn range(self) -> std::ops::Range<f64> {
        if self.lo.is_finite() && self.hi.is_finite() && self.hi > self.lo {
            self.lo..self.hi
        } else {
            0.0..1.0
        }
    }
}

/// Splits `(x, key)` samples into runs of equal keys: `(x_start, x_end, key)`, each run ending
/// where the next begins.
fn runs<K: PartialEq + Copy>(samples: &[(f64, K)]) -> Vec<(f64, f64, K)> {
    let mut out: Vec<(f64, f64, K)> = Vec::new();
    for &(x, key) in samples {
        if let Some(last) = out.last_mut() {
            last.1 = x;
            if last.2 == key {
                continue;
            }
        }
        out.push((x, x, key));
    }
    out
}

/// Step-line pieces: each value holds until the next sample; a missing value breaks the line.
fn step_lines(samples: &[(f64, Option<f64>)]) -> Vec<Vec<Xy>> {
    let mut lines = Vec::new();
    let mut current = Vec::new();
    for (i, &(x, value)) in samples.iter().enumerate() {
        let Some(v) = value else {
            flush(&mut lines, &mut current);
            continue;
        };
        current.push((x, v));
        if let Some(&(next_x, _)) = samples.get(i + 1) {
            current.push((next_x, v));
        }
    }
    flush(&mut lines, &mut current);
    lines
}

/// Polyline pieces joining consecutive samples; a missing value breaks the line.
fn plain_lines(samples: &[(f64, Option<f64>)]) -> Vec<Vec<Xy>> {
    let mut lines = Vec::new();
    let mut current = Vec::new();
    for &(x, value) in samples {
        match value {
            Some(v) => current.push((x, v)),
            None => flush(&mut lines, &mut current),
        }
    }
    flush(&mut lines, &mut current);
    lines
}

fn flush(lines: &mut Vec<Vec<Xy>>, current: &mut Vec<Xy>) {
    if !current.is_empty() {
        lines.push(std::mem::take(current));
    }
}

fn draw_lines<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    lines: Vec<Vec<Xy>>,
    style: ShapeStyle,
) -> DrawResult<(), DB> {
    for line in lines {
        if line.len() == 1 {
            chart.draw_series(std::iter::once(Circle::new(line[0], 2, style.filled())))?;
        } else {
            chart.draw_series(LineSeries::new(line, style))?;
        }
    }
    Ok(())
}

/// Full-height bands of `(x_start, x_end, colour)`.
fn draw_bands<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    bands: impl IntoIterator<Item = (f64, f64, RGBAColor)>,
    y: Span,
) -> DrawResult<(), DB> {
    let rects = bands
        .into_iter()
        .filter(|b| b.1 > b.0)
        .map(|(x0, x1, c)| Rectangle::new([(x0, y.lo), (x1, y.hi)], c.filled()));
    chart.draw_series(rects)?;
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Speed and alerts against the distance before the zone

/// One drawable sample: x = position relative to the zone start (= minus the true distance),
/// so that the car moves left to right.
struct SpeedSample<'a> {
    x: f64,
    speed_kmh: Option<f64>,
    limit_kmh: Option<f64>,
    state: &'a str,
    primary: Option<&'a str>,
}

fn speed_sample(p: &TrackPoint) -> Option<SpeedSample<'_>> {
    let kmh = |v: Option<f64>| v.and_then(ok).map(|v| v * 3.6);
    Some(SpeedSample {
        x: -ok(p.true_distance_m?)?,
        speed_kmh: kmh(p.speed_mps),
        limit_kmh: kmh(p.limit_mps),
        state: &p.zone_state,
        primary: p.primary.as_deref(),
    })
}

/// Primary alert kinds in order of first appearance (their colour is their index).
fn alert_kinds(track: &[TrackPoint]) -> Vec<&str> {
    let mut kinds: Vec<&str> = Vec::new();
    for kind in track.iter().filter_map(|p| p.primary.as_deref()) {
        if !kinds.contains(&kind) {
            kinds.push(kind);
        }
    }
    kinds
}

fn kind_color(kinds: &[&str], kind: &str) -> RGBColor {
    let i = kinds.iter().position(|k| *k == kind).unwrap_or(0);
    KIND_COLORS[i % KIND_COLORS.len()]
}

fn draw_speed<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    input: &PlotInput<'_>,
    ink: Ink,
) -> DrawResult<(), DB> {
    let (main, side) = layout(root, ink, &heading(input.title, "speed and alerts"))?;
    let samples: Vec<_> = input.track.iter().filter_map(speed_sample).collect();
    let warning = input.warning_distance_m.and_then(ok);
    let x = Span { lo: 0.0, hi: 0.0 }.union(Span::of(samples.iter().map(|s| s.x)));
    let x = x.union(Span::of(warning.map(|w| -w))).pad(0.03, 5.0);
    let values = samples
        .iter()
        .flat_map(|s| [s.speed_kmh, s.limit_kmh])
        .flatten();
    let top = Span::of(values).map_or(10.0, |s| s.hi.max(10.0));
    let y = Span {
        lo: 0.0,
        hi: top * 1.12,
    };
    let mut chart = chart(&main, x, y)?;
    let state_runs = runs(&samples.iter().map(|s| (s.x, s.state)).collect::<Vec<_>>());
    let bands = state_runs
        .into_iter()
        .map(|(a, b, s)| (a, b, state_color(s).mix(0.18)));
    draw_bands(&mut chart, bands, y)?;
    let desc = (
        "distance before the zone start (m, negative = inside the zone)",
        "speed (km/h)",
    );
    mesh(&mut chart, ink, desc, &|v| number(-v))?;
    draw_marks(&mut chart, ink, y, warning)?;
    draw_speed_lines(&mut chart, &samples)?;
    draw_alert_dots(&mut chart, &samples, &alert_kinds(input.track), x)?;
    if samples.iter().all(|s| s.speed_kmh.is_none()) {
        no_data(&main, ink)?;
    }
    draw_legend(&side, ink, &speed_legend(input.track, warning.is_some()))
}

/// Vertical lines at the zone start and at the warning distance.
fn draw_marks<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    ink: Ink,
    y: Span,
    warning: Option<f64>,
) -> DrawResult<(), DB> {
    let marks = [
        Some((0.0, START_RED, "zone start")),
        warning.map(|w| (-w, WARN_AMBER, "warning")),
    ];
    for (x, color, label) in marks.into_iter().flatten() {
        let line = vec![(x, y.lo), (x, y.hi)];
        chart.draw_series(DashedLineSeries::new(line, 8, 5, color.stroke_width(2)))?;
        let style = ink.style(13, color).pos(Pos::new(HPos::Left, VPos::Top));
        chart
            .plotting_area()
            .draw(&Text::new(label, (x, y.hi), style))?;
    }
    Ok(())
}

fn draw_speed_lines<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    samples: &[SpeedSample<'_>],
) -> DrawResult<(), DB> {
    let limit: Vec<_> = samples.iter().map(|s| (s.x, s.limit_kmh)).collect();
    draw_lines(chart, step_lines(&limit), LIMIT_PURPLE.stroke_width(2))?;
    let speed: Vec<_> = samples.iter().map(|s| (s.x, s.speed_kmh)).collect();
    draw_lines(chart, plain_lines(&speed), BLACK.stroke_width(2))
}

/// Dots on the speed curve (or on the axis when the speed is missing) coloured by the primary
/// alert, thinned to about one per 1/150 of the axis per kind.
fn draw_alert_dots<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    samples: &[SpeedSample<'_>],
    kinds: &[&str],
    x: Span,
) -> DrawResult<(), DB> {
    let gap = x.len() / 150.0;
    let mut last: Option<(f64, &str)> = None;
    for s in samples {
        let Some(kind) = s.primary else { continue };
        if last.is_some_and(|(lx, lk)| lk == kind && (s.x - lx).abs() < gap) {
            continue;
        }
        last = Some((s.x, kind));
        let at = (s.x, s.speed_kmh.unwrap_or(0.0));
        let dot = Circle::new(at, 4, kind_color(kinds, kind).filled());
        chart.draw_series(std::iter::once(dot))?;
    }
    Ok(())
}

fn speed_legend(track: &[TrackPoint], warning: bool) -> Vec<Entry> {
    let mut entries = vec![
        Entry::new(Swatch::Line(BLACK), "speed shown by the OBU"),
        Entry::new(Swatch::Line(LIMIT_PURPLE), "limit shown by the OBU"),
        Entry::new(Swatch::Dashed(START_RED), "zone start"),
    ];
    if warning {
        entries.push(Entry::new(Swatch::Dashed(WARN_AMBER), "warning distance"));
    }
    entries.push(Entry::new(Swatch::Heading, "zone state (bands)"));
    for state in legend_states(track) {
        entries.push(Entry::new(
            Swatch::Band(state_color(state).mix(0.35)),
            state,
        ));
    }
    entries.push(Entry::new(Swatch::Heading, "primary alert (dots)"));
    let kinds = alert_kinds(track);
    for kind in &kinds {
        entries.push(Entry::new(Swatch::Dot(kind_color(&kinds, kind)), *kind));
    }
    if kinds.is_empty() {
        entries.push(Entry::new(Swatch::Heading, "  (none)"));
    }
    entries
}

// ---------------------------------------------------------------------------------------------
// Trajectory over the lane map

/// How map coordinates become plot coordinates: east/north as they are, or rotated into the
/// drive's main direction (along, lateral with left positive) from `origin`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct View {
    origin: [f64; 2],
    axis: Option<[f64; 2]>,
}

impl View {
    const PLAIN: View = View {
        origin: [0.0, 0.0],
        axis: None,
    };

    fn map(&self, p: [f64; 2]) -> Xy {
        let Some(u) = self.axis else {
            return (p[0], p[1]);
        };
        let d = [p[0] - self.origin[0], p[1] - self.origin[1]];
        (d[0] * u[0] + d[1] * u[1], d[1] * u[0] - d[0] * u[1])
    }
}

/// The principal direction of `points`, pointing from the first toward the last.
fn main_axis(points: &[[f64; 2]]) -> Option<[f64; 2]> {
    let (first, last) = (points.first()?, points.last()?);
    let n = points.len() as f64;
    let mean = points
        .iter()
        .fold([0.0, 0.0], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for p in points {
        let (dx, dy) = (p[0] - mean[0], p[1] - mean[1]);
        (sxx, syy, sxy) = (sxx + dx * dx, syy + dy * dy, sxy + dx * dy);
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let u = [angle.cos(), angle.sin()];
    let forward = (last[0] - first[0]) * u[0] + (last[1] - first[1]) * u[1] >= 0.0;
    Some(if forward { u } else { [-u[0], -u[1]] })
}

/// Rotates into the road direction `road` (else the points' main direction) when the points
/// are much longer than wide (`margin` is added to the width on each side).
fn choose_view(points: &[[f64; 2]], road: Option<[f64; 2]>, margin: f64) -> View {
    let (Some(axis), Some(&origin)) = (main_axis(points), points.first()) else {
        return View::PLAIN;
    };
    let axis = road.map_or(axis, |r| {
        let forward = r[0] * axis[0] + r[1] * axis[1] >= 0.0;
        if forward {
            r
        } else {
            [-r[0], -r[1]]
        }
    });
    let view = View {
        origin,
        axis: Some(axis),
    };
    let mapped: Vec<Xy> = points.iter().map(|&p| view.map(p)).collect();
    let along = Span::of(mapped.iter().map(|p| p.0)).map_or(0.0, Span::len);
    let lateral = Span::of(mapped.iter().map(|p| p.1)).map_or(0.0, Span::len);
    if along > EXTREME_ASPECT * (lateral + 2.0 * margin) {
        view
    } else {
        View::PLAIN
    }
}

/// The length-weighted mean direction (undirected) of the lane centreline segments that cross
/// the box `x` × `y`, or of all of them when none does; `None` without lanes.
fn road_axis(shapes: &MapShapes, x: Span, y: Span) -> Option<[f64; 2]> {
    let segments = || shapes.lanes.iter().flat_map(|l| l.1.centre.windows(2));
    let sum = |near: bool| {
        let crossing = |w: &&[[f64; 2]]| !near || clip_segment(pt(w[0]), pt(w[1]), x, y).is_some();
        let doubled = segments().filter(crossing).map(|w| {
            let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
            let angle = 2.0 * dy.atan2(dx);
            let len = dx.hypot(dy);
            [len * angle.cos(), len * angle.sin()]
        });
        unit(doubled.fold([0.0, 0.0], |s, v| [s[0] + v[0], s[1] + v[1]]))
    };
    let mean = sum(true).or_else(|| sum(false))?;
    let angle = 0.5 * mean[1].atan2(mean[0]);
    Some([angle.cos(), angle.sin()])
}

fn pt(p: [f64; 2]) -> Xy {
    (p[0], p[1])
}

/// Lane and zone geometry in map coordinates, ready to draw.
struct MapShapes {
    /// Per lane: its id and shape.
    lanes: Vec<(u8, LaneShape)>,
    zones: Vec<LaneShape>,
    max_width: f64,
}

struct LaneShape {
    band: Vec<[f64; 2]>,
    edges: [Vec<[f64; 2]>; 2],
    centre: Vec<[f64; 2]>,
    width: f64,
}

fn map_shapes(input: &PlotInput<'_>) -> MapShapes {
    let widths = input
        .lanes
        .iter()
        .filter_map(|l| ok(l.width_m).filter(|w| *w > 0.0));
    let max_width = widths.fold(None, |m: Option<f64>, w| Some(m.map_or(w, |m| m.max(w))));
    let max_width = max_width.unwrap_or(3.5).min(50.0);
    let lanes = input.lanes.iter().filter_map(|lane| {
        let width = ok(lane.width_m)
            .filter(|w| *w > 0.0)
            .unwrap_or(max_width)
            .min(50.0);
        Some((lane.id, lane_shape(&lane.centre, width)?))
    });
    let lanes = lanes.collect();
    let zones = input
        .zones
        .iter()
        .filter_map(|z| lane_shape(z, max_width))
        .collect();
    MapShapes {
        lanes,
        zones,
        max_width,
    }
}

fn lane_shape(centre: &[[f64; 2]], width: f64) -> Option<LaneShape> {
    let mut pts: Vec<[f64; 2]> = centre.iter().filter_map(|&p| ok_point(p)).collect();
    pts.dedup();
    if pts.len() < 2 {
        return None;
    }
    let left = offset_line(&pts, 0.5 * width);
    let right = offset_line(&pts, -0.5 * width);
    let band = left.iter().chain(right.iter().rev()).copied().collect();
    Some(LaneShape {
        band,
        edges: [left, right],
        centre: pts,
        width,
    })
}

/// The polyline shifted sideways by `off` metres (left positive); `pts` has no repeated points.
fn offset_line(pts: &[[f64; 2]], off: f64) -> Vec<[f64; 2]> {
    let normal = |a: [f64; 2], b: [f64; 2]| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        [-dy / len, dx / len]
    };
    let shifted = |i: usize| {
        let before = i
            .checked_sub(1)
            .and_then(|j| Some(normal(*pts.get(j)?, pts[i])));
        let after = pts.get(i + 1).map(|&b| normal(pts[i], b));
        let n = match (before, after) {
            (Some(a), Some(b)) => unit([a[0] + b[0], a[1] + b[1]]).unwrap_or(a),
            (Some(n), None) | (None, Some(n)) => n,
            (None, None) => [0.0, 0.0],
        };
        [pts[i][0] + n[0] * off, pts[i][1] + n[1] * off]
    };
    (0..pts.len()).map(shifted).collect()
}

fn unit(v: [f64; 2]) -> Option<[f64; 2]> {
    let len = v[0].hypot(v[1]);
    (len > 1e-9).then(|| [v[0] / len, v[1] / len])
}

/// The view, its x/y spans and the axis labels for the trajectory figure.
struct Frame {
    view: View,
    x: Span,
    y: Span,
    desc: (String, String),
}

fn trajectory_frame(track: &[[f64; 2]], shapes: &MapShapes, px: Xy) -> Option<Frame> {
    let geometry = || shapes.lanes.iter().map(|l| &l.1).chain(&shapes.zones);
    let map_points: Vec<[f64; 2]> = geometry().flat_map(|s| s.band.iter().copied()).collect();
    let fit = if track.is_empty() { &map_points } else { track };
    let bx = Span::of(fit.iter().map(|p| p[0]))?.pad(0.0, 2.0 * shapes.max_width);
    let by = Span::of(fit.iter().map(|p| p[1]))?.pad(0.0, 2.0 * shapes.max_width);
    let view = choose_view(fit, road_axis(shapes, bx, by), shapes.max_width);
    let fitted: Vec<Xy> = fit.iter().map(|&p| view.map(p)).collect();
    let x = Span::of(fitted.iter().map(|p| p.0))?;
    let y = Span::of(fitted.iter().map(|p| p.1))?;
    if view.axis.is_none() {
        let margin = (0.08 * x.len().max(y.len())).max(2.0 * shapes.max_width);
        let (x, y) = equal_scale(x.pad(0.0, margin), y.pad(0.0, margin), px);
        let desc = (
            "east (m; equal scales)".to_string(),
            "north (m)".to_string(),
        );
        return Some(Frame { view, x, y, desc });
    }
    let x = x.pad(0.03, 5.0);
    let y = y.union(road_lateral(shapes, &view, x, y)).pad(0.0, 1.0);
    let desc = road_desc(&view, x, y, px);
    Some(Frame { view, x, y, desc })
}

/// The lateral extent of the lane and zone edges over the along-road span `x`, limited to
/// three lane widths beside the track's lateral span `y` (so a crossing road does not count).
fn road_lateral(shapes: &MapShapes, view: &View, x: Span, y: Span) -> Option<Span> {
    let window = y.pad(0.0, 3.0 * shapes.max_width);
    let geometry = shapes.lanes.iter().map(|l| &l.1).chain(&shapes.zones);
    let edges = geometry.flat_map(|s| s.edges.iter());
    let mapped = edges.map(|e| e.iter().map(|&p| view.map(p)).collect::<Vec<Xy>>());
    let inside = mapped.flat_map(|e| clip_polyline(&e, x, window)).flatten();
    Span::of(inside.map(|p| p.1))
}

/// Grows the shorter side so that a metre has the same length on both axes.
fn equal_scale(x: Span, y: Span, px: Xy) -> (Span, Span) {
    let m_per_px = (x.len() / px.0).max(y.len() / px.1);
    (x.centred(m_per_px * px.0), y.centred(m_per_px * px.1))
}

fn road_desc(view: &View, x: Span, y: Span, px: Xy) -> (String, String) {
    let u = view.axis.unwrap_or([1.0, 0.0]);
    let heading = u[0].atan2(u[1]).to_degrees().rem_euclid(360.0);
    let exaggeration = (x.len() / px.0) / (y.len() / px.1);
    (
        format!("along the road (m from the drive start, heading {heading:03.0}°)"),
        format!("lateral, left + (m; ×{exaggeration:.0} exaggerated)"),
    )
}

fn draw_trajectory<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    input: &PlotInput<'_>,
    ink: Ink,
) -> DrawResult<(), DB> {
    let (main, side) = layout(root, ink, &heading(input.title, "trajectory"))?;
    let track: Vec<[f64; 2]> = input
        .track
        .iter()
        .filter_map(|p| ok_point(p.true_point))
        .collect();
    let shapes = map_shapes(input);
    let legend = trajectory_legend(input.track);
    let Some(frame) = trajectory_frame(&track, &shapes, plot_pixels(&main)) else {
        let mut chart = chart(
            &main,
            Span { lo: 0.0, hi: 100.0 },
            Span { lo: 0.0, hi: 100.0 },
        )?;
        mesh(&mut chart, ink, ("east (m)", "north (m)"), &|v| number(*v))?;
        no_data(&main, ink)?;
        return draw_legend(&side, ink, &legend);
    };
    let mut chart = chart(&main, frame.x, frame.y)?;
    let desc = (frame.desc.0.as_str(), frame.desc.1.as_str());
    mesh(&mut chart, ink, desc, &|v| number(*v))?;
    draw_map(&mut chart, &shapes, &frame)?;
    draw_lane_ids(&mut chart, ink, &shapes, &frame)?;
    draw_track(&mut chart, input.track, &frame)?;
    draw_legend(&side, ink, &legend)
}

fn draw_map<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    shapes: &MapShapes,
    frame: &Frame,
) -> DrawResult<(), DB> {
    let lane_fill = RGBColor(222, 222, 222).filled();
    let lanes = shapes.lanes.iter().map(|l| &l.1);
    for shape in lanes.clone() {
        draw_polygon(chart, &shape.band, frame, lane_fill)?;
    }
    for shape in lanes {
        for edge in &shape.edges {
            draw_clipped(chart, edge, frame, RGBColor(90, 90, 90).stroke_width(1))?;
        }
        draw_clipped(chart, &shape.centre, frame, WHITE.stroke_width(1))?;
    }
    for zone in &shapes.zones {
        draw_polygon(chart, &zone.band, frame, START_RED.mix(0.45).filled())?;
        for edge in &zone.edges {
            draw_clipped(chart, edge, frame, START_RED.stroke_width(2))?;
        }
    }
    Ok(())
}

fn draw_polygon<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    points: &[[f64; 2]],
    frame: &Frame,
    style: ShapeStyle,
) -> DrawResult<(), DB> {
    let mapped: Vec<Xy> = points.iter().map(|&p| frame.view.map(p)).collect();
    let clipped = clip_polygon(&mapped, frame.x, frame.y);
    if clipped.len() >= 3 {
        chart.draw_series(std::iter::once(Polygon::new(clipped, style)))?;
    }
    Ok(())
}

fn draw_clipped<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    points: &[[f64; 2]],
    frame: &Frame,
    style: ShapeStyle,
) -> DrawResult<(), DB> {
    let mapped: Vec<Xy> = points.iter().map(|&p| frame.view.map(p)).collect();
    for piece in clip_polyline(&mapped, frame.x, frame.y) {
        chart.draw_series(LineSeries::new(piece, style))?;
    }
    Ok(())
}

/// "lane N" left of the centreline (where the car does not drive), where the lane enters the
/// plot (3 % in from its edges).
fn draw_lane_ids<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    ink: Ink,
    shapes: &MapShapes,
    frame: &Frame,
) -> DrawResult<(), DB> {
    let inner_x = frame.x.pad(-0.03, 0.0);
    let inner_y = frame.y.pad(-0.03, 0.0);
    let style = ink
        .style(13, RGBColor(60, 60, 60))
        .pos(Pos::new(HPos::Left, VPos::Center));
    for (id, shape) in &shapes.lanes {
        let beside = offset_line(&shape.centre, 0.3 * shape.width);
        let mapped: Vec<Xy> = beside.iter().map(|&p| frame.view.map(p)).collect();
        let pieces = clip_polyline(&mapped, inner_x, inner_y);
        if let Some(&at) = pieces.first().and_then(|piece| piece.first()) {
            let text = Text::new(format!("lane {id}"), at, style.clone());
            chart.plotting_area().draw(&text)?;
        }
    }
    Ok(())
}

/// The true trajectory, one line per run of equal zone state, and a dot at the start.
fn draw_track<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    track: &[TrackPoint],
    frame: &Frame,
) -> DrawResult<(), DB> {
    let points = track
        .iter()
        .filter_map(|p| Some((ok_point(p.true_point)?, &p.zone_state)));
    let points: Vec<(Xy, &String)> = points.map(|(p, s)| (frame.view.map(p), s)).collect();
    let mut start = 0;
    while start < points.len() {
        let state = points[start].1;
        let len = points[start..].iter().take_while(|p| p.1 == state).count();
        let end = (start + len + 1).min(points.len());
        let line = points[start..end].iter().map(|p| p.0);
        chart.draw_series(LineSeries::new(line, state_color(state).stroke_width(3)))?;
        start += len;
    }
    if let Some((first, _)) = points.first() {
        chart.draw_series(std::iter::once(Circle::new(*first, 5, BLACK.filled())))?;
    }
    Ok(())
}

fn trajectory_legend(track: &[TrackPoint]) -> Vec<Entry> {
    let mut entries = vec![
        Entry::new(
            Swatch::Band(RGBColor(222, 222, 222).to_rgba()),
            "lane (width)",
        ),
        Entry::new(Swatch::Band(START_RED.mix(0.45)), "closed lane (zone)"),
        Entry::new(Swatch::Dot(BLACK), "drive start"),
        Entry::new(Swatch::Heading, "true trajectory, zone state"),
    ];
    for state in legend_states(track) {
        entries.push(Entry::new(Swatch::Line(state_color(state)), state));
    }
    entries
}

// ---------------------------------------------------------------------------------------------
// Clipping to the plot rectangle (plotters does not clip)

/// The parts of a polyline inside the rectangle `x` × `y`.
fn clip_polyline(line: &[Xy], x: Span, y: Span) -> Vec<Vec<Xy>> {
    let mut pieces = Vec::new();
    let mut current: Vec<Xy> = Vec::new();
    for pair in line.windows(2) {
        match clip_segment(pair[0], pair[1], x, y) {
            Some((a, b)) => {
                if current.last() != Some(&a) {
                    flush(&mut pieces, &mut current);
                    current.push(a);
                }
                current.push(b);
            }
            None => flush(&mut pieces, &mut current),
        }
    }
    flush(&mut pieces, &mut current);
    pieces
}

/// Liang-Barsky: the part of the segment `a`-`b` inside the rectangle, ends kept exact.
fn clip_segment(a: Xy, b: Xy, x: Span, y: Span) -> Option<(Xy, Xy)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-dx, a.0 - x.lo),
        (dx, x.hi - a.0),
        (-dy, a.1 - y.lo),
        (dy, y.hi - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
            continue;
        }
        let t = q / p;
        if p < 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
        if t0 > t1 {
            return None;
        }
    }
    let at = |t: f64| (a.0 + dx * t, a.1 + dy * t);
    let start = if t0 > 0.0 { at(t0) } else { a };
    let end = if t1 < 1.0 { at(t1) } else { b };
    Some((start, end))
}

/// Sutherland-Hodgman: the polygon cut to the rectangle `x` × `y`.
fn clip_polygon(poly: &[Xy], x: Span, y: Span) -> Vec<Xy> {
    let halves = [
        (0, x.lo, true),
        (0, x.hi, false),
        (1, y.lo, true),
        (1, y.hi, false),
    ];
    halves
        .iter()
        .fold(poly.to_vec(), |p, &(axis, bound, above)| {
            clip_half(&p, axis, bound, above)
        })
}

fn clip_half(poly: &[Xy], axis: usize, bound: f64, above: bool) -> Vec<Xy> {
    let coord = |p: Xy| if axis == 0 { p.0 } else { p.1 };
    let inside = |p: Xy| {
        if above {
            coord(p) >= bound
        } else {
            coord(p) <= bound
        }
    };
    let cross = |a: Xy, b: Xy| {
        let t = (bound - coord(a)) / (coord(b) - coord(a));
        (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t)
    };
    let mut out = Vec::with_capacity(poly.len() + 4);
    let Some(&last) = poly.last() else {
        return out;
    };
    let mut prev = last;
    for &cur in poly {
        if inside(cur) != inside(prev) {
            out.push(cross(prev, cur));
        }
        if inside(cur) {
            out.push(cur);
        }
        prev = cur;
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Matched lane against the true lane over time

fn draw_lanes<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    input: &PlotInput<'_>,
    ink: Ink,
) -> DrawResult<(), DB> {
    let (main, side) = layout(root, ink, &heading(input.title, "matched and true lane"))?;
    let samples: Vec<&TrackPoint> = input.track.iter().filter(|p| ok(p.t_s).is_some()).collect();
    let x = Span::of(samples.iter().map(|p| p.t_s)).unwrap_or(Span { lo: 0.0, hi: 1.0 });
    let x = x.pad(0.02, 0.5);
    let ids = lane_ids(input);
    let y = Span::of(ids.iter().copied())
        .unwrap_or(Span { lo: 1.0, hi: 1.0 })
        .pad(0.0, 0.6);
    let mut chart = chart(&main, x, y)?;
    let gaps: Vec<(f64, bool)> = samples
        .iter()
        .map(|p| (p.t_s, p.matched_lane.is_none()))
        .collect();
    let gaps = runs(&gaps)
        .into_iter()
        .filter(|r| r.2)
        .map(|(a, b, _)| (a, b, gap_color()));
    draw_bands(&mut chart, gaps, y)?;
    lane_mesh(&mut chart, ink, &ids)?;
    let truth: Vec<_> = samples
        .iter()
        .map(|p| (p.t_s, Some(f64::from(p.true_lane))))
        .collect();
    draw_lines(
        &mut chart,
        step_lines(&truth),
        RGBColor(31, 119, 180).mix(0.45).stroke_width(9),
    )?;
    let matched: Vec<_> = samples
        .iter()
        .map(|p| (p.t_s, p.matched_lane.map(f64::from)))
        .collect();
    draw_lines(
        &mut chart,
        step_lines(&matched),
        RGBColor(230, 85, 13).stroke_width(2),
    )?;
    if samples.is_empty() {
        no_data(&main, ink)?;
    }
    draw_legend(&side, ink, &lanes_legend())
}

fn gap_color() -> RGBAColor {
    RGBColor(120, 120, 120).mix(0.22)
}

/// Lane ids seen in the track or the map, sorted, as plot values.
fn lane_ids(input: &PlotInput<'_>) -> Vec<f64> {
    let track = input
        .track
        .iter()
        .flat_map(|p| [Some(p.true_lane), p.matched_lane])
        .flatten();
    let mut ids: Vec<u8> = track.chain(input.lanes.iter().map(|l| l.id)).collect();
    ids.sort_unstable();
    ids.dedup();
    ids.into_iter().map(f64::from).collect()
}

/// The grid with integer lane ids (every n-th when there are many) on the y axis.
fn lane_mesh<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    ink: Ink,
    ids: &[f64],
) -> DrawResult<(), DB> {
    let whole = |v: &f64| {
        if v.fract() == 0.0 {
            number(*v)
        } else {
            String::new()
        }
    };
    let step = ids.len().div_ceil(20).max(1);
    chart
        .configure_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .label_style(ink.style(13, BLACK))
        .axis_desc_style(ink.style(16, BLACK))
        .x_desc("time since the drive start (s)")
        .y_desc("lane id")
        .y_labels(ids.len().div_ceil(step).max(2) * 2)
        .x_label_formatter(&|v| number(*v))
        .y_label_formatter(&whole)
        .draw()
}

fn lanes_legend() -> Vec<Entry> {
    vec![
        Entry::new(Swatch::Band(RGBColor(31, 119, 180).mix(0.45)), "true lane"),
        Entry::new(
            Swatch::Line(RGBColor(230, 85, 13)),
            "lane matched by the OBU",
        ),
        Entry::new(Swatch::Band(gap_color()), "OBU had no lane"),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_track() -> Vec<TrackPoint> {
        let point = |i: u8| TrackPoint {
            t_s: f64::from(i),
            true_point: [f64::from(i) * 20.0, 0.0],
            true_lane: 1 + i / 5,
            true_distance_m: Some(100.0 - f64::from(i) * 20.0),
            speed_mps: Some(20.0),
            limit_mps: (!i.is_multiple_of(3)).then_some(16.7),
            zone_state: ZONE_STATES[usize::from(i) % 5].to_string(),
            primary: (i > 3).then(|| "Overspeed".to_string()),
            matched_lane: (i != 4).then_some(1 + i / 5),
        };
        (0..10).map(point).collect()
    }

    fn svg(figure: Figure, input: &PlotInput<'_>, ink: Ink) -> String {
        let mut text = String::new();
        let root = SVGBackend::with_string(&mut text, SIZE).into_drawing_area();
        render(&root, figure, input, ink).expect("svg drawn");
        drop(root);
        text
    }

    fn png(figure: Figure, input: &PlotInput<'_>, ink: Ink) -> Result<(), String> {
        let mut buffer = vec![0; (SIZE.0 * SIZE.1 * 3) as usize];
        let root = BitMapBackend::with_buffer(&mut buffer, SIZE).into_drawing_area();
        render(&root, figure, input, ink).map_err(|e| e.to_string())
    }

    #[test]
    fn draws_without_any_font() {
        let track = sample_track();
        let lane = PlotLane {
            id: 1,
            centre: vec![[0.0, 0.0], [200.0, 0.0]],
            width_m: 3.5,
        };
        let (lanes, zones) = (vec![lane], vec![vec![[60.0, 0.0], [90.0, 0.0]]]);
        let input = PlotInput {
            title: "t",
            track: &track,
            lanes: &lanes,
            zones: &zones,
            warning_distance_m: Some(50.0),
        };
        let unknown = Ink {
            family: "no-such-font-family",
            text: true,
        };
        assert!(svg(Figure::Speed, &input, unknown).contains("speed (km/h)"));
        // Text on a bitmap needs the font: that is why a fontless PNG gets transparent text.
        assert!(png(Figure::Speed, &input, unknown).is_err());
        let silent = Ink {
            text: false,
            ..unknown
        };
        for figure in [Figure::Speed, Figure::Trajectory, Figure::Lanes] {
            assert_eq!(png(figure, &input, silent), Ok(()), "{figure:?}");
            assert!(svg(figure, &input, unknown).contains("<svg"));
        }
    }

    #[test]
    fn runs_and_steps() {
        let runs = runs(&[(0.0, 'a'), (1.0, 'a'), (2.0, 'b'), (3.0, 'b'), (4.0, 'a')]);
        assert_eq!(
            runs,
            vec![(0.0, 2.0, 'a'), (2.0, 4.0, 'b'), (4.0, 4.0, 'a')]
        );
        let steps = step_lines(&[
            (0.0, Some(1.0)),
            (1.0, Some(2.0)),
            (2.0, None),
            (3.0, Some(3.0)),
        ]);
        let expected = vec![
            vec![(0.0, 1.0), (1.0, 1.0), (1.0, 2.0), (2.0, 2.0)],
            vec![(3.0, 3.0)],
        ];
        assert_eq!(steps, expected);
        assert_eq!(
            plain_lines(&[(0.0, Some(1.0)), (1.0, None), (2.0, Some(2.0))]).len(),
            2
        );
    }

    #[test]
    fn clipping() {
        let (x, y) = (Span { lo: 0.0, hi: 10.0 }, Span { lo: 0.0, hi: 10.0 });
        assert_eq!(
            clip_segment((-5.0, 5.0), (5.0, 5.0), x, y),
            Some(((0.0, 5.0), (5.0, 5.0)))
        );
        assert_eq!(clip_segment((-5.0, -5.0), (-1.0, 20.0), x, y), None);
        let line = [
            (-5.0, 5.0),
            (5.0, 5.0),
            (8.0, 5.0),
            (20.0, 5.0),
            (20.0, 6.0),
            (5.0, 6.0),
        ];
        let pieces = clip_polyline(&line, x, y);
        assert_eq!(
            pieces,
            vec![
                vec![(0.0, 5.0), (5.0, 5.0), (8.0, 5.0), (10.0, 5.0)],
                vec![(10.0, 6.0), (5.0, 6.0)]
            ]
        );
        let square = [(-5.0, -5.0), (5.0, -5.0), (5.0, 5.0), (-5.0, 5.0)];
        let cut = clip_polygon(&square, x, y);
        assert_eq!(cut.len(), 4);
        assert!(cut
            .iter()
            .all(|p| (0.0..=5.0).contains(&p.0) && (0.0..=5.0).contains(&p.1)));
        assert!(clip_polygon(&[], x, y).is_empty());
    }

    #[test]
    fn views_and_offsets() {
        let diagonal: Vec<[f64; 2]> = (0..50)
            .map(|i| [f64::from(i) * 10.0, f64::from(i) * 10.0])
            .collect();
        let view = choose_view(&diagonal, None, 3.5);
        let (along, lateral) = view.map([100.0, 100.0]);
        assert!((along - 100.0 * 2f64.sqrt()).abs() < 1e-9 && lateral.abs() < 1e-9);
        assert_eq!(choose_view(&diagonal[..3], None, 3.5), View::PLAIN);
        let left = offset_line(&[[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]], 1.0);
        assert_eq!(left[0], [0.0, 1.0]);
        assert!((left[1][0] - (10.0 - 0.5f64.sqrt())).abs() < 1e-9);
        assert_eq!(number(-0.2), "-0.2");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(-250.0), "-250");
    }
}
