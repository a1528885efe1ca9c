//! Layout of a figure (title, chart and legend columns, axes), axis labels and colours.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use super::font::Ink;
use super::span::Span;
use super::TrackPoint;

/// Size of every figure, pixels.
pub(super) const SIZE: (u32, u32) = (1200, 700);
const LEGEND_W: u32 = 250;
const TITLE_H: u32 = 44;
const PAD: u32 = 16;
const X_LABEL_H: u32 = 56;
const Y_LABEL_W: u32 = 80;

/// What drawing on a backend `DB` returns.
pub(super) type DrawResult<T, DB> =
    Result<T, DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;
/// A chart with two `f64` axes.
pub(super) type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;
/// A point in plot coordinates.
pub(super) type Xy = (f64, f64);
/// The chart column and the legend column of a figure.
type Columns<DB> = (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>);

/// "title: what", or just "what" without a title.
pub(super) fn heading(title: &str, what: &str) -> String {
    if title.trim().is_empty() {
        what.to_string()
    } else {
        format!("{title}: {what}")
    }
}

/// Draws the title and splits the rest into the chart column and the legend column.
pub(super) fn layout<DB: DrawingBackend>(
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
pub(super) fn plot_pixels<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>) -> Xy {
    let (w, h) = area.dim_in_pixel();
    let w = w.saturating_sub(2 * PAD + Y_LABEL_W).max(1);
    let h = h.saturating_sub(2 * PAD + X_LABEL_H).max(1);
    (f64::from(w), f64::from(h))
}

/// A chart with the axes `x` × `y` in `area`.
pub(super) fn chart<'a, DB: DrawingBackend>(
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

/// The grid, axis labels (x through `x_fmt`) and axis descriptions.
pub(super) fn mesh<DB: DrawingBackend>(
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

/// Writes "no data" in the middle of `area`.
pub(super) fn no_data<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    ink: Ink,
) -> DrawResult<(), DB> {
    let (w, h) = area.dim_in_pixel();
    let style = ink.at(20, HPos::Center, VPos::Center);
    area.draw_text("no data", &style, (w as i32 / 2, h as i32 / 2))
}

/// An axis label for a number of metres, seconds or km/h, without "-0".
pub(super) fn number(v: f64) -> String {
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

/// The zone states the OBU shows, in order.
pub(super) const ZONE_STATES: [&str; 5] = ["None", "Approaching", "Warning", "InZone", "Leaving"];
/// The zone start and closed lanes.
pub(super) const START_RED: RGBColor = RGBColor(214, 39, 40);
/// The warning distance and state.
pub(super) const WARN_AMBER: RGBColor = RGBColor(255, 170, 0);
/// The limit shown by the OBU.
pub(super) const LIMIT_PURPLE: RGBColor = RGBColor(118, 42, 131);
/// Colours of the primary alert kinds, by order of first appearance.
pub(super) const KIND_COLORS: [RGBColor; 8] = [
    RGBColor(204, 0, 204),
    RGBColor(140, 86, 75),
    RGBColor(0, 128, 128),
    RGBColor(23, 43, 110),
    RGBColor(128, 128, 0),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
    RGBColor(200, 82, 0),
];

/// The colour of a zone state (purple for an unknown one).
pub(super) fn state_color(state: &str) -> RGBColor {
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
pub(super) fn legend_states(track: &[TrackPoint]) -> Vec<&str> {
    let mut states = ZONE_STATES.to_vec();
    for p in track {
        if !states.contains(&p.zone_state.as_str()) {
            states.push(&p.zone_state);
        }
    }
    states
}
