// SPDX-License-Identifier: MIT OR Apache-2.0
//! The simulated plant of `network = "sim"`: every configured device (but those marked
//! `sim = "absent"`) as a simulated PROFINET device on an in-process Ethernet link and UDP
//! network, in a thread of its own (SCHED_FIFO below the cycle thread where allowed). The
//! controller reaches them exactly as it reaches real devices: DCP, RPC, alarms and cyclic
//! frames, byte for byte.

use super::sim_behaviour::DemoApplication;
use crate::config::{Config, SimBehaviour};
use crate::phy::datagram::{SimDatagram, SimDatagramPeer};
use crate::sys::clock::{now_ns, sleep_until_ns};
use procimg_nic::Nic;
use procimg_nic::sim_link::{self, LinkEnd};
use procimg_profinet::device::{Device, DeviceAction, DeviceSetup};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::record::{Im0, SoftwareRevision, blank_padded};
use std::net::SocketAddrV4;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

/// A simulated device running one of the demo's behaviours.
pub type DemoDevice = Device<DemoApplication>;

/// The longest the plant sleeps between looks at the link.
const MAX_SLEEP_NS: u64 = 500_000;
/// How long a plant without devices (all `absent`) sleeps between emptying the link: no
/// frame needs an answer, and a thread woken twice a cycle at a client's priority would
/// only get in the clients' way.
const IDLE_SLEEP_NS: u64 = 20_000_000;

/// The first four bytes of every simulated device's MAC address.
const MAC_PREFIX: [u8; 4] = [0x02, 0x50, 0x49, 0x00];

/// The MAC address of simulated device `d`: locally administered, `02:50:49:00:<d>`.
pub fn device_mac(d: usize) -> MacAddress {
    let d = d as u16;
    let [p0, p1, p2, p3] = MAC_PREFIX;
    MacAddress([p0, p1, p2, p3, (d >> 8) as u8, d as u8])
}

/// How many frames deep the plant's link is for `devices` devices: room for two cycles'
/// frames in each direction (a cyclic frame per device and cycle), so that a plant or cycle
/// thread one cycle late loses nothing; never less than the link's default.
pub fn link_depth(devices: usize) -> usize {
    sim_link::DEPTH.max(2 * devices)
}

/// Whom a frame on the link is addressed to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Addressee {
    /// Every device: a multicast or broadcast destination (DCP Identify).
    All,
    /// The device of this configuration index, by its [`device_mac`].
    Device(usize),
    /// No simulated device (another address, a runt).
    Nobody,
}

fn addressee(frame: &[u8]) -> Addressee {
    let Some(dst) = frame.get(..6) else {
        return Addressee::Nobody;
    };
    if dst[0] & 1 == 1 {
        Addressee::All
    } else if dst[..4] == MAC_PREFIX {
        Addressee::Device(usize::from(u16::from_be_bytes([dst[4], dst[5]])))
    } else {
        Addressee::Nobody
    }
}

/// The plant's devices, found by the destination of a frame. Offering each frame to every
/// device made the plant's work per cycle grow with the square of its devices (a cyclic
/// frame per device, each looked at by all): 256 devices kept a CPU busy and still fell
/// behind.
struct Devices {
    devices: Vec<DemoDevice>,
    /// Position in `devices` of the device with each configuration index (absent devices
    /// have none).
    position: Vec<Option<usize>>,
}

impl Devices {
    fn new(devices: Vec<DemoDevice>) -> Devices {
        let mut position = Vec::new();
        for (p, d) in devices.iter().enumerate() {
            if let Addressee::Device(i) = addressee(&d.station().mac().0) {
                if position.len() <= i {
                    position.resize(i + 1, None);
                }
                position[i] = Some(p);
            }
        }
        Devices { devices, position }
    }

    /// The devices `frame` is for.
    fn recipients(&mut self, frame: &[u8]) -> &mut [DemoDevice] {
        match addressee(frame) {
            Addressee::All => &mut self.devices,
            Addressee::Device(i) => match self.position.get(i).copied().flatten() {
                Some(p) => &mut self.devices[p..=p],
                None => &mut [],
            },
            Addressee::Nobody => &mut [],
        }
    }
}

/// The address a simulated device has of its own when the configuration gives it none:
/// 192.168.1.10 and up, as if set up in the field.
pub fn own_ip(d: usize) -> [u8; 4] {
    [192, 168, 1 + (d / 200) as u8, 10 + (d % 200) as u8]
}

/// The simulated devices of `config`, named, all but those with `sim = "absent"`: those
/// with a configured `ip` come without an address (the controller gives it to them by DCP,
/// as to a new device), the others with one of their own ([`own_ip`]).
pub fn devices(config: &Config) -> Vec<DemoDevice> {
    config
        .devices
        .iter()
        .enumerate()
        .filter(|(_, dev)| dev.sim != SimBehaviour::Absent)
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
    devices: Vec<DemoDevice>,
    mut link: LinkEnd,
    udp: SimDatagramPeer,
    stop: Arc<AtomicBool>,
    priority: u8,
) -> std::io::Result<JoinHandle<()>> {
    std::thread::Builder::new()
        .name("procimg-simnet".into())
        .stack_size(crate::sys::rt::HELPER_THREAD_STACK)
        .spawn(move || {
            // Without the right to (not root), the devices run at normal priority, as the
            // cycle thread then does too.
            let _ = crate::sys::rt::set_fifo(priority);
            let mut plant = Devices::new(devices);
            let mut out = Vec::new();
            // The devices' frames, sent once the link is not being read.
            let mut frames = Vec::new();
            while !stop.load(Ordering::Acquire) {
                let now = now_ns();
                while let Ok(true) = link.receive(&mut |frame| {
                    for d in plant.recipients(frame) {
                        d.on_frame(frame, now, &mut out);
                        deliver(&mut out, d, &mut frames, &udp);
                    }
                }) {
                    send_all(&mut frames, &mut link);
                }
                while let Ok(g) = udp.rx.try_recv() {
                    let to = g.to.ip().octets();
                    if let Some(d) = plant.devices.iter_mut().find(|d| d.station().ip() == to) {
                        d.on_datagram(g.from, g.to.port(), &g.payload, now, &mut out);
                        deliver(&mut out, d, &mut frames, &udp);
                    }
                }
                send_all(&mut frames, &mut link);
                let longest = if plant.devices.is_empty() {
                    IDLE_SLEEP_NS
                } else {
                    MAX_SLEEP_NS
                };
                let mut next = now + longest;
                for d in &mut plant.devices {
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
                    from: SocketAddrV4::new(d.station().ip().into(), from_port),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{DeviceConfig, Network};

    fn frame_to(dst: MacAddress) -> Vec<u8> {
        let mut f = dst.0.to_vec();
        f.extend_from_slice(&[0x02, 0, 0, 0, 0, 1, 0x88, 0x92, 0xc0, 0x00]);
        f
    }

    /// A sim network of `n` devices; those in `absent` are left out.
    fn plant(n: usize, absent: &[usize]) -> Devices {
        let mut config = Config::demo();
        config.network = Network::Sim;
        let template = config.devices[0].clone();
        config.devices = (0..n)
            .map(|d| DeviceConfig {
                name: format!("dev{d}"),
                sim: if absent.contains(&d) {
                    SimBehaviour::Absent
                } else {
                    SimBehaviour::None
                },
                ..template.clone()
            })
            .collect();
        Devices::new(devices(&config))
    }

    fn names(devices: &[DemoDevice]) -> Vec<String> {
        devices
            .iter()
            .map(|d| d.station().name().to_string())
            .collect()
    }

    #[test]
    fn a_unicast_frame_goes_to_its_device_only() {
        let mut p = plant(300, &[]);
        for d in [0, 1, 255, 256, 299] {
            assert_eq!(
                names(p.recipients(&frame_to(device_mac(d)))),
                [format!("dev{d}")]
            );
        }
    }

    #[test]
    fn multicast_and_broadcast_frames_go_to_every_device() {
        let mut p = plant(5, &[]);
        let dcp_identify = MacAddress([0x01, 0x0e, 0xcf, 0x00, 0x00, 0x00]);
        assert_eq!(p.recipients(&frame_to(dcp_identify)).len(), 5);
        assert_eq!(p.recipients(&frame_to(MacAddress([0xff; 6]))).len(), 5);
    }

    #[test]
    fn frames_for_no_simulated_device_go_nowhere() {
        let mut p = plant(7, &[]);
        // Beyond the plant, another prefix, the controller's own address, a runt.
        assert!(p.recipients(&frame_to(device_mac(7))).is_empty());
        let other = MacAddress([0x02, 0x50, 0x49, 0x01, 0, 1]);
        assert!(p.recipients(&frame_to(other)).is_empty());
        assert!(
            p.recipients(&frame_to(super::super::SIM_CONTROLLER_MAC))
                .is_empty()
        );
        assert!(p.recipients(&[0x02, 0x50]).is_empty());
    }

    #[test]
    fn absent_devices_are_not_on_the_network_and_the_others_keep_their_addresses() {
        let mut p = plant(4, &[0, 2]);
        assert_eq!(names(&p.devices), ["dev1", "dev3"]);
        assert!(p.recipients(&frame_to(device_mac(0))).is_empty());
        assert!(p.recipients(&frame_to(device_mac(2))).is_empty());
        assert_eq!(names(p.recipients(&frame_to(device_mac(3)))), ["dev3"]);
        let broadcast = frame_to(MacAddress([0xff; 6]));
        assert_eq!(names(p.recipients(&broadcast)), ["dev1", "dev3"]);
    }
}
