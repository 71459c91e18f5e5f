// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd's SNMP: an AgentX subagent (RFC 2741) of net-snmp's snmpd.
//!
//! A conformance class B PROFINET station answers SNMP with MIB-II's `system` group, the
//! LLDP-MIB and the LLDP-EXT-PNO-MIB. On Linux, snmpd owns UDP 161 (and ifTable); procimgd
//! attaches to it as a subagent over the AgentX socket and serves those groups from its
//! own data.
//!
//! The layers, each usable alone:
//!
//! - [`pdu`]: the AgentX PDU codec, sans-IO, in the smoltcp style (views, `Repr`s with
//!   `parse`, `emit` and `buffer_len`; no parser panics on any input; both byte orders);
//! - [`mib`]: the read-only MIB over plain data: the runtime fills a
//!   [`Snapshot`](mib::Snapshot), [`MibView`](mib::MibView) answers Get, GetNext and
//!   GetBulk from it in OID order;
//! - [`session`]: one AgentX session as a state machine, bytes in and bytes out, time
//!   passed in: open, register, answer, close;
//! - [`runner`]: the thin blocking part: connects to the master's socket, runs a session,
//!   reconnects every few seconds while the master is missing, until told to stop.
//!
//! # The runtime's side
//!
//! Run the runner on a thread of its own with a closure that takes a snapshot of the
//! station (called at most once per batch of requests, off the real-time path):
//!
//! ```no_run
//! use std::sync::atomic::AtomicBool;
//! use procimg_agentx::mib::Snapshot;
//! use procimg_agentx::runner::{self, RunnerConfig, RunnerEvent};
//!
//! # fn station_snapshot() -> Snapshot { Snapshot::example() }
//! let stop = AtomicBool::new(false);
//! runner::run(&RunnerConfig::default(), &stop, station_snapshot, |event| match event {
//!     RunnerEvent::ConnectFailed(master, e) => eprintln!("no AgentX master at {master}: {e}"),
//!     other => eprintln!("agentx: {other:?}"),
//! });
//! ```
//!
//! What a manager then reads is what [`MibView`](mib::MibView) makes of the snapshot:
//!
//! ```
//! use procimg_agentx::mib::{MibView, Snapshot};
//! use procimg_agentx::pdu::Value;
//!
//! let view = MibView::new(&Snapshot::example());
//! let sys_name = "1.3.6.1.2.1.1.5.0".parse().unwrap();
//! assert_eq!(view.get(&sys_name), Value::string("plc-station"));
//! ```
//!
//! # snmpd
//!
//! snmpd must run as AgentX master (`master agentx` in snmpd.conf, which Debian's
//! default configuration has); the subagent connects to `agentXSocket`
//! (`/var/agentx/master` unless set; `tcp:HOST:PORT` works too). A procimgd that does not
//! run as root needs `agentXPerms` to let it open the socket.
//!
//! snmpd serves the system group itself. How the subagent takes sysDescr to sysServices
//! over, as net-snmp 5.9.3 behaves (tried with this crate's session, see
//! [`SessionConfig::procimgd`](session::SessionConfig::procimgd)): snmpd registers each of
//! the seven objects as a subtree of its own (1.3.6.1.2.1.1.N) at priority 127. A more
//! specific registration wins before priority counts, so registering `system` whole is
//! accepted but changes nothing, at any priority; the same seven subtrees at priority 127
//! are refused (duplicateRegistration); at a better priority (1) they are taken over. The
//! session registers them as one range registration (1.3.6.1.2.1.1.\[1-7\]) at priority 1.
//! An instance registration (sysName.0 with INSTANCE_REGISTRATION) is also more specific
//! and wins at the default priority, for a subagent that wants single objects only.
//! sysORLastChange and sysORTable stay snmpd's, and so does everything outside the system
//! group and the LLDP-MIB (ifTable in particular).
//!
//! Debian's `snmp` package comes without the standard MIB files: its tools print numeric
//! OIDs (`snmpget -v2c -c public HOST 1.3.6.1.2.1.1.5.0`), and `sysName.0` is not known
//! by name unless the MIBs are installed.
#![deny(missing_docs)]

pub mod mib;
pub mod pdu;
pub mod runner;
pub mod session;
