//! The test RSU's SNMP side: net-snmp's `snmpd` hands every request under the RSU MIB's
//! root to this program over the `pass_persist` protocol (a request on stdin, the answer
//! on stdout), and [`Agent`] answers from the [`super::tables`].
//!
//! What snmpd does with a SET (net-snmp 5.9): it first asks `get` for each varbind (an
//! object that answers nothing is notWritable), then sends one `set` per varbind in order,
//! and applies the first error's status at its index without undoing the others. So a
//! `get` of a column of a row that does not exist yet answers a placeholder, and the end of
//! a SET request is seen as the next request, or 50 ms of quiet.

use super::tables::{Table, TableId, Val};
use std::io::{BufRead, Write};
use std::time::{Duration, Instant};

/// Which MIB the test RSU speaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mib {
    /// NTCIP 1218: `rsuMsgRepeatStatusTable`, `rsuIFMStatusTable` and identity scalars.
    Ntcip1218,
    /// RSU 4.1: `rsuSRMStatusTable` and identity scalars.
    Rsu41,
}

impl Mib {
    /// The root snmpd hands to the agent.
    pub fn root(self) -> Vec<u64> {
        match self {
            Self::Ntcip1218 => vec![1, 3, 6, 1, 4, 1, 1206, 4, 2, 18],
            Self::Rsu41 => vec![1, 0, 15628, 4, 1],
        }
    }

    /// The name on the command line.
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "ntcip1218" => Some(Self::Ntcip1218),
            "rsu4.1" => Some(Self::Rsu41),
            _ => None,
        }
    }
}

/// How long a SET request may pause between varbinds before it is taken as ended.
pub const REQUEST_QUIET: Duration = Duration::from_millis(50);

/// The test RSU's MIB: tables and scalars.
#[derive(Debug)]
pub struct Agent {
    /// The MIB.
    pub mib: Mib,
    /// Its tables.
    pub tables: Vec<Table>,
    scalars: Vec<(Vec<u64>, Val)>,
    /// When the last `set` came, if the request it belongs to has not ended.
    set_open: Option<Instant>,
    /// Immediate-forward rows written by requests that ended, to send once each.
    pub forward: Vec<u32>,
}

impl Agent {
    /// The agent of `mib` with tables of `max_rows` rows.
    pub fn new(mib: Mib, max_rows: u32) -> Self {
        let root = mib.root();
        let at = |tail: &[u64]| root.iter().chain(tail).copied().collect::<Vec<_>>();
        let text = |s: &str| Val::Octets(s.as_bytes().to_vec());
        let (tables, scalars) = match mib {
            Mib::Ntcip1218 => (
                vec![
                    Table::new(TableId::MsgRepeat, max_rows),
                    Table::new(TableId::Ifm, max_rows),
                ],
                vec![
                    (at(&[3, 1, 0]), Val::Int(max_rows.into())),
                    (at(&[4, 1, 0]), Val::Int(max_rows.into())),
                    (at(&[13, 1, 0]), text("NTCIP 1218 v01 (hil-sim test RSU)")),
                    (at(&[13, 2, 0]), text("hil-sim test RSU")),
                    (at(&[13, 4, 0]), text("test-rsu")),
                ],
            ),
            Mib::Rsu41 => (
                vec![Table::new(TableId::Srm, max_rows)],
                vec![
                    (
                        at(&[17, 1, 0]),
                        text("rsuMIB 4.1 rev201812060000Z (hil-sim test RSU)"),
                    ),
                    (at(&[17, 2, 0]), text("hil-sim test RSU")),
                    (at(&[17, 4, 0]), text("test-rsu")),
                ],
            ),
        };
        Self {
            mib,
            tables,
            scalars,
            set_open: None,
            forward: Vec::new(),
        }
    }

    /// Ends the open SET request (if any): values of existing rows applied, immediate
    /// forwards queued.
    pub fn end_request(&mut self) {
        if self.set_open.take().is_none() {
            return;
        }
        for t in &mut self.tables {
            let changed = t.end_request();
            if t.id == TableId::Ifm {
                self.forward.extend(changed);
            }
        }
    }

    /// Whether a SET request is open (varbinds may still come).
    pub fn is_in_request(&self) -> bool {
        self.set_open.is_some()
    }

    /// Ends the open SET request once it has been quiet for [`REQUEST_QUIET`].
    pub fn end_quiet_request(&mut self, now: Instant) {
        if self.set_open.is_some_and(|at| now - at >= REQUEST_QUIET) {
            self.end_request();
        }
    }

    /// Every object, in OID order.
    fn objects(&self) -> Vec<(Vec<u64>, Val)> {
        let mut out = self.scalars.clone();
        for t in &self.tables {
            let entry = t.id.entry();
            for (index, row) in &t.rows {
                for (column, v) in row {
                    let mut oid = entry.clone();
                    oid.extend([u64::from(*column), u64::from(*index)]);
                    out.push((oid, v.clone()));
                }
            }
        }
        out.sort_by(|a, b| a.0.cmp(&b.0));
        out
    }

    /// The table, column and index an OID names.
    fn locate(&self, oid: &[u64]) -> Option<(usize, u32, u32)> {
        self.tables.iter().enumerate().find_map(|(i, t)| {
            let entry = t.id.entry();
            match oid.strip_prefix(entry.as_slice())? {
                [column, index] => {
                    Some((i, u32::try_from(*column).ok()?, u32::try_from(*index).ok()?))
                }
                _ => None,
            }
        })
    }

    /// `get`: the object, or for a writable column of a row not created yet a placeholder
    /// (snmpd's writability check before a SET).
    pub fn get(&mut self, oid: &[u64]) -> Option<(Vec<u64>, Val)> {
        if let Some(v) = self.objects().into_iter().find(|(o, _)| o == oid) {
            return Some(v);
        }
        let (t, column, index) = self.locate(oid)?;
        let table = &self.tables[t];
        let spec = table.id.columns().iter().find(|c| c.column == column)?;
        (index >= 1 && index <= table.max_rows).then(|| {
            let v = match spec.kind {
                super::tables::Kind::Int(..) | super::tables::Kind::Status => Val::Int(0),
                _ => Val::Octets(Vec::new()),
            };
            (oid.to_vec(), v)
        })
    }

    /// `getnext`: the first object after `oid`.
    pub fn get_next(&mut self, oid: &[u64]) -> Option<(Vec<u64>, Val)> {
        self.objects().into_iter().find(|(o, _)| o.as_slice() > oid)
    }

    /// `set`: the pass_persist reply (`DONE` or the error's name).
    pub fn set(&mut self, oid: &[u64], value: Val, now: Instant) -> &'static str {
        self.set_open = Some(now);
        let Some((t, column, index)) = self.locate(oid) else {
            return "not-writable";
        };
        match self.tables[t].set(column, index, value) {
            Ok(()) => "DONE",
            Err(e) => e.reply(),
        }
    }
}

/// Parses a dotted OID (`.1.3.6…`).
pub fn parse_oid(text: &str) -> Option<Vec<u64>> {
    text.trim()
        .trim_start_matches('.')
        .split('.')
        .map(|a| a.parse().ok())
        .collect()
}

/// Parses a pass_persist SET value line (`integer 4`, `octet "80 03"`, `string "AB"`).
pub fn parse_value(line: &str) -> Option<Val> {
    let (kind, rest) = line.trim_end_matches(['\r', '\n']).split_once(' ')?;
    let unquoted = |s: &str| {
        s.strip_prefix('"')
            .and_then(|s| s.strip_suffix('"'))
            .map(str::to_string)
    };
    match kind.to_ascii_lowercase().as_str() {
        "integer" | "gauge" | "counter" | "timeticks" | "unsigned" => {
            rest.trim().parse().ok().map(Val::Int)
        }
        "string" => unquoted(rest).map(|s| Val::Octets(s.into_bytes())),
        "octet" => {
            let hex = unquoted(rest)?;
            hex.split_whitespace()
                .map(|b| u8::from_str_radix(b.trim_start_matches("0x"), 16).ok())
                .collect::<Option<Vec<u8>>>()
                .map(Val::Octets)
        }
        _ => None,
    }
}

/// The answer lines of an object: OID, type, value.
fn answer(oid: &[u64], v: &Val) -> String {
    let dotted: String = oid.iter().map(|a| format!(".{a}")).collect();
    match v {
        Val::Int(i) => format!("{dotted}\ninteger\n{i}\n"),
        Val::Octets(o) => {
            let hex: Vec<String> = o.iter().map(|b| format!("{b:02x}")).collect();
            format!("{dotted}\noctet\n{}\n", hex.join(" "))
        }
    }
}

/// Serves pass_persist requests from `input` to `output` until the input ends; `agent`
/// is locked for each request.
///
/// # Errors
///
/// An I/O error of the pipes.
pub fn serve(
    agent: &std::sync::Mutex<Agent>,
    input: impl BufRead,
    mut output: impl Write,
) -> std::io::Result<()> {
    let mut lines = input.lines();
    let mut next = || -> std::io::Result<Option<String>> {
        for line in lines.by_ref() {
            let line = line?;
            if !line.trim().is_empty() {
                return Ok(Some(line));
            }
        }
        Ok(None)
    };
    while let Some(command) = next()? {
        let lock = || {
            agent
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
        };
        let reply = match command.trim() {
            "PING" => "PONG\n".to_string(),
            "get" | "getnext" => {
                let oid = next()?.and_then(|l| parse_oid(&l));
                let mut a = lock();
                a.end_request();
                let found = oid.and_then(|o| {
                    if command.trim() == "get" {
                        a.get(&o)
                    } else {
                        a.get_next(&o)
                    }
                });
                found.map_or("NONE\n".to_string(), |(o, v)| answer(&o, &v))
            }
            "set" => {
                let oid = next()?.and_then(|l| parse_oid(&l));
                let value = next()?.and_then(|l| parse_value(&l));
                match (oid, value) {
                    (Some(o), Some(v)) => format!("{}\n", lock().set(&o, v, Instant::now())),
                    (Some(_), None) => "wrong-type\n".to_string(),
                    _ => "not-writable\n".to_string(),
                }
            }
            _ => "NONE\n".to_string(),
        };
        output.write_all(reply.as_bytes())?;
        output.flush()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    fn talk(agent: &Mutex<Agent>, script: &str) -> String {
        let mut out = Vec::new();
        serve(agent, script.as_bytes(), &mut out).unwrap();
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn a_set_request_as_snmpd_sends_it_creates_a_row_that_walks() {
        let agent = Mutex::new(Agent::new(Mib::Ntcip1218, 16));
        let e = ".1.3.6.1.4.1.1206.4.2.18.3.2.1";
        let script = format!(
            "PING\nget\n{e}.2.1\nset\n{e}.2.1\noctet \"80 03\"\n\nset\n{e}.4.1\ninteger 100\n\
             set\n{e}.5.1\noctet \"07 ea 0c 04 0d 00 00 00\"\nset\n{e}.6.1\noctet \"07 ea 0c 04 0e 00 00 00\"\n\
             set\n{e}.7.1\nstring \"AB\"\nset\n{e}.8.1\ninteger 1\nset\n{e}.9.1\ninteger 4\n\
             getnext\n{e}\ngetnext\n{e}.2.1\n"
        );
        let out = talk(&agent, &script);
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[0], "PONG");
        assert_eq!(&lines[1..4], [&format!("{e}.2.1")[..], "octet", ""]);
        assert!(lines[4..11].iter().all(|l| *l == "DONE"), "{out}");
        assert_eq!(&lines[11..14], [&format!("{e}.2.1")[..], "octet", "80 03"]);
        assert_eq!(&lines[14..17], [&format!("{e}.3.1")[..], "integer", "183"]);
        assert!(agent.lock().unwrap().tables[0].is_active(1));
    }

    #[test]
    fn errors_are_spelled_as_snmpd_takes_them() {
        let agent = Mutex::new(Agent::new(Mib::Ntcip1218, 16));
        let e = ".1.3.6.1.4.1.1206.4.2.18.3.2.1";
        let out = talk(
            &agent,
            &format!("set\n{e}.9.1\ninteger 4\nset\n{e}.4.1\noctet \"01\"\n"),
        );
        assert_eq!(out, "inconsistent-value\nwrong-type\n");
        let out = talk(
            &agent,
            "get\n.1.3.6.1.4.1.1206.4.2.18.13.1.0\nget\n.1.3.6.1.4.1.1206.4.2.18.99.0\n",
        );
        assert!(
            out.starts_with(".1.3.6.1.4.1.1206.4.2.18.13.1.0\noctet\n4e 54"),
            "{out}"
        );
        assert!(out.ends_with("NONE\n"));
    }

    #[test]
    fn parses_every_value_form() {
        assert_eq!(parse_value("integer 42"), Some(Val::Int(42)));
        assert_eq!(
            parse_value("string \"he said \"hi\"\""),
            Some(Val::Octets(b"he said \"hi\"".to_vec()))
        );
        assert_eq!(
            parse_value("octet \"de ad 00\""),
            Some(Val::Octets(vec![0xde, 0xad, 0]))
        );
        assert_eq!(parse_value("string \"\""), Some(Val::Octets(vec![])));
        assert_eq!(parse_value("octet \"zz\""), None);
        assert_eq!(parse_oid(".1.3.6"), Some(vec![1, 3, 6]));
    }
}
