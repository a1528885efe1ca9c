//! What is wrong with an input, and where: [`Problem`] and [`InputError`].

use std::fmt;

/// What is wrong with one part of an input (the [`InputError`] says which part).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Problem {
    /// A required member is absent or `null`.
    Missing {
        /// JSON path of the member (`properties.width_m`).
        what: String,
    },
    /// A member of the wrong JSON type.
    WrongType {
        /// JSON path of the member.
        what: String,
        /// The type it must have.
        expected: &'static str,
        /// The type it has.
        found: &'static str,
    },
    /// A value that is not allowed.
    Invalid {
        /// JSON path of the member (or `line`).
        what: String,
        /// The value as found.
        value: String,
        /// What is allowed.
        expected: String,
    },
    /// A line with fewer than two distinct points.
    TooFewPoints {
        /// Points given.
        given: usize,
        /// Points left after merging consecutive ones less than 1 cm apart.
        distinct: usize,
    },
    /// A lane id that an earlier feature already uses.
    DuplicateLaneId {
        /// The lane id.
        lane_id: u8,
        /// Index of the feature that uses it first.
        first_feature: usize,
    },
    /// Two members that exclude each other are both given.
    Conflict {
        /// One member.
        a: &'static str,
        /// The other.
        b: &'static str,
    },
    /// A WZDx event lists a different number of travel lanes than the lane map has running
    /// its way beside it.
    LaneCountMismatch {
        /// Travel lanes of the event (`lanes` entries that are not shoulders, sidewalks,
        /// bike lanes, parking or medians).
        wzdx_lanes: usize,
        /// Ids of the map's lanes running the event's way, left to right.
        map_lanes: Vec<u8>,
    },
    /// A work zone that covers (almost) no length of the lane it closes.
    NoLength {
        /// The lane.
        lane_id: u8,
        /// Station of the event's first point, metres.
        start_m: f64,
        /// Station of the event's last point, metres.
        end_m: f64,
    },
    /// A point too far from the reference or the road.
    TooFar {
        /// JSON path of the point (or `cone`).
        what: String,
        /// What it is too far from (`the reference`, `the nearest lane`).
        from: &'static str,
        /// Its distance, metres.
        distance_m: f64,
        /// The limit, metres.
        limit_m: f64,
    },
    /// The input holds nothing of what it must hold.
    Empty {
        /// What is missing (`features`).
        what: &'static str,
    },
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Missing { what } => write!(f, "{} is missing; add it", Named(what)),
            Self::WrongType {
                what,
                expected,
                found,
            } => write!(f, "{} is {found}; it must be {expected}", Named(what)),
            Self::Invalid {
                what,
                value,
                expected,
            } => write!(f, "{} is {value}; expected {expected}", Named(what)),
            Self::TooFewPoints { given, distinct } => write!(
                f,
                "the geometry has {given} coordinates ({distinct} distinct); a line needs at least 2 distinct points"
            ),
            Self::DuplicateLaneId {
                lane_id,
                first_feature,
            } => write!(
                f,
                "lane_id {lane_id} is already used by features[{first_feature}]; give every lane its own id"
            ),
            Self::Conflict { a, b } => {
                write!(f, "both `{a}` and `{b}` are given; keep only one of them")
            }
            Self::LaneCountMismatch {
                wzdx_lanes,
                map_lanes,
            } => write!(
                f,
                "the event lists {wzdx_lanes} travel lanes but the lane map has {} lanes running its way beside it (ids {map_lanes:?}, left to right); make the feed's `lanes` and the lane map agree",
                map_lanes.len()
            ),
            Self::NoLength {
                lane_id,
                start_m,
                end_m,
            } => write!(
                f,
                "the event runs from station {start_m:.1} m to {end_m:.1} m of lane {lane_id}, which is no zone; check that its geometry starts upstream and lies along the lane map"
            ),
            Self::TooFar {
                what,
                from,
                distance_m,
                limit_m,
            } => write!(
                f,
                "{} lies {distance_m:.0} m from {from}, more than {limit_m:.0} m; check the coordinate (and the lat/lon order)",
                Named(what)
            ),
            Self::Empty { what } => write!(f, "there are no {what}"),
        }
    }
}

/// A JSON path in backticks, or `the line` / `the cone` for those words.
struct Named<'a>(&'a str);

impl fmt::Display for Named<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            "line" | "cone" => write!(f, "the {}", self.0),
            path => write!(f, "`{path}`"),
        }
    }
}

/// Why an input file was refused: where, and the [`Problem`] there.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum InputError {
    /// The text is not JSON.
    Json {
        /// 1-based line of the parser's complaint.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// The document as a whole (its top level).
    Document(Problem),
    /// Feature `index` (0-based, file order) of a `FeatureCollection`.
    Feature {
        /// Index in `features`.
        index: usize,
        /// What is wrong with it.
        problem: Problem,
    },
    /// Item `index` (0-based) of a JSON cone list.
    Item {
        /// Index in the list.
        index: usize,
        /// What is wrong with it.
        problem: Problem,
    },
    /// Line `line` (1-based) of a CSV cone list.
    Line {
        /// The line number.
        line: usize,
        /// What is wrong with it.
        problem: Problem,
    },
}

impl InputError {
    /// The problem, unless the text is not JSON at all.
    pub fn problem(&self) -> Option<&Problem> {
        match self {
            Self::Json { .. } => None,
            Self::Document(problem)
            | Self::Feature { problem, .. }
            | Self::Item { problem, .. }
            | Self::Line { problem, .. } => Some(problem),
        }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Json {
                line,
                column,
                message,
            } => write!(
                f,
                "not valid JSON at line {line}, column {column}: {message}"
            ),
            Self::Document(problem) => write!(f, "document: {problem}"),
            Self::Feature { index, problem } => write!(f, "features[{index}]: {problem}"),
            Self::Item { index, problem } => write!(f, "item [{index}]: {problem}"),
            Self::Line { line, problem } => write!(f, "line {line}: {problem}"),
        }
    }
}

impl std::error::Error for InputError {}
