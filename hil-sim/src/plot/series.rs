//! Runs of equal keys, step and plain lines, and drawing them (usable values and spans
//! are in `span`).

use plotters::prelude::*;

use super::span::Span;
use super::style::{Chart, DrawResult, Xy};

/// Splits `(x, key)` samples into runs of equal keys: `(x_start, x_end, key)`, each run ending
/// where the next begins.
pub(super) fn runs<K: PartialEq + Copy>(samples: &[(f64, K)]) -> Vec<(f64, f64, K)> {
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
pub(super) fn step_lines(samples: &[(f64, Option<f64>)]) -> Vec<Vec<Xy>> {
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
pub(super) fn plain_lines(samples: &[(f64, Option<f64>)]) -> Vec<Vec<Xy>> {
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

/// Moves a non-empty `current` line into `lines`.
pub(super) fn flush(lines: &mut Vec<Vec<Xy>>, current: &mut Vec<Xy>) {
    if !current.is_empty() {
        lines.push(std::mem::take(current));
    }
}

/// Draws line pieces (a single point as a dot).
pub(super) fn draw_lines<DB: DrawingBackend>(
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
pub(super) fn draw_bands<DB: DrawingBackend>(
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
