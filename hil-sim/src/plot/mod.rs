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

mod clip;
mod font;
mod lanes;
mod legend;
mod series;
mod shapes;
mod span;
mod speed;
mod style;
mod trajectory;
mod view;

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

pub use font::png_text_available;
use font::Ink;
use lanes::draw_lanes;
use speed::draw_speed;
use style::{DrawResult, SIZE};
use trajectory::draw_trajectory;

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

/// Draws into an RGB buffer and encodes it with the `image` crate the bench already uses
/// (plotters' own encoder would build a second, older `image`).
fn write_png(path: &Path, figure: Figure, input: &PlotInput<'_>, ink: Ink) -> Result<(), String> {
    let mut buffer = vec![0; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, SIZE).into_drawing_area();
        render(&root, figure, input, ink).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let image = image::RgbImage::from_raw(SIZE.0, SIZE.1, buffer).ok_or_else(|| {
        format!(
            "{}: the drawing's buffer has the wrong size",
            path.display()
        )
    })?;
    image
        .save(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

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

#[cfg(test)]
mod tests {
    use super::style::ZONE_STATES;
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
}
