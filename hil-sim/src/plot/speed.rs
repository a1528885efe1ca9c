//! The `speed_alert` figure: speed and alerts against the distance before the zone.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::font::Ink;
use super::legend::{draw_legend, Entry, Swatch};
use super::series::{draw_bands, draw_lines, plain_lines, runs, step_lines};
use super::span::{ok, Span};
use super::style::{
    chart, heading, layout, legend_states, mesh, no_data, number, state_color, Chart, DrawResult,
    KIND_COLORS, LIMIT_PURPLE, START_RED, WARN_AMBER,
};
use super::{PlotInput, TrackPoint};

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

/// Draws the `speed_alert` figure.
pub(super) fn draw_speed<DB: DrawingBackend>(
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
