//! The Host check against DNS rebinding: a page of another site whose name an attacker
//! points at the unit's address reaches the daemon with that site's name in `Host`, so only
//! the names the unit is known by are served (others get 421 Misdirected Request).
//!
//! Allowed by default: the address the request reached (the local address of its
//! connection, so it holds on every interface the daemon listens on), `localhost`, and the
//! configured host name; `[http] allowed_hosts` replaces that list. A port in `Host` must
//! be the port the request reached; a `Host` without a port is taken as it is.

use std::net::{IpAddr, SocketAddr};

/// Why a request's host was refused (the counter reason is [`HostRefusal::reason`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HostRefusal {
    /// Neither a `Host` header nor an absolute request target.
    Missing,
    /// Not a host of the allowed list, or a wrong port, or not a host at all.
    Wrong,
}

impl HostRefusal {
    /// The counter reason.
    pub const fn reason(self) -> &'static str {
        match self {
            HostRefusal::Missing => "missing host",
            HostRefusal::Wrong => "wrong host",
        }
    }
}

/// One allowed entry.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Entry {
    Name(String),
    Ip(IpAddr),
}

/// The hosts the daemon answers to.
#[derive(Clone, Debug)]
pub struct AllowedHosts {
    entries: Vec<Entry>,
    /// The defaults also allow the address the request reached.
    local_address: bool,
}

impl AllowedHosts {
    /// From the configuration: `allowed` when not empty, else the defaults (the reached
    /// address, `localhost` and `hostname`). Entries are checked by the configuration
    /// ([`valid_host_entry`]); one that is not is left out.
    pub fn new(hostname: Option<&str>, allowed: &[String]) -> Self {
        let parse = |s: &str| match s.parse::<IpAddr>() {
            Ok(ip) => Some(Entry::Ip(ip.to_canonical())),
            Err(_) => valid_host_entry(s).then(|| Entry::Name(normalise_name(s))),
        };
        if allowed.is_empty() {
            let names = std::iter::once("localhost").chain(hostname);
            Self {
                entries: names.filter_map(parse).collect(),
                local_address: true,
            }
        } else {
            Self {
                entries: allowed.iter().filter_map(|s| parse(s)).collect(),
                local_address: false,
            }
        }
    }

    /// Checks the authority a request names (its absolute target's, else its `Host`
    /// header), for a request that reached `local`.
    pub fn check(&self, authority: Option<&str>, local: SocketAddr) -> Result<(), HostRefusal> {
        let authority = authority.ok_or(HostRefusal::Missing)?;
        let (host, port) = split_authority(authority).ok_or(HostRefusal::Wrong)?;
        if port.is_some_and(|p| p != local.port()) {
            return Err(HostRefusal::Wrong);
        }
        let ok = match host.parse::<IpAddr>() {
            Ok(ip) => {
                let ip = ip.to_canonical();
                (self.local_address && ip == local.ip().to_canonical())
                    || self.entries.contains(&Entry::Ip(ip))
            }
            Err(_) => self.entries.contains(&Entry::Name(normalise_name(host))),
        };
        if ok {
            Ok(())
        } else {
            Err(HostRefusal::Wrong)
        }
    }
}

/// Lower case, without the trailing dot of a fully qualified name.
fn normalise_name(name: &str) -> String {
    name.strip_suffix('.').unwrap_or(name).to_ascii_lowercase()
}

/// Whether `s` is a host name (letters, digits, `-`, `.`; labels of 1 to 63) or an IP
/// address, without a port.
pub fn valid_host_entry(s: &str) -> bool {
    if s.parse::<IpAddr>().is_ok() {
        return true;
    }
    let name = s.strip_suffix('.').unwrap_or(s);
    !name.is_empty()
        && name.len() <= 253
        && name.split('.').all(|label| {
            (1..=63).contains(&label.len())
                && label
                    .bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b == b'-')
        })
}

/// `host[:port]` or `[v6][:port]` into the host and the port; `None` when it is neither.
fn split_authority(authority: &str) -> Option<(&str, Option<u16>)> {
    let (host, port) = if let Some(rest) = authority.strip_prefix('[') {
        let (v6, after) = rest.split_once(']')?;
        v6.parse::<std::net::Ipv6Addr>().ok()?;
        match after {
            "" => (v6, None),
            _ => (v6, Some(after.strip_prefix(':')?)),
        }
    } else {
        match authority.rsplit_once(':') {
            Some((host, port)) => (host, Some(port)),
            None => (authority, None),
        }
    };
    let port = match port {
        None => None,
        Some(p) if !p.is_empty() && p.len() <= 5 && p.bytes().all(|b| b.is_ascii_digit()) => {
            Some(p.parse().ok()?)
        }
        Some(_) => return None,
    };
    let host_ok = host.parse::<IpAddr>().is_ok() || valid_host_entry(host);
    host_ok.then_some((host, port))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(s: &str) -> SocketAddr {
        s.parse().unwrap()
    }

    #[test]
    fn the_defaults_take_the_reached_address_localhost_and_the_hostname() {
        let hosts = AllowedHosts::new(Some("OBU.local"), &[]);
        let local = at("192.168.4.1:8080");
        for ok in [
            "192.168.4.1",
            "192.168.4.1:8080",
            "localhost:8080",
            "LOCALHOST",
            "obu.local",
            "obu.local.:8080",
        ] {
            assert_eq!(hosts.check(Some(ok), local), Ok(()), "{ok}");
        }
        for bad in [
            "evil.example",
            "evil.example:8080",
            "192.168.4.1:80",
            "127.0.0.1:8080",
            "obu.local:8081",
            "192.168.4.1:",
            "192.168.4.1:8080x",
            "192.168.4.1:99999999",
            "obu local",
            "",
            "[::1]:8080",
            "[192.168.4.1]:8080",
        ] {
            assert_eq!(
                hosts.check(Some(bad), local),
                Err(HostRefusal::Wrong),
                "{bad}"
            );
        }
        assert_eq!(hosts.check(None, local), Err(HostRefusal::Missing));
    }

    #[test]
    fn ipv6_and_mapped_addresses() {
        let hosts = AllowedHosts::new(None, &[]);
        assert_eq!(hosts.check(Some("[::1]:8080"), at("[::1]:8080")), Ok(()));
        assert_eq!(hosts.check(Some("[::1]"), at("[::1]:8080")), Ok(()));
        // A dual-stack socket sees IPv4 clients at a mapped address.
        let mapped = at("[::ffff:10.0.0.2]:8080");
        assert_eq!(hosts.check(Some("10.0.0.2:8080"), mapped), Ok(()));
        assert_eq!(
            hosts.check(Some("[::1]x"), at("[::1]:8080")),
            Err(HostRefusal::Wrong)
        );
        assert_eq!(
            hosts.check(Some("[zz]:8080"), at("[::1]:8080")),
            Err(HostRefusal::Wrong)
        );
    }

    #[test]
    fn a_configured_list_replaces_the_defaults() {
        let hosts = AllowedHosts::new(Some("obu.local"), &["10.1.1.1".into(), "tablet-gw".into()]);
        let local = at("127.0.0.1:80");
        assert_eq!(hosts.check(Some("10.1.1.1"), local), Ok(()));
        assert_eq!(hosts.check(Some("tablet-gw:80"), local), Ok(()));
        for no in ["127.0.0.1", "localhost", "obu.local"] {
            assert_eq!(
                hosts.check(Some(no), local),
                Err(HostRefusal::Wrong),
                "{no}"
            );
        }
    }

    #[test]
    fn entries_are_names_or_addresses() {
        for ok in ["obu.local", "a-b.c", "10.0.0.1", "::1", "x."] {
            assert!(valid_host_entry(ok), "{ok}");
        }
        for bad in [
            "",
            "a..b",
            "a b",
            "a:80",
            "[::1]",
            "-".repeat(64).as_str(),
            "é.local",
        ] {
            assert!(!valid_host_entry(bad), "{bad}");
        }
    }
}
