//! The font for text in PNGs, and how text is drawn on each backend.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{FONT_ENV, FONT_PATHS};

/// The family name of all text (SVG names it; the PNG font is registered under it).
const FONT_FAMILY: &str = "sans-serif";

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

/// How text is drawn on one backend: the font family, and whether text is drawn at all.
/// Without text every style is transparent, which both backends skip before any font lookup.
#[derive(Debug, Clone, Copy)]
pub(super) struct Ink {
    pub(super) family: &'static str,
    pub(super) text: bool,
}

impl Ink {
    pub(super) fn svg() -> Self {
        Ink {
            family: FONT_FAMILY,
            text: true,
        }
    }

    pub(super) fn png() -> Self {
        Ink {
            family: FONT_FAMILY,
            text: png_text_available(),
        }
    }

    pub(super) fn style(self, size: u32, color: RGBColor) -> TextStyle<'static> {
        let font = FontDesc::new(self.family.into(), f64::from(size), FontStyle::Normal);
        if self.text {
            font.color(&color)
        } else {
            font.color(&TRANSPARENT)
        }
    }

    pub(super) fn at(self, size: u32, h: HPos, v: VPos) -> TextStyle<'static> {
        self.style(size, BLACK).pos(Pos::new(h, v))
    }
}
