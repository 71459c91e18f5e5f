// SPDX-License-Identifier: MIT OR Apache-2.0
//! The DCP side of a station, an IO device's or an IO controller's alike: Identify (all, by
//! name and the other filters, answered after the ResponseDelay the request asks for), Get,
//! and the Set of the IP parameters and NameOfStation, Signal, start/stop transaction and
//! reset to factory; and the Hello request a device may send at start-up. The station's
//! role (IO device, IO controller) is its [`DcpIdentity::role`]; what a Set changes comes
//! back as [`DcpChanges`] for the station to act on, and a Set the station wants to hold
//! first (a device program's veto) comes back unanswered.

use crate::wire::MacAddress;
use crate::wire::dcp::{self, Block, BlockRepr, ServiceId, ServiceType, block_error, code};
use crate::wire::ethernet::profinet_frame;

/// DeviceRole bit 0: IO device.
pub const ROLE_IO_DEVICE: u8 = 0x01;
/// DeviceRole bit 1: IO controller.
pub const ROLE_IO_CONTROLLER: u8 = 0x02;
/// BlockInfo of the IP parameter block: bit 0, an IP address is set.
const BLOCK_INFO_IP_SET: u16 = 0x0001;
/// Longest NameOfStation.
const MAX_NAME_LEN: usize = 240;
/// Identify responses waiting for their delay at most; more requests in the window are not
/// answered (a bound against a flood, far above what a network of controllers sends).
const MAX_PENDING: usize = 64;

/// The Xid of the Hello request (one per start-up, as p-net's).
const HELLO_XID: u32 = 1;
/// DeviceInitiative bit 0: the device sends a Hello request at start-up.
const INITIATIVE_HELLO: u16 = 0x0001;

/// The (option, suboption) pairs we answer in Get and announce in DeviceOptions.
const OPTIONS: [(u8, u8); 14] = [
    code::MAC_ADDRESS,
    code::IP_PARAMETER,
    code::FULL_IP_SUITE,
    code::DEVICE_VENDOR,
    code::NAME_OF_STATION,
    code::DEVICE_ID,
    code::DEVICE_ROLE,
    code::DEVICE_OPTIONS,
    code::DEVICE_INSTANCE,
    code::CONTROL_START,
    code::CONTROL_STOP,
    code::CONTROL_SIGNAL,
    code::RESET_TO_FACTORY,
    code::DEVICE_INITIATIVE,
];

/// What a station is called and where it is, as DCP reads and sets it.
#[derive(Clone, Debug)]
pub struct DcpIdentity {
    /// The interface's MAC address.
    pub mac: MacAddress,
    /// NameOfStation (empty: none).
    pub name: String,
    /// IPv4 address (all zero: none).
    pub ip: [u8; 4],
    /// Subnet mask.
    pub mask: [u8; 4],
    /// Default gateway.
    pub gateway: [u8; 4],
    /// VendorID.
    pub vendor_id: u16,
    /// DeviceID.
    pub device_id: u16,
    /// Instance.
    pub instance: u16,
    /// The type of station (DeviceVendorValue).
    pub type_of_station: String,
    /// DeviceRole: [`ROLE_IO_DEVICE`] or [`ROLE_IO_CONTROLLER`].
    pub role: u8,
    /// Whether the station sends a Hello request at start-up (its DeviceInitiative).
    pub hello: bool,
    /// The alias name its LLDP neighbour gives it (`<peer port>.<peer station>`), if it has
    /// one neighbour that names itself.
    pub alias: Option<String>,
}

/// What a Set changed, for the station to act on (a device's AR ends when its station
/// changes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DcpChanges {
    /// The NameOfStation changed.
    pub name: bool,
    /// The IP suite changed.
    pub ip: bool,
    /// The name was set to be kept permanently (BlockQualifier bit 0), changed or not.
    pub store_name: bool,
    /// The IP suite was set to be kept permanently.
    pub store_ip: bool,
    /// A Signal request arrived (flash the LED).
    pub signal: bool,
    /// Reset to factory (communication parameters).
    pub reset: bool,
}

/// What became of a DCP request.
#[derive(Debug)]
pub enum DcpRequest {
    /// Not for this station, or answered (an Identify, a Get).
    Done,
    /// A Set to this station: the station carries it out with [`answer_set`] (now, or once
    /// it has checked it), or refuses it with [`busy_response`].
    Set(dcp::Repr),
}

/// The Identify responses of a station waiting for their delay.
#[derive(Debug, Default)]
pub struct DcpAnswers {
    pending: Vec<(u64, Vec<u8>)>,
}

impl DcpAnswers {
    /// A DCP PDU (`pdu` from the FrameID on) in a frame from `src` to `dst`: answers an
    /// Identify (into `frames`, or later by [`poll`](Self::poll)) or a Get to `id`, and
    /// hands back a Set to it.
    pub fn on_pdu(
        &mut self,
        id: &DcpIdentity,
        dst: MacAddress,
        src: MacAddress,
        pdu: &[u8],
        now_ns: u64,
        frames: &mut Vec<Vec<u8>>,
    ) -> DcpRequest {
        let Ok(packet) = dcp::Packet::new_checked(pdu) else {
            return DcpRequest::Done;
        };
        let Ok(req) = dcp::Repr::parse(&packet) else {
            return DcpRequest::Done;
        };
        if req.service_type != ServiceType::Request {
            return DcpRequest::Done;
        }
        let to_us = dst == id.mac;
        match (req.frame_id, req.service_id) {
            (dcp::FRAME_ID_IDENTIFY_REQUEST, ServiceId::Identify)
                if to_us || dst == MacAddress::DCP_IDENTIFY =>
            {
                if !req.blocks.iter().all(|b| matches(id, &b.value)) {
                    return DcpRequest::Done;
                }
                let res = response(&req, dcp::FRAME_ID_IDENTIFY_RESPONSE, identify_blocks(id));
                let Some(frame) = frame(id.mac, src, &res) else {
                    return DcpRequest::Done;
                };
                let delay = dcp::response_delay_ns(id.mac, req.response_delay);
                if delay == 0 {
                    frames.push(frame);
                } else if self.pending.len() < MAX_PENDING {
                    self.pending.push((now_ns.saturating_add(delay), frame));
                }
                DcpRequest::Done
            }
            (dcp::FRAME_ID_GET_SET, ServiceId::Get) if to_us => {
                let blocks = req.blocks.iter().map(|b| get(id, b.value.code())).collect();
                let res = response(&req, dcp::FRAME_ID_GET_SET, blocks);
                frames.extend(frame(id.mac, src, &res));
                DcpRequest::Done
            }
            (dcp::FRAME_ID_GET_SET, ServiceId::Set) if to_us => DcpRequest::Set(req),
            _ => DcpRequest::Done,
        }
    }

    /// Sends the Identify responses whose delay is over.
    pub fn poll(&mut self, now_ns: u64, frames: &mut Vec<Vec<u8>>) {
        let (due, later): (Vec<_>, Vec<_>) =
            self.pending.drain(..).partition(|(at, _)| *at <= now_ns);
        self.pending = later;
        frames.extend(due.into_iter().map(|(_, f)| f));
    }

    /// When the next delayed response is due.
    pub fn next_deadline_ns(&self) -> Option<u64> {
        self.pending.iter().map(|(at, _)| *at).min()
    }
}

/// The answer to a Set the station cannot take now: every block refused with "resource
/// error".
pub fn busy_response(id: &DcpIdentity, src: MacAddress, req: &dcp::Repr) -> Option<Vec<u8>> {
    let blocks = req
        .blocks
        .iter()
        .map(|b| control_response(b, block_error::RESOURCE_ERROR))
        .collect();
    frame(id.mac, src, &response(req, dcp::FRAME_ID_GET_SET, blocks))
}

/// The response to `req`: same service and Xid, ServiceType success, no delay field.
fn response(req: &dcp::Repr, frame_id: u16, blocks: Vec<Block>) -> dcp::Repr {
    dcp::Repr {
        frame_id,
        service_id: req.service_id,
        service_type: ServiceType::Success,
        xid: req.xid,
        response_delay: 0,
        blocks,
    }
}

/// The response frame: untagged, like p-net's (DCP needs no priority), padded to 60 bytes.
fn frame(src: MacAddress, dst: MacAddress, repr: &dcp::Repr) -> Option<Vec<u8>> {
    let pdu = repr.to_vec().ok()?;
    Some(profinet_frame(dst, src, None, &pdu))
}

/// Whether an Identify filter block matches the device (every block must).
fn matches(id: &DcpIdentity, filter: &BlockRepr) -> bool {
    match filter {
        BlockRepr::AllSelector => true,
        BlockRepr::NameOfStation(n) => !id.name.is_empty() && *n == id.name,
        BlockRepr::DeviceVendor(v) => *v == id.type_of_station,
        BlockRepr::DeviceId {
            vendor_id,
            device_id,
        } => (*vendor_id, *device_id) == (id.vendor_id, id.device_id),
        BlockRepr::DeviceRole { role, .. } => role & id.role != 0,
        BlockRepr::DeviceInstance { high, low } => u16::from_be_bytes([*high, *low]) == id.instance,
        BlockRepr::IpParameter { ip, mask, gateway } => {
            (*ip, *mask, *gateway) == (id.ip, id.mask, id.gateway)
        }
        BlockRepr::MacAddress(m) => *m == id.mac,
        // The alias is what the LLDP neighbour makes of the device: a controller finds a
        // device without a name by where it is plugged.
        BlockRepr::AliasName(a) => id.alias.as_deref() == Some(a.as_str()),
        // Filters we do not know match nothing.
        _ => false,
    }
}

/// The value of one (option, suboption) as a response block.
fn value(id: &DcpIdentity, (option, suboption): (u8, u8)) -> Option<Block> {
    let v = match (option, suboption) {
        code::MAC_ADDRESS => BlockRepr::MacAddress(id.mac),
        code::IP_PARAMETER => BlockRepr::IpParameter {
            ip: id.ip,
            mask: id.mask,
            gateway: id.gateway,
        },
        code::FULL_IP_SUITE => BlockRepr::FullIpSuite {
            ip: id.ip,
            mask: id.mask,
            gateway: id.gateway,
            dns: [[0; 4]; 4],
        },
        code::DEVICE_VENDOR => BlockRepr::DeviceVendor(id.type_of_station.clone()),
        code::NAME_OF_STATION => BlockRepr::NameOfStation(id.name.clone()),
        code::DEVICE_ID => BlockRepr::DeviceId {
            vendor_id: id.vendor_id,
            device_id: id.device_id,
        },
        code::DEVICE_ROLE => BlockRepr::DeviceRole {
            role: id.role,
            reserved: 0,
        },
        code::DEVICE_OPTIONS => BlockRepr::DeviceOptions(OPTIONS.to_vec()),
        code::DEVICE_INSTANCE => {
            let [high, low] = id.instance.to_be_bytes();
            BlockRepr::DeviceInstance { high, low }
        }
        code::DEVICE_INITIATIVE => {
            BlockRepr::DeviceInitiative(if id.hello { INITIATIVE_HELLO } else { 0 })
        }
        _ => return None,
    };
    // BlockInfo of the IP blocks: whether an address is set; 0 for the others.
    let info = match v {
        BlockRepr::IpParameter { .. } | BlockRepr::FullIpSuite { .. } if id.ip != [0; 4] => {
            BLOCK_INFO_IP_SET
        }
        _ => 0,
    };
    Some(Block::new(info, v))
}

/// The blocks of an Identify response, in p-net's order plus the DeviceInstance (which lets
/// a controller build our RPC object UUID without guessing the instance).
fn identify_blocks(id: &DcpIdentity) -> Vec<Block> {
    [
        code::IP_PARAMETER,
        code::DEVICE_VENDOR,
        code::NAME_OF_STATION,
        code::DEVICE_ID,
        code::DEVICE_ROLE,
        code::DEVICE_OPTIONS,
        code::DEVICE_INSTANCE,
    ]
    .into_iter()
    .filter_map(|c| value(id, c))
    .collect()
}

/// The Hello request (device initiative) to [`MacAddress::DCP_HELLO`], untagged: the
/// blocks IEC 61158-6-10's DCP-Hello-ReqPDU lists (as p-net quotes its syntax:
/// NameOfStation, IPParameter, DeviceID, DeviceOptions or DeviceVendor, DeviceRole,
/// DeviceInitiative), each with its BlockInfo, the DeviceVendor chosen of the two.
pub fn hello_frame(id: &DcpIdentity) -> Option<Vec<u8>> {
    let blocks = [
        code::NAME_OF_STATION,
        code::IP_PARAMETER,
        code::DEVICE_ID,
        code::DEVICE_VENDOR,
        code::DEVICE_ROLE,
        code::DEVICE_INITIATIVE,
    ]
    .into_iter()
    .filter_map(|c| value(id, c))
    .collect();
    let req = dcp::Repr {
        frame_id: dcp::FRAME_ID_HELLO,
        service_id: ServiceId::Hello,
        service_type: ServiceType::Request,
        xid: HELLO_XID,
        response_delay: 0,
        blocks,
    };
    frame(id.mac, MacAddress::DCP_HELLO, &req)
}

/// The answer to one Get pair: its value, or a ControlResponse with the reason.
fn get(id: &DcpIdentity, (option, suboption): (u8, u8)) -> Block {
    value(id, (option, suboption)).unwrap_or_else(|| {
        Block::bare(BlockRepr::ControlResponse {
            option,
            suboption,
            error: unsupported(option),
        })
    })
}

/// BlockError for an (option, suboption) we do not serve.
fn unsupported(option: u8) -> u8 {
    if matches!(option, 0x01 | 0x02 | 0x05 | 0x06) {
        block_error::SUBOPTION_UNSUPPORTED
    } else {
        block_error::OPTION_UNSUPPORTED
    }
}

/// What a DCP Set may change of a station.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Settable {
    /// Its NameOfStation.
    pub name: bool,
    /// Its IP suite.
    pub ip: bool,
}

impl Settable {
    /// Both, or neither.
    pub const fn all(allow: bool) -> Settable {
        Settable {
            name: allow,
            ip: allow,
        }
    }

    /// Whether Set block `value` may be carried out: a reset to factory clears both, so it
    /// needs both.
    fn allows(self, value: &BlockRepr) -> bool {
        match value {
            BlockRepr::NameOfStation(_) => self.name,
            BlockRepr::IpParameter { .. } | BlockRepr::FullIpSuite { .. } => self.ip,
            BlockRepr::ResetToFactory(_) | BlockRepr::FactoryReset(_) => self.name && self.ip,
            _ => true,
        }
    }
}

/// Carries out Set request `req` from `src` and answers it; the name, address and reset
/// blocks `allow` does not allow are refused ("SET not possible") and leave the station
/// alone. Returns what changed.
pub fn answer_set(
    id: &mut DcpIdentity,
    src: MacAddress,
    req: &dcp::Repr,
    allow: Settable,
    frames: &mut Vec<Vec<u8>>,
) -> DcpChanges {
    let mut changes = DcpChanges::default();
    let blocks = req
        .blocks
        .iter()
        .map(|b| {
            let vetoed = !allow.allows(&b.value);
            let error = if vetoed {
                block_error::SET_NOT_POSSIBLE
            } else {
                set(id, b, &mut changes)
            };
            control_response(b, error)
        })
        .collect();
    let res = response(req, dcp::FRAME_ID_GET_SET, blocks);
    frames.extend(frame(id.mac, src, &res));
    changes
}

/// The ControlResponse block answering Set block `b` with `error`.
fn control_response(b: &Block, error: u8) -> Block {
    let (option, suboption) = b.value.code();
    Block::bare(BlockRepr::ControlResponse {
        option,
        suboption,
        error,
    })
}

/// Applies one Set block; returns its BlockError.
fn set(id: &mut DcpIdentity, b: &Block, changes: &mut DcpChanges) -> u8 {
    // BlockQualifier bit 0: keep the value across a restart (permanent), else until then.
    let permanent = b.prefix & 1 == 1;
    match &b.value {
        BlockRepr::IpParameter { ip, mask, gateway }
        | BlockRepr::FullIpSuite {
            ip, mask, gateway, ..
        } => {
            if !valid_ip(*ip, *mask, *gateway) {
                return block_error::SET_NOT_POSSIBLE;
            }
            changes.ip |= (id.ip, id.mask, id.gateway) != (*ip, *mask, *gateway);
            changes.store_ip |= permanent;
            (id.ip, id.mask, id.gateway) = (*ip, *mask, *gateway);
            block_error::OK
        }
        BlockRepr::NameOfStation(n) => {
            if !valid_name(n) {
                return block_error::SET_NOT_POSSIBLE;
            }
            changes.name |= id.name != *n;
            changes.store_name |= permanent;
            id.name.clone_from(n);
            block_error::OK
        }
        BlockRepr::ControlStart | BlockRepr::ControlStop => block_error::OK,
        BlockRepr::ControlSignal(_) => {
            changes.signal = true;
            block_error::OK
        }
        BlockRepr::ResetToFactory(_) | BlockRepr::FactoryReset(_) => {
            // Resetting the communication parameters: no name, no IP.
            changes.reset = true;
            // What a restart comes back with, too: the factory state.
            changes.store_name = true;
            changes.store_ip = true;
            id.name.clear();
            (id.ip, id.mask, id.gateway) = ([0; 4], [0; 4], [0; 4]);
            block_error::OK
        }
        // Read-only properties of the device.
        BlockRepr::MacAddress(_)
        | BlockRepr::DeviceVendor(_)
        | BlockRepr::DeviceId { .. }
        | BlockRepr::DeviceRole { .. }
        | BlockRepr::DeviceOptions(_)
        | BlockRepr::DeviceInstance { .. } => block_error::SET_NOT_POSSIBLE,
        other => unsupported(other.code().0),
    }
}

/// A NameOfStation a station accepts: empty (no name) or up to 240 characters of dot-separated
/// labels of 1 to 63 lower-case letters, digits and inner hyphens, not an IPv4 address and not
/// a port name (`port-xyz`, `port-xyz-abcde`).
pub fn valid_name(n: &str) -> bool {
    if n.is_empty() {
        return true;
    }
    if n.len() > MAX_NAME_LEN {
        return false;
    }
    let label_ok = |l: &str| {
        !l.is_empty()
            && l.len() <= 63
            && !l.starts_with('-')
            && !l.ends_with('-')
            && l.bytes()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'-')
    };
    if !n.split('.').all(label_ok) {
        return false;
    }
    let looks_like_ip = n.split('.').count() == 4 && n.split('.').all(|l| l.parse::<u8>().is_ok());
    let first = n.split('.').next().unwrap_or("");
    let port = |s: &str| s.len() == 3 && s.bytes().all(|c| c.is_ascii_digit());
    let looks_like_port = first.strip_prefix("port-").is_some_and(|rest| {
        rest.split_once('-')
            .map_or(port(rest), |(a, b)| port(a) && b.len() == 5)
    });
    !looks_like_ip && !looks_like_port
}

/// IP parameters a station accepts: all zero (no address), or a unicast address with a
/// contiguous mask and a gateway that is none (0 or the address itself) or in the subnet.
pub fn valid_ip(ip: [u8; 4], mask: [u8; 4], gateway: [u8; 4]) -> bool {
    if ip == [0; 4] {
        return mask == [0; 4] && gateway == [0; 4];
    }
    let (a, m, g) = (
        u32::from_be_bytes(ip),
        u32::from_be_bytes(mask),
        u32::from_be_bytes(gateway),
    );
    let contiguous = m.leading_ones() + m.trailing_zeros() == 32;
    let unicast = ip[0] != 0 && ip[0] != 127 && ip[0] < 224;
    let host_part_ok = m == u32::MAX || (a & !m != 0 && a & !m != !m);
    let gateway_ok = g == 0 || g == a || (g & m == a & m && g & !m != 0 && g & !m != !m);
    contiguous && unicast && host_part_ok && gateway_ok
}

/// Whether a FrameID is one of the DCP requests a station answers (Identify, Get/Set).
pub fn is_request_frame_id(frame_id: u16) -> bool {
    frame_id == dcp::FRAME_ID_IDENTIFY_REQUEST || frame_id == dcp::FRAME_ID_GET_SET
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        for ok in ["", "rt-labs-dev", "a.b-c.d0", "dio"] {
            assert!(valid_name(ok), "{ok}");
        }
        for bad in [
            "Upper",
            "-x",
            "x-",
            "a..b",
            "1.2.3.4",
            "port-001",
            "port-001-00001",
            "under_score",
        ] {
            assert!(!valid_name(bad), "{bad}");
        }
        assert!(!valid_name(&"a".repeat(241)));
    }

    #[test]
    fn ip_parameters() {
        let ip = [172, 16, 2, 10];
        assert!(valid_ip(ip, [255, 255, 255, 0], ip));
        assert!(valid_ip(ip, [255, 255, 255, 0], [172, 16, 2, 1]));
        assert!(valid_ip([0; 4], [0; 4], [0; 4]));
        assert!(!valid_ip(ip, [255, 0, 255, 0], ip));
        assert!(!valid_ip([224, 0, 0, 1], [255, 0, 0, 0], [0; 4]));
        assert!(!valid_ip([172, 16, 2, 255], [255, 255, 255, 0], [0; 4]));
        assert!(!valid_ip(ip, [255, 255, 255, 0], [10, 0, 0, 1]));
    }
}
