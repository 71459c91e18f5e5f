// SPDX-License-Identifier: MIT OR Apache-2.0
//! The simulated plant of `network = "sim"`: every configured device as a simulated
//! PROFINET device on an in-process Ethernet link and UDP network, in a thread of its own at
//! normal priority. The controller reaches them exactly as it reaches real devices: DCP,
//! RPC, alarms and cyclic frames, byte for byte.

use super::sim_behaviour::DemoApplication;
use crate::config::Config;
use crate::phy::datagram::{SimDatagram, SimDatagramPeer};
use procimg_nic::Nic;
use procimg_nic::sim_link::LinkEnd;
use procimg_profinet::device::{Device, DeviceAction, DeviceSetup};

/// A simulated device running one of the demo's behaviours.
pub type DemoDevice = Device<DemoApplication>;
use crate::sys::clock::{now_ns, sleep_until_ns};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::record::{Im0, SoftwareRevision, blank_padded};
use std::net::SocketAddrV4;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

/// The longest the plant sleeps between looks at the link.
const MAX_SLEEP_NS: u64 = 500_000;

/// The MAC address of simulated device `d`: locally administered, `02:50:49:00:<d>`.
pub fn device_mac(d: usize) -> MacAddress {
    let d = d as u16;
    MacAddress([0x02, 0x50, 0x49, 0x00, (d >> 8) as u8, d as u8])
}

/// The address a simulated device has of its own when the configuration gives it none:
/// 192.168.1.10 and up, as if set up in the field.
pub fn own_ip(d: usize) -> [u8; 4] {
    [192, 168, 1 + (d / 200) as u8, 10 + (d % 200) as u8]
}

/// The simulated devices of `config`, named: those with a configured `ip` come without an
/// address (the controller gives it to them by DCP, as to a new device), the others with one
/// of their own ([`own_ip`]).
pub fn devices(config: &Config) -> Vec<DemoDevice> {
    config
        .devices
        .iter()
        .enumerate()
        .map(|(d, dev)| {
            Device::new(DeviceSetup {
                name: dev.name.clone(),
                mac: device_mac(d),
                ip: dev.ip.is_none().then(|| own_ip(d)),
                vendor_id: dev.vendor_id,
                device_id: dev.device_id,
                instance: dev.instance,
                submodules: dev.submodules.iter().map(crate::roles::plugged).collect(),
                application: DemoApplication(dev.sim),
                im0: Im0 {
                    vendor_id: dev.vendor_id,
                    order_id: blank_padded("PROCIMG-SIM").unwrap_or([b' '; 20]),
                    serial_number: blank_padded(&format!("SIM{d:05}")).unwrap_or([b' '; 16]),
                    hardware_revision: 1,
                    software_revision: SoftwareRevision {
                        prefix: b'V',
                        functional_enhancement: 1,
                        bug_fix: 0,
                        internal_change: 0,
                    },
                    revision_counter: 0,
                    profile_id: 0,
                    profile_specific_type: 0,
                    im_version: (1, 1),
                    im_supported: 0,
                },
            })
        })
        .collect()
}

/// Runs `devices` on `link` and `udp` until `stop`. The thread runs SCHED_FIFO at `priority`
/// where allowed (below the cycle thread, out of its way), else at normal priority, where
/// the scheduler may delay it by milliseconds: simulated devices want a larger
/// `watchdog_factor` than real ones (the demo's is 100).
pub fn spawn(
    mut devices: Vec<DemoDevice>,
    mut link: LinkEnd,
    udp: SimDatagramPeer,
    stop: Arc<AtomicBool>,
    priority: u8,
) -> std::io::Result<JoinHandle<()>> {
    std::thread::Builder::new()
        .name("procimg-simnet".into())
        .spawn(move || {
            // Without the right to (not root), the devices run at normal priority, as the
            // cycle thread then does too.
            let _ = crate::sys::rt::set_fifo(priority);
            let mut out = Vec::new();
            // The devices' frames, sent once the link is not being read.
            let mut frames = Vec::new();
            while !stop.load(Ordering::Acquire) {
                let now = now_ns();
                while let Ok(true) = link.receive(&mut |frame| {
                    for d in &mut devices {
                        d.on_frame(frame, now, &mut out);
                        deliver(&mut out, d, &mut frames, &udp);
                    }
                }) {
                    send_all(&mut frames, &mut link);
                }
                while let Ok(g) = udp.rx.try_recv() {
                    if let Some(d) = devices.iter_mut().find(|d| d.ip() == g.to.ip().octets()) {
                        d.on_datagram(g.from, g.to.port(), &g.payload, now, &mut out);
                        deliver(&mut out, d, &mut frames, &udp);
                    }
                }
                send_all(&mut frames, &mut link);
                let mut next = now + MAX_SLEEP_NS;
                for d in &mut devices {
                    d.poll(now, &mut out);
                    deliver(&mut out, d, &mut frames, &udp);
                    if let Some(t) = d.next_deadline_ns() {
                        next = next.min(t);
                    }
                }
                send_all(&mut frames, &mut link);
                sleep_until_ns(next.max(now + 20_000));
            }
        })
}

/// Sends the datagrams of `out` and moves its frames to `frames`.
fn deliver(
    out: &mut Vec<DeviceAction>,
    d: &DemoDevice,
    frames: &mut Vec<Vec<u8>>,
    udp: &SimDatagramPeer,
) {
    for a in out.drain(..) {
        match a {
            DeviceAction::Frame(f) => frames.push(f),
            DeviceAction::Datagram {
                to,
                from_port,
                payload,
            } => {
                let _ = udp.tx.send(SimDatagram {
                    from: SocketAddrV4::new(d.ip().into(), from_port),
                    to,
                    payload,
                });
            }
            // The simulated devices run their own cyclic exchange.
            DeviceAction::StartCyclic(_)
            | DeviceAction::StopCyclic { .. }
            | DeviceAction::Record(_)
            | DeviceAction::ArCheck(_)
            | DeviceAction::DcpSetCheck(_) => {}
        }
    }
}

fn send_all(frames: &mut Vec<Vec<u8>>, link: &mut LinkEnd) {
    for f in frames.drain(..) {
        // A full link drops, as a real one does.
        let _ = link.send(&f);
    }
}
