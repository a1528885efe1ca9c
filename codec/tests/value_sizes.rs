//! The crate docs' table of value sizes (`codec/docs/value-sizes.md`) against this build:
//! the column of this build's storage and capacity profile must hold the sizes the compiler
//! gives each message (`MESSAGE_NAMES[..].value_octets`), on a 64-bit host.
//!
//! Regenerate a column after changing capacities or types: `J2735_WRITE_SIZES=1 cargo test -p
//! j2735 --test value_sizes` with no features, with `--features alloc` and with
//! `--features firmware-capacities` (CI checks all three).

use j2735::msg::message_frame::MESSAGE_NAMES;
use j2735::MessageFrame;

const PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/value-sizes.md");
const COLUMNS: [&str; 3] = [
    "no-heap, default capacities",
    "no-heap, `firmware-capacities`",
    "`alloc`",
];

/// This build's column.
fn column() -> usize {
    if cfg!(feature = "alloc") {
        2
    } else if cfg!(feature = "firmware-capacities") {
        1
    } else {
        0
    }
}

/// (row label, octets) of this build: the MessageFrame, then every message by id.
fn measured() -> Vec<(String, usize)> {
    let mut rows = vec![(
        "`MessageFrame` (any message)".to_string(),
        core::mem::size_of::<MessageFrame>(),
    )];
    rows.extend(MESSAGE_NAMES.iter().map(|m| {
        (
            format!("{} `{}` ({})", m.id, m.type_name, m.short),
            m.value_octets,
        )
    }));
    rows
}

fn parse(text: &str) -> Vec<(String, [String; 3])> {
    text.lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| message") && !l.starts_with("| ---"))
        .map(|l| {
            let cells: Vec<String> = l
                .trim_matches('|')
                .split(" | ")
                .map(|c| c.trim().to_string())
                .collect();
            assert_eq!(cells.len(), 4, "{PATH}: bad row {l:?}");
            (
                cells[0].clone(),
                [cells[1].clone(), cells[2].clone(), cells[3].clone()],
            )
        })
        .collect()
}

fn render(rows: &[(String, [String; 3])]) -> String {
    let mut out = format!(
        "| message | {} |\n| --- | ---: | ---: | ---: |\n",
        COLUMNS.join(" | ")
    );
    for (label, cells) in rows {
        out.push_str(&format!("| {label} | {} |\n", cells.join(" | ")));
    }
    out
}

/// Octets with thousands separators (as the docs write them).
fn octets(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[test]
fn the_docs_table_of_value_sizes_holds_this_builds_sizes() {
    if cfg!(not(target_pointer_width = "64")) {
        panic!("the table is of a 64-bit host");
    }
    let col = column();
    let text = std::fs::read_to_string(PATH).unwrap_or_default();
    let old = parse(&text);
    let new: Vec<(String, [String; 3])> = measured()
        .into_iter()
        .map(|(label, n)| {
            let mut cells = old
                .iter()
                .find(|(l, _)| *l == label)
                .map(|(_, c)| c.clone())
                .unwrap_or_else(|| ["?".into(), "?".into(), "?".into()]);
            cells[col] = octets(n);
            (label, cells)
        })
        .collect();
    let old = if std::env::var_os("J2735_WRITE_SIZES").is_some() {
        std::fs::write(PATH, render(&new)).unwrap();
        parse(&std::fs::read_to_string(PATH).unwrap())
    } else {
        old
    };
    assert_eq!(
        render(&old),
        render(&new),
        "{PATH} ({}) is not this build's: J2735_WRITE_SIZES=1 regenerates it",
        COLUMNS[col]
    );
    assert!(
        old.iter().all(|(_, cells)| cells.iter().all(|c| c != "?")),
        "{PATH} has a column not generated yet"
    );
}

/// With `alloc` a MessageFrame keeps a BSM (the ten-a-second message of every vehicle) and
/// every message no larger than a BSM in place, the others behind a pointer (`[boxed]
/// open_in_place` in `codec/codegen/capacities.toml`): the frame is then the size of a BSM
/// and the frame's own extensions (a pointer; the value's tag fits in the BSM's unused bit
/// patterns). A message put in place that is larger than a BSM would grow every
/// frame, and every new frame is moved out of its result by its caller; a boxed one no
/// larger than a BSM would allocate for no room saved.
#[cfg(feature = "alloc")]
#[test]
fn with_alloc_a_frame_is_the_size_of_a_bsm_and_only_larger_messages_are_boxed() {
    use j2735::msg::basic_safety_message::BasicSafetyMessage;
    let bsm = core::mem::size_of::<BasicSafetyMessage>();
    let frame = core::mem::size_of::<MessageFrame>();
    let word = core::mem::size_of::<usize>();
    assert!(
        frame <= bsm + word,
        "a MessageFrame {frame} octets, a BSM {bsm}"
    );
    for m in MESSAGE_NAMES {
        if m.boxed_with_alloc {
            assert!(
                m.value_octets > bsm,
                "{} ({} octets) is boxed",
                m.short,
                m.value_octets
            );
        } else {
            assert!(
                m.value_octets <= bsm,
                "{} ({} octets) is in place",
                m.short,
                m.value_octets
            );
        }
    }
}
