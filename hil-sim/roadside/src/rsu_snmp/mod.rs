//! RSU management over SNMP: the roadside deposits its MAP and TIMs into each RSU's
//! store-and-repeat table (NTCIP 1218 `rsuMsgRepeatStatusTable`, or RSU 4.1
//! `rsuSRMStatusTable` on older units), keeps them there, and sends cancels through the
//! immediate-forward table, as USDOT's jpo-ode and V2X-Hub program RSUs.
//!
//! - [`credentials`]: the 0600 file of SNMPv3 users (and v2c communities for lab units);
//! - [`session`]: one SNMP session with one RSU (the `snmp2` crate), outcomes as a closed
//!   set;
//! - [`mib`]: object identifiers and row encodings of the two MIBs;
//! - [`dates`]: `DateAndTime` and the RSU 4.1 date;
//! - [`deposit`]: the site's messages as rows (PSID, window, who signs);
//! - [`reconcile`]: the pure plan that brings a table to what is wanted;
//! - [`fleet`]: many RSUs from one process (workers, backoff, counters, owned rows);
//! - [`table`]: one pass over one RSU (read, plan, write) and its problems in an
//!   operator's terms.

pub mod credentials;
pub mod dates;
pub mod deposit;
pub mod fleet;
pub mod mib;
pub mod reconcile;
pub mod session;
pub mod table;
