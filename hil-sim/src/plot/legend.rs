//! The legend column of a figure: swatches and labels.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use super::font::Ink;
use super::style::DrawResult;

/// The mark drawn before a legend label.
pub(super) enum Swatch {
    Heading,
    Line(RGBColor),
    Dashed(RGBColor),
    Band(RGBAColor),
    Dot(RGBColor),
}

/// One legend line: a swatch and its label.
pub(super) struct Entry {
    swatch: Swatch,
    label: String,
}

impl Entry {
    pub(super) fn new(swatch: Swatch, label: impl Into<String>) -> Self {
        Entry {
            swatch,
            label: label.into(),
        }
    }
}

/// Draws the entries one below the other into the legend column.
pub(super) fn draw_legend<DB: DrawingBackend>(
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
