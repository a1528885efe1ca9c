//! The `lanes` figure: the matched lane against the true lane over time.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::font::Ink;
use super::legend::{draw_legend, Entry, Swatch};
use super::series::{draw_bands, draw_lines, runs, step_lines};
use super::span::{ok, Span};
use super::style::{chart, heading, layout, no_data, number, Chart, DrawResult};
use super::{PlotInput, TrackPoint};

/// Draws the `lanes` figure.
pub(super) fn draw_lanes<DB: DrawingBackend>(
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
