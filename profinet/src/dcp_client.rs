// SPDX-License-Identifier: MIT OR Apache-2.0
//! The requesting side of DCP, sans-IO: build a request, feed it the frames that come back,
//! and read the outcome. No socket and no clock inside: the caller sends the frame, passes
//! received frames to `on_frame`, and decides when the answer window is over.

use super::wire::dcp::{self, ServiceId, ServiceType};
use super::wire::ethernet::{self, ETHERTYPE_PROFINET};
use super::wire::{EmitResult, MacAddress};

/// A device as its Identify response describes it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeviceInfo {
    /// The device's MAC address (the response's source).
    pub mac: MacAddress,
    /// NameOfStation, if set.
    pub name: Option<String>,
    /// IP, mask, gateway.
    pub ip: Option<([u8; 4], [u8; 4], [u8; 4])>,
    /// Vendor and device ID.
    pub id: Option<(u16, u16)>,
    /// DeviceVendor (type of station).
    pub vendor: Option<String>,
}

/// An Ethernet frame (untagged) around a DCP PDU, padded to the Ethernet minimum.
pub fn frame(dst: MacAddress, src: MacAddress, repr: &dcp::Repr) -> EmitResult<Vec<u8>> {
    let eth = ethernet::Repr {
        dst,
        src,
        vlan: None,
        ethertype: ETHERTYPE_PROFINET,
    };
    Ok(eth.frame(&repr.to_vec()?, 60))
}

/// The DCP response in `frame` if it answers transaction `xid`: its source and its Repr.
fn response_to(frame: &[u8], xid: u32) -> Option<(MacAddress, dcp::Repr)> {
    let eth = ethernet::Frame::new_checked(frame).ok()?;
    if eth.ethertype() != ETHERTYPE_PROFINET {
        return None;
    }
    let repr = dcp::Repr::parse(&dcp::Packet::new_checked(eth.payload()).ok()?).ok()?;
    (repr.xid == xid && repr.service_type != ServiceType::Request).then_some((eth.src(), repr))
}

/// An Identify: all devices, or the one with a name; collects the responses.
pub struct Identify {
    xid: u32,
    found: Vec<DeviceInfo>,
}

impl Identify {
    /// A new Identify transaction.
    pub fn new(xid: u32) -> Identify {
        Identify {
            xid,
            found: Vec::new(),
        }
    }

    /// The request frame. Devices answer within `response_delay` × 10 ms (spread by their
    /// MAC), so collect for at least that long.
    pub fn request(
        &self,
        src: MacAddress,
        name: Option<&str>,
        response_delay: u16,
    ) -> EmitResult<Vec<u8>> {
        let repr = match name {
            Some(n) => dcp::Repr::identify_by_name(self.xid, response_delay, n),
            None => dcp::Repr::identify_all(self.xid, response_delay),
        };
        frame(MacAddress::DCP_IDENTIFY, src, &repr)
    }

    /// Takes a received frame; returns whether it answered this Identify.
    pub fn on_frame(&mut self, frame: &[u8]) -> bool {
        let Some((mac, r)) = response_to(frame, self.xid) else {
            return false;
        };
        // The device is listed under the MAC address it names, else the frame's source; a
        // second answer from either is the same device.
        let device_mac = r.mac().unwrap_or(mac);
        if r.service_id != ServiceId::Identify
            || self
                .found
                .iter()
                .any(|d| d.mac == mac || d.mac == device_mac)
        {
            return false;
        }
        self.found.push(DeviceInfo {
            mac: device_mac,
            name: r.name_of_station().map(str::to_string),
            ip: r.ip(),
            id: r.device_id(),
            vendor: r.device_vendor().map(str::to_string),
        });
        true
    }

    /// The devices that answered, in order of arrival.
    pub fn devices(&self) -> &[DeviceInfo] {
        &self.found
    }
}

/// The outcome of a Set.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SetOutcome {
    /// Every block was accepted.
    Done,
    /// The device refused: (option, suboption, BlockError) per refused block.
    Refused(Vec<(u8, u8, u8)>),
    /// The device does not support the request.
    NotSupported,
}

impl core::fmt::Display for SetOutcome {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SetOutcome::Done => f.write_str("done"),
            SetOutcome::NotSupported => f.write_str("the device does not support this request"),
            SetOutcome::Refused(errs) => {
                f.write_str("refused:")?;
                for (o, s, e) in errs {
                    let why = match e {
                        1 => "option not supported",
                        2 => "suboption not supported or no data set",
                        3 => "suboption not set",
                        4 => "resource error",
                        5 => "set not possible (local reasons)",
                        6 => "set not possible in operation",
                        _ => "unknown error",
                    };
                    write!(f, " block {o:02x}/{s:02x}: {why} ({e});")?;
                }
                Ok(())
            }
        }
    }
}

/// A Set (name, IP, signal) to one device; reads its answer.
pub struct Set {
    xid: u32,
    device: MacAddress,
    repr: dcp::Repr,
}

impl Set {
    /// Sets the NameOfStation.
    pub fn name(xid: u32, device: MacAddress, name: &str, permanent: bool) -> Set {
        Set {
            xid,
            device,
            repr: dcp::Repr::set_name(xid, name, permanent),
        }
    }

    /// Sets the IP parameters.
    pub fn ip(
        xid: u32,
        device: MacAddress,
        ip: [u8; 4],
        mask: [u8; 4],
        gateway: [u8; 4],
        permanent: bool,
    ) -> Set {
        Set {
            xid,
            device,
            repr: dcp::Repr::set_ip(xid, ip, mask, gateway, permanent),
        }
    }

    /// Resets the device's communication parameters to factory (reset mode 2: no name, no
    /// IP address).
    pub fn reset_to_factory(xid: u32, device: MacAddress) -> Set {
        Set {
            xid,
            device,
            repr: dcp::Repr::reset_to_factory(xid, 2),
        }
    }

    /// Flashes the device's LED (DCP Signal).
    pub fn signal(xid: u32, device: MacAddress) -> Set {
        Set {
            xid,
            device,
            repr: dcp::Repr::signal(xid),
        }
    }

    /// The request frame.
    pub fn request(&self, src: MacAddress) -> EmitResult<Vec<u8>> {
        frame(self.device, src, &self.repr)
    }

    /// Takes a received frame; the outcome if it is the device's answer.
    pub fn on_frame(&self, frame: &[u8]) -> Option<SetOutcome> {
        let (mac, r) = response_to(frame, self.xid)?;
        if mac != self.device || r.service_id != ServiceId::Set {
            return None;
        }
        if r.service_type == ServiceType::NotSupported {
            return Some(SetOutcome::NotSupported);
        }
        let refused: Vec<(u8, u8, u8)> = r.set_result().filter(|&(_, _, e)| e != 0).collect();
        Some(if refused.is_empty() {
            SetOutcome::Done
        } else {
            SetOutcome::Refused(refused)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_fixtures::capture;

    /// p-net's Identify response and Set response from the S7-1515 capture
    /// (captures/cm/ident_ok_pnet.hex, dcp_set_res.hex; pnio crate 0.1.0, MIT OR Apache-2.0).
    #[test]
    fn captured_answers_are_recognised() {
        let ident = capture("cm/ident_ok_pnet");
        let mut id = Identify::new(0x0300_012c);
        assert!(id.on_frame(&ident));
        assert!(!id.on_frame(&ident), "a device is listed once");
        let d = &id.devices()[0];
        assert_eq!(d.name.as_deref(), Some("rt-labs-dev"));
        assert_eq!(d.id, Some((0x0493, 0x0002)));
        assert_eq!(d.mac, MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8]));
        assert!(!Identify::new(1).on_frame(&ident), "another transaction");

        let set_res = capture("cm/dcp_set_res");
        let set = Set::ip(
            0x0300_012d,
            d.mac,
            [172, 16, 2, 10],
            [255, 255, 255, 0],
            [172, 16, 2, 10],
            false,
        );
        assert_eq!(set.on_frame(&set_res), Some(SetOutcome::Done));
        assert_eq!(
            Set::signal(0x0300_012d, MacAddress([1; 6])).on_frame(&set_res),
            None
        );
    }

    /// An answer whose MAC address block names another address than the frame's source
    /// (found by the `dcp` fuzz target): listed once all the same.
    #[test]
    fn an_answer_naming_another_mac_is_listed_once() {
        let pdu = [
            0xfe, 0x01, 0x05, 0x0f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x12, 0x01, 0x01,
            0x00, 0x08, 0x05, 0x36, 0xd8, 0x1e, 0x00, 0x00, 0x00, 0x00, 0x00, 0x76, 0x00, 0x02,
            0xf2, 0x00, 0xf6,
        ];
        let eth = ethernet::Repr {
            dst: MacAddress([2, 0, 0, 0, 0, 1]),
            src: MacAddress([2, 0, 0, 0, 0, 2]),
            vlan: None,
            ethertype: ethernet::ETHERTYPE_PROFINET,
        };
        let mut frame = vec![0u8; eth.buffer_len()];
        eth.emit(&mut frame).unwrap();
        frame.extend_from_slice(&pdu);
        let mut id = Identify::new(0);
        assert!(id.on_frame(&frame), "an answer to the transaction");
        assert!(!id.on_frame(&frame), "a device is listed once");
        assert_eq!(id.devices().len(), 1);
    }

    #[test]
    fn requests_are_dcp_frames() {
        let me = MacAddress([2, 0, 0, 0, 0, 1]);
        let f = Identify::new(5).request(me, Some("echo"), 1).unwrap();
        assert_eq!(&f[..6], &MacAddress::DCP_IDENTIFY.0);
        assert_eq!(f.len(), 60);
        let f = Set::name(6, MacAddress([2; 6]), "echo", true)
            .request(me)
            .unwrap();
        assert_eq!(&f[..6], &[2; 6]);
        let f = Set::reset_to_factory(7, MacAddress([2; 6]))
            .request(me)
            .unwrap();
        let eth = ethernet::Frame::new_checked(&f[..]).unwrap();
        let r = dcp::Repr::parse(&dcp::Packet::new_checked(eth.payload()).unwrap()).unwrap();
        assert_eq!((r.xid, r.service_id), (7, ServiceId::Set));
        // Reset mode 2 (communication parameters) in bits 1 to 15 of the qualifier.
        assert!(matches!(
            r.blocks[..],
            [dcp::Block {
                value: dcp::BlockRepr::ResetToFactory(4),
                ..
            }]
        ));
    }
}
