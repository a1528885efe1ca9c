//! `roadside rsu probe|status|deposit|clear`.

use crate::CommandError;
use clap::Subcommand;
use roadside::clock::Utc;
use roadside::rsu_snmp::fleet::{
    load_owned, save_owned, OwnedFileError, RsuSpec, RsuStatus, REASONS,
};
use roadside::rsu_snmp::reconcile::Columns;
use roadside::rsu_snmp::session::{Agent, Session, SnmpValue};
use roadside::rsu_snmp::table::{payload_digest, probe, read_table, reconcile, Owned, TableRules};
use roadside::site_file::SiteFile;
use std::collections::BTreeMap;
use std::path::PathBuf;

#[derive(Debug, Subcommand)]
pub enum RsuCommand {
    /// Which MIB each RSU answers (NTCIP 1218 or RSU 4.1), its firmware and id; exit 1 when
    /// an RSU answers another MIB than its entry says, or none.
    Probe(Which),
    /// Each RSU's store-and-repeat table as it stands (ours, foreign), and the running
    /// roadside's counters (from the state folder's status.json).
    Status(Which),
    /// One reconciliation pass now (what `run` does at each poll); exit 1 unless every RSU
    /// is in step.
    Deposit(Which),
    /// Destroy the rows the roadside placed (with --all-rows: every row of the table).
    Clear {
        #[command(flatten)]
        which: Which,
        /// Every row, also those other managers placed.
        #[arg(long)]
        all_rows: bool,
    },
}

#[derive(Debug, clap::Args)]
pub struct Which {
    /// The site file.
    #[arg(long, value_name = "SITE.toml")]
    site: PathBuf,
    /// Only this RSU (its name in the site file).
    #[arg(long, value_name = "NAME")]
    rsu: Option<String>,
}

struct Ctx {
    site: SiteFile,
    specs: Vec<RsuSpec>,
}

fn ctx(w: &Which) -> Result<Ctx, CommandError> {
    let site = SiteFile::load(&w.site)?;
    let mut specs = site.rsu_specs()?;
    if let Some(name) = &w.rsu {
        specs.retain(|s| &s.name == name);
        if specs.is_empty() {
            return Err(format!("{}: no [[rsu]] named {name}", w.site.display()).into());
        }
    }
    Ok(Ctx { site, specs })
}

fn session(site: &SiteFile, s: &RsuSpec) -> Session {
    let t = site.timing();
    Session::new(s.address, s.credentials.clone(), t.timeout, t.retries)
}

pub fn rsu(c: &RsuCommand) -> Result<bool, CommandError> {
    match c {
        RsuCommand::Probe(w) => probe_all(&ctx(w)?),
        RsuCommand::Status(w) => status(&ctx(w)?),
        RsuCommand::Deposit(w) => {
            let stop = std::sync::atomic::AtomicBool::new(false);
            let reload = std::sync::atomic::AtomicBool::new(false);
            let c = ctx(w)?;
            if w.rsu.is_some() {
                return Err("deposit works on the whole site (leave out --rsu)".into());
            }
            let ok = roadside::service::run(&w.site, &stop, &reload, true, &mut std::io::stdout())?;
            let _ = status(&c);
            Ok(ok)
        }
        RsuCommand::Clear { which, all_rows } => clear(&ctx(which)?, *all_rows),
    }
}

fn probe_all(c: &Ctx) -> Result<bool, CommandError> {
    let mut ok = true;
    for s in &c.specs {
        let mut session = session(&c.site, s);
        match probe(&mut session) {
            Ok(speaks) if speaks.is_empty() => {
                ok = false;
                println!(
                    "{}  {}  answers neither NTCIP 1218 nor RSU 4.1",
                    s.name, s.address
                );
            }
            Ok(speaks) => {
                for (mib, version) in &speaks {
                    let [fw, id] = mib.identity();
                    let got = session.get(&[fw, id]).unwrap_or_default();
                    // Text from the RSU, shown escaped (no control characters reach the
                    // terminal).
                    let text = |v: Option<&SnmpValue>| match v {
                        Some(SnmpValue::Octets(o)) => {
                            String::from_utf8_lossy(o).escape_debug().to_string()
                        }
                        _ => "-".into(),
                    };
                    let matches = *mib == s.rules.mib;
                    ok &= matches || speaks.iter().any(|(m, _)| *m == s.rules.mib);
                    println!(
                        "{}  {}  speaks {} ({}); firmware {}; id {}{}",
                        s.name,
                        s.address,
                        mib.name(),
                        version.escape_debug(),
                        text(got.first()),
                        text(got.get(1)),
                        if matches {
                            ""
                        } else {
                            "  <- the site says another MIB"
                        }
                    );
                }
            }
            Err(e) => {
                ok = false;
                println!("{}  {}  {e}", s.name, s.address);
            }
        }
    }
    Ok(ok)
}

fn owned_of(site: &SiteFile) -> Result<BTreeMap<String, Owned>, OwnedFileError> {
    load_owned(&site.state_dir().join("owned.json"))
}

fn status(c: &Ctx) -> Result<bool, CommandError> {
    let owned = owned_of(&c.site)?;
    let running = roadside::service::read_status(&c.site.state_dir());
    if let Some(feed) = running.as_ref().and_then(|s| s.feed.as_ref()) {
        let counts: Vec<String> = feed
            .counts
            .iter()
            .map(|(k, v)| format!("{k} {v}"))
            .collect();
        println!(
            "wzdx feed {}: {}; {} zones; last good {}; polls: {}",
            feed.url,
            feed.problem.as_deref().unwrap_or("good"),
            feed.zones,
            when(feed.last_good_unix_ms),
            counts.join(", ")
        );
    }
    let counters: Vec<RsuStatus> = running.map(|s| s.rsus).unwrap_or_default();
    let mut ok = true;
    for s in &c.specs {
        println!("{}  {}  {}", s.name, s.address, s.rules.mib.name());
        if let Some(st) = counters.iter().find(|x| x.name == s.name) {
            let n = |k: &str| st.counts.get(k).copied().unwrap_or(0);
            let problems: Vec<String> = REASONS
                .iter()
                .filter(|r| n(r) > 0)
                .map(|r| format!("{r} {}", n(r)))
                .collect();
            println!(
                "  roadside: {} at {}; passes {} (converged {}, changed {}), rows created {}, destroyed {}; problems: {}; requests {} reads, {} writes",
                st.problem.as_deref().unwrap_or("in step"),
                when(st.last_pass_unix_ms),
                n("passes"),
                n("converged"),
                n("changed"),
                n("created"),
                n("destroyed"),
                if problems.is_empty() { "none".into() } else { problems.join(", ") },
                st.reads,
                st.writes
            );
        }
        let mut session = session(&c.site, s);
        match read_table(&mut session, s.rules.mib) {
            Ok(rows) => print_rows(s, &rows, owned.get(&s.name)),
            Err(e) => {
                ok = false;
                println!("  table: {e}");
            }
        }
    }
    Ok(ok)
}

fn when(unix_ms: u64) -> String {
    if unix_ms == 0 {
        return "-".into();
    }
    Utc::from_unix_ms(unix_ms).rfc3339_seconds()
}

fn print_rows(s: &RsuSpec, rows: &BTreeMap<u32, Columns>, owned: Option<&Owned>) {
    use roadside::rsu_snmp::mib::RsuMib;
    // (psid, channel, interval, start, stop, payload, enable, status) columns.
    let cols = match s.rules.mib {
        RsuMib::Ntcip1218 => [2, 3, 4, 5, 6, 7, 8, 9],
        RsuMib::Rsu41 => [2, 5, 6, 7, 8, 9, 10, 11],
    };
    if rows.is_empty() {
        println!("  table: empty");
        return;
    }
    println!("  index  psid         ch   every  start              stop               on  status  bytes  row");
    for (index, r) in rows {
        let show = |c: usize| match r.get(&cols[c]) {
            Some(SnmpValue::Integer(i)) => i.to_string(),
            Some(SnmpValue::Octets(o)) if c == 3 || c == 4 => {
                roadside::rsu_snmp::dates::unix_ms_of(o)
                    .map_or_else(|| "?".into(), |ms| when(ms)[..16].to_string())
            }
            Some(SnmpValue::Octets(o)) if c == 5 => o.len().to_string(),
            Some(SnmpValue::Octets(o)) => o
                .iter()
                .map(|b| format!("{b:02x}"))
                .collect::<Vec<_>>()
                .join(" "),
            _ => "-".into(),
        };
        let payload = match r.get(&cols[5]) {
            Some(SnmpValue::Octets(p)) => Some(payload_digest(p)),
            _ => None,
        };
        let ours = owned
            .and_then(|o| o.get(index))
            .is_some_and(|d| Some(*d) == payload);
        let status = match r.get(&cols[7]) {
            Some(SnmpValue::Integer(1)) => "active".to_string(),
            Some(SnmpValue::Integer(i)) => format!("({i})"),
            _ => "-".into(),
        };
        println!(
            "  {index:<6} {:<12} {:<4} {:<6} {:<18} {:<18} {:<3} {:<7} {:<6} {}",
            show(0),
            show(1),
            show(2),
            show(3),
            show(4),
            show(6),
            status,
            show(5),
            if ours { "ours" } else { "foreign" }
        );
    }
}

fn clear(c: &Ctx, all_rows: bool) -> Result<bool, CommandError> {
    let mut owned = owned_of(&c.site)?;
    let mut ok = true;
    for s in &c.specs {
        let mut session = session(&c.site, s);
        let rules = TableRules {
            manage_all: all_rows,
            ..s.rules
        };
        let mine = owned.entry(s.name.clone()).or_default();
        match reconcile(&mut session, rules, &[], mine) {
            Ok(r) => println!(
                "{}: {} rows destroyed, {} left alone",
                s.name,
                r.destroyed,
                r.plan.foreign.len()
            ),
            Err(e) => {
                ok = false;
                println!("{}: {e}", s.name);
            }
        }
    }
    save_owned(&c.site.state_dir().join("owned.json"), &owned)?;
    Ok(ok)
}
