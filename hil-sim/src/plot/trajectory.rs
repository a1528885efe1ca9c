//! The `trajectory` figure: the true trajectory over the lane map.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::clip::{clip_polygon, clip_polyline};
use super::font::Ink;
use super::legend::{draw_legend, Entry, Swatch};
use super::shapes::{map_shapes, offset_line, MapShapes};
use super::span::{ok_point, Span};
use super::style::{
    chart, heading, layout, legend_states, mesh, no_data, number, plot_pixels, state_color, Chart,
    DrawResult, Xy, START_RED,
};
use super::view::{trajectory_frame, Frame};
use super::{PlotInput, TrackPoint};

/// Draws the `trajectory` figure.
pub(super) fn draw_trajectory<DB: DrawingBackend>(
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
