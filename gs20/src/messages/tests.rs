// SPDX-License-Identifier: MIT OR Apache-2.0
//! The messages against the reference: its example frames byte for byte, every frame's
//! layout at the offsets of its table (§1.5), the checks of what the bytes mean, and a
//! round trip of every frame type.

use std::net::{Ipv4Addr, SocketAddrV4};

use proptest::prelude::*;

use super::config::AddItemError;
use super::*;
use crate::frame::{FrameRepr, MAX_IO_DATA, MAX_SOCKET_DATA, MAX_SOCKET_EVENT_INFO};

/// Add Item 3008 (0x0BC0) at slot 1 (§1.4).
static ADD_ITEM_3008_SLOT_1: [u8; 10] =
    [0x03, 0x06, 0x0B, 0xC0, 0x00, 0x00, 0x00, 0x01, 0xA6, 0xB4];
/// Its Adapter Response: Config with the error flag, "no network configuration",
/// PROFINET, version 1.
static RESPONSE_NO_NETWORK: [u8; 10] = [0xF0, 0x06, 0x00, 0x03, 0x00, 0x04, 0x02, 0x01, 0xEC, 0x2E];
static REQUEST_STATUS: [u8; 4] = [0x20, 0x00, 0x18, 0x70];
static REQUEST_RESET: [u8; 4] = [0x21, 0x00, 0x19, 0xE0];
static REQUEST_START: [u8; 4] = [0x22, 0x00, 0x19, 0x10];

fn host(bytes: &[u8]) -> HostMessage<'_> {
    HostMessage::parse(&FrameRepr::parse_bytes(bytes).unwrap()).unwrap()
}

fn adapter(bytes: &[u8]) -> AdapterMessage<'_> {
    AdapterMessage::parse(&FrameRepr::parse_bytes(bytes).unwrap()).unwrap()
}

/// The frame's bytes without the CRC (the frame tests check the CRC).
fn body<'a>(m: &impl Message<'a>) -> Vec<u8> {
    let v = m.to_vec().unwrap();
    v[..v.len() - 2].to_vec()
}

#[test]
fn add_item_3008_at_slot_1_and_its_response() {
    let m = host(&ADD_ITEM_3008_SLOT_1);
    let add = AddItem {
        item_id: 3008,
        position: 1,
    };
    assert_eq!(m, HostMessage::AddItem(add));
    let (item, slot) = add.validate().unwrap();
    assert_eq!(
        (item.kind(), item.size(), slot),
        (ItemKind::InputOutput, 8, 1)
    );
    assert_eq!((item.input_len(), item.output_len()), (8, 8));
    assert_eq!(add.to_vec().unwrap(), ADD_ITEM_3008_SLOT_1);

    let response = AdapterResponse::new(
        Mode::Config,
        StatusFlags::empty(),
        ErrorBits::NO_NETWORK_CONFIG,
    );
    assert_eq!(response.to_vec().unwrap(), RESPONSE_NO_NETWORK);
    assert_eq!(
        adapter(&RESPONSE_NO_NETWORK),
        AdapterMessage::AdapterResponse(response)
    );
    assert_eq!(response.status.mode, Mode::Config);
    assert_eq!(response.status.flags, StatusFlags::ERROR);
    assert_eq!(response.protocol, Protocol::Profinet);
    assert_eq!(response.version, 1);
    assert_eq!(response.errors.to_string(), "no network configuration");
}

#[test]
fn the_requests_without_data() {
    assert_eq!(
        host(&REQUEST_STATUS),
        HostMessage::RequestStatus(RequestStatus)
    );
    assert_eq!(
        host(&REQUEST_RESET),
        HostMessage::RequestReset(RequestReset)
    );
    assert_eq!(
        host(&REQUEST_START),
        HostMessage::RequestStart(RequestStart)
    );
    assert_eq!(RequestStatus.to_vec().unwrap(), REQUEST_STATUS);
    assert_eq!(RequestReset.to_vec().unwrap(), REQUEST_RESET);
    assert_eq!(RequestStart.to_vec().unwrap(), REQUEST_START);
}

#[test]
fn the_status_word_bits() {
    // Mode in bits 1-2 (§1.6).
    for (mode, bits) in [
        (Mode::Standby, 0b000),
        (Mode::Config, 0b010),
        (Mode::Pending, 0b100),
        (Mode::Run, 0b110),
    ] {
        let w = StatusWord {
            mode,
            flags: StatusFlags::empty(),
        };
        assert_eq!(w.to_u16(), bits);
        assert_eq!(StatusWord::from_u16(bits), w);
    }
    let run_connected = StatusWord {
        mode: Mode::Run,
        flags: StatusFlags::LINK_KNOWN
            | StatusFlags::LINK_UP
            | StatusFlags::IP_OK
            | StatusFlags::NETWORK_OK
            | StatusFlags::PLC_CONNECTED,
    };
    assert_eq!(run_connected.to_u16(), 0b0_1111_1110);
    assert_eq!(StatusFlags::LITTLE_ENDIAN.bits(), 1 << 8);
    // The error bits 0-8 in the table's order.
    let names: Vec<_> = ErrorBits::DESCRIPTIONS
        .iter()
        .map(|(b, _)| b.bits().trailing_zeros())
        .collect();
    assert_eq!(names, (0..9).collect::<Vec<_>>());
    assert_eq!(
        (ErrorBits::CRC | ErrorBits::LOCKOUT).to_string(),
        "frame CRC error, lockout (basket vs device/item)"
    );
    // Without errors the error flag is clear.
    let ok = AdapterResponse::new(Mode::Run, StatusFlags::ERROR, ErrorBits::empty());
    assert_eq!(ok.status.to_u16(), 0b110);
}

#[test]
fn add_basket_add_device_set_mac_set_serial_layouts() {
    assert_eq!(
        body(&AddBasket { basket_id: 0x1234 }),
        [0x01, 2, 0x12, 0x34]
    );
    assert_eq!(
        body(&AddDevice { device_id: 0xBEEF }),
        [0x02, 2, 0xBE, 0xEF]
    );
    let mac = MacAddress([0x00, 0x1B, 0x1B, 0x12, 0x34, 0x56]);
    assert_eq!(
        body(&SetMac { mac }),
        [0x11, 6, 0x00, 0x1B, 0x1B, 0x12, 0x34, 0x56]
    );
    assert_eq!(mac.to_string(), "00:1b:1b:12:34:56");
    assert!(mac.is_unicast());
    assert!(!MacAddress([1, 0, 0x5E, 0, 0, 1]).is_unicast());
    assert_eq!(
        body(&SetSerialNumber {
            serial: 0x0102_0304
        }),
        [0x12, 4, 1, 2, 3, 4]
    );
}

#[test]
fn set_network_configuration_layout() {
    let m = SetNetworkConfig {
        mode: AddressMode::Static,
        ip: Ipv4Addr::new(192, 168, 0, 50),
        mask: Ipv4Addr::new(255, 255, 255, 0),
        gateway: Ipv4Addr::new(192, 168, 0, 1),
        dns1: Ipv4Addr::new(192, 168, 0, 2),
        dns2: Ipv4Addr::UNSPECIFIED,
        host_name: b"gs20-host",
    };
    let b = body(&m);
    assert_eq!(b[0], 0x10);
    assert_eq!(usize::from(b[1]), 21 + 9);
    assert_eq!(b[2], 0);
    assert_eq!(b[3..7], [192, 168, 0, 50]);
    assert_eq!(b[7..11], [255, 255, 255, 0]);
    assert_eq!(b[11..15], [192, 168, 0, 1]);
    assert_eq!(b[15..19], [192, 168, 0, 2]);
    assert_eq!(b[19..23], [0, 0, 0, 0]);
    assert_eq!(&b[23..], b"gs20-host");
    assert_eq!(m.validate(), Ok(()));
    assert_eq!(m.station_name().unwrap(), "gs20-host");
}

#[test]
fn data_frames_have_a_two_byte_len() {
    let data = [0xAA; 6];
    assert_eq!(
        body(&SetBusData { data: &data }),
        [0x30, 0, 6, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA]
    );
    assert_eq!(
        body(&AdapterData { data: &data[..2] }),
        [0x31, 0, 2, 0xAA, 0xAA]
    );
    // An empty image (a station without inputs) is a frame too.
    assert_eq!(body(&SetBusData { data: &[] }), [0x30, 0, 0]);
    let big = [0; MAX_IO_DATA + 1];
    assert!(SetBusData { data: &big }.to_vec().is_err());
}

#[test]
fn adapter_event_layouts() {
    let up = AdapterEvent {
        mode: Mode::Run,
        event: Event::NetworkUp(NetworkUp {
            mode: AddressMode::Dhcp,
            ip: Ipv4Addr::new(10, 0, 0, 7),
            mask: Ipv4Addr::new(255, 0, 0, 0),
            gateway: Ipv4Addr::new(10, 0, 0, 1),
            dns: Ipv4Addr::new(10, 0, 0, 2),
        }),
    };
    assert_eq!(
        body(&up),
        [
            0xF1, 20, 3, 0, 3, 1, 10, 0, 0, 7, 255, 0, 0, 0, 10, 0, 0, 1, 10, 0, 0, 2
        ]
    );
    for (event, code) in [
        (Event::LinkUp, 1),
        (Event::LinkDown, 2),
        (Event::PlcConnected, 4),
        (Event::PlcLost, 5),
    ] {
        assert_eq!(
            body(&AdapterEvent {
                mode: Mode::Run,
                event
            }),
            [0xF1, 3, 3, 0, code]
        );
    }
    assert_eq!(
        body(&AdapterEvent {
            mode: Mode::Run,
            event: Event::PlcReset { reset_type: 1 }
        }),
        [0xF1, 4, 3, 0, 6, 1]
    );
    // A named code with the wrong information length is an error, both ways.
    let mut wrong = vec![0xF1, 4, 3, 0, 4, 0];
    wrong.extend(crate::frame::crc16(&wrong).to_le_bytes());
    assert_eq!(
        AdapterMessage::parse(&FrameRepr::parse_bytes(&wrong).unwrap()),
        Err(ParseError::InfoLength {
            id: FrameId::AdapterEvent,
            code: 4,
            expected: 0,
            len: 1
        })
    );
    let reserved_as_named = AdapterEvent {
        mode: Mode::Run,
        event: Event::Reserved { code: 4, info: &[] },
    };
    assert!(matches!(
        reserved_as_named.to_vec(),
        Err(EmitError::Invalid(_))
    ));
    // A mode above 3 is no mode.
    let mut bad_mode = vec![0xF1, 3, 4, 0, 1];
    bad_mode.extend(crate::frame::crc16(&bad_mode).to_le_bytes());
    assert!(matches!(
        AdapterMessage::parse(&FrameRepr::parse_bytes(&bad_mode).unwrap()),
        Err(ParseError::Invalid { value: 4, .. })
    ));
}

#[test]
fn socket_frame_layouts() {
    let open = OpenSocket {
        role: SocketRole::Client,
        protocol: SocketProtocol::Udp,
        port: 5000,
        ip: Ipv4Addr::new(192, 168, 0, 9),
    };
    assert_eq!(body(&open), [0x40, 8, 0, 1, 0x13, 0x88, 192, 168, 0, 9]);
    let opt = SetSocketOption {
        handle: 3,
        option: SocketOption::JoinMulticast,
        data: &[239, 1, 2, 3],
    };
    assert_eq!(body(&opt), [0x41, 6, 3, 4, 239, 1, 2, 3]);
    assert_eq!(opt.option.data_len(), Some(4));
    assert_eq!(SocketOption::TcpNoDelay.data_len(), Some(1));
    assert_eq!(SocketOption::from_raw(8).data_len(), None);
    assert_eq!(body(&RequestSocketStatus { handle: 3 }), [0x42, 1, 3]);
    assert_eq!(body(&CloseSocket { handle: 3 }), [0x43, 1, 3]);
    assert_eq!(
        body(&SendSocketData {
            handle: 3,
            data: b"hi"
        }),
        [0x50, 0, 3, 3, b'h', b'i']
    );
    assert_eq!(
        body(&AdapterSocketData {
            handle: 4,
            data: b"ok"
        }),
        [0x51, 0, 3, 4, b'o', b'k']
    );
    assert_eq!(
        body(&SocketResponse {
            handle: 3,
            status: SocketStatus::CONNECTED,
            errors: SocketErrors::SEND_FAILED,
        }),
        [0xE0, 5, 3, 0, 0x08, 0, 0x10]
    );
    let remote = SocketAddrV4::new(Ipv4Addr::new(192, 168, 0, 9), 502);
    assert_eq!(
        body(&SocketEvent {
            handle: 2,
            status: SocketStatus::ACCEPTING,
            event: SocketEventKind::Accepted { child: 5, remote },
        }),
        [0xE1, 0, 11, 2, 0, 0x04, 2, 5, 192, 168, 0, 9, 0x01, 0xF6]
    );
    assert_eq!(
        body(&SocketEvent {
            handle: 5,
            status: SocketStatus::DEAD,
            event: SocketEventKind::Disconnected,
        }),
        [0xE1, 0, 4, 5, 0, 0x10, 3]
    );
    // A frame of the other direction.
    assert_eq!(
        HostMessage::parse(&FrameRepr::parse_bytes(&RESPONSE_NO_NETWORK).unwrap()),
        Err(ParseError::WrongDirection {
            id: FrameId::AdapterResponse
        })
    );
    assert_eq!(
        <AddItem as Message>::parse(&FrameRepr::parse_bytes(&REQUEST_STATUS).unwrap()),
        Err(ParseError::WrongId {
            expected: FrameId::AddItem,
            received: FrameId::RequestStatus
        })
    );
}

#[test]
fn the_item_catalogue() {
    // The reference's table (§1.5): D = 1 input, 2 output, 3 both; n bytes.
    for (id, kind, n) in [
        (1001, ItemKind::Input, 1),
        (1016, ItemKind::Input, 16),
        (2128, ItemKind::Output, 128),
        (3008, ItemKind::InputOutput, 8),
        (3064, ItemKind::InputOutput, 64),
        (3256, ItemKind::InputOutput, 256),
    ] {
        let item = ItemId::from_u16(id).unwrap();
        assert_eq!((item.kind(), item.size(), item.to_u16()), (kind, n, id));
    }
    // 3008 is 0x0BC0 on the wire.
    assert_eq!(ItemId::from_u16(0x0BC0).unwrap().to_u16(), 3008);
    assert_eq!(ItemId::from_u16(1016).unwrap().output_len(), 0);
    assert_eq!(ItemId::from_u16(2128).unwrap().input_len(), 0);
    // 512 exceeds the module's 384 bytes; 3, 10 are no sizes; D outside 1-3.
    for (id, e) in [
        (
            3512,
            ItemIdError::Size {
                id: 3512,
                size: 512,
            },
        ),
        (1003, ItemIdError::Size { id: 1003, size: 3 }),
        (2010, ItemIdError::Size { id: 2010, size: 10 }),
        (3000, ItemIdError::Size { id: 3000, size: 0 }),
        (8, ItemIdError::Kind { id: 8 }),
        (4008, ItemIdError::Kind { id: 4008 }),
        (u16::MAX, ItemIdError::Kind { id: u16::MAX }),
    ] {
        assert_eq!(ItemId::from_u16(id), Err(e), "{id}");
    }
    let all: Vec<u16> = ItemId::all().map(ItemId::to_u16).collect();
    assert_eq!(all.len(), 27);
    assert_eq!(all[..3], [1001, 1002, 1004]);
    assert_eq!(all[26], 3256);
    assert!(all.iter().all(|&id| ItemId::from_u16(id).is_ok()));
    // Slot 0 is the DAP's.
    assert_eq!(
        AddItem {
            item_id: 1001,
            position: 0
        }
        .validate(),
        Err(AddItemError::Slot { position: 0 })
    );
    // The catalogue's slots end at 64.
    assert_eq!(
        AddItem {
            item_id: 1001,
            position: 64
        }
        .validate(),
        Ok((ItemId::from_u16(1001).unwrap(), 64))
    );
    for position in [65, 0x8000, 0x1_0001] {
        let e = AddItem {
            item_id: 1001,
            position,
        }
        .validate();
        assert_eq!(e, Err(AddItemError::Slot { position }));
    }
    let shown = AddItemError::Slot { position: 65 }.to_string();
    assert!(shown.contains("use 1 to 64"), "{shown}");
    assert!(matches!(
        AddItem {
            item_id: 3512,
            position: 1
        }
        .validate(),
        Err(AddItemError::Item(ItemIdError::Size { .. }))
    ));
}

#[test]
fn network_configuration_checks() {
    let good = SetNetworkConfig {
        mode: AddressMode::Static,
        ip: Ipv4Addr::new(192, 168, 0, 50),
        mask: Ipv4Addr::new(255, 255, 255, 0),
        gateway: Ipv4Addr::UNSPECIFIED,
        dns1: Ipv4Addr::UNSPECIFIED,
        dns2: Ipv4Addr::UNSPECIFIED,
        host_name: b"Io-Device-1",
    };
    assert_eq!(good.validate(), Ok(()));
    assert_eq!(good.station_name().unwrap(), "io-device-1");
    let with = |f: &dyn Fn(&mut SetNetworkConfig<'static>)| {
        let mut c = good;
        f(&mut c);
        c.validate()
    };
    use NetworkConfigError as E;
    assert_eq!(
        with(&|c| c.mode = AddressMode::from_raw(2)),
        Err(E::AddressMode(2))
    );
    assert_eq!(
        with(&|c| c.ip = Ipv4Addr::UNSPECIFIED),
        Err(E::Ip(Ipv4Addr::UNSPECIFIED))
    );
    assert_eq!(
        with(&|c| c.ip = Ipv4Addr::new(192, 168, 0, 255)),
        Err(E::Ip(Ipv4Addr::new(192, 168, 0, 255)))
    );
    assert_eq!(
        with(&|c| c.ip = Ipv4Addr::new(224, 0, 0, 1)),
        Err(E::Ip(Ipv4Addr::new(224, 0, 0, 1)))
    );
    assert_eq!(
        with(&|c| c.mask = Ipv4Addr::new(255, 0, 255, 0)),
        Err(E::Mask(Ipv4Addr::new(255, 0, 255, 0)))
    );
    assert_eq!(
        with(&|c| c.mask = Ipv4Addr::BROADCAST),
        Err(E::Mask(Ipv4Addr::BROADCAST))
    );
    assert_eq!(
        with(&|c| c.gateway = Ipv4Addr::new(10, 0, 0, 1)),
        Err(E::Gateway(Ipv4Addr::new(10, 0, 0, 1)))
    );
    assert_eq!(with(&|c| c.gateway = c.ip), Ok(()));
    assert_eq!(with(&|c| c.gateway = Ipv4Addr::new(192, 168, 0, 1)), Ok(()));
    assert_eq!(
        with(&|c| c.dns2 = Ipv4Addr::BROADCAST),
        Err(E::Dns(Ipv4Addr::BROADCAST))
    );
    // With DHCP the addresses are the server's business.
    assert_eq!(
        with(&|c| {
            c.mode = AddressMode::Dhcp;
            c.ip = Ipv4Addr::UNSPECIFIED;
            c.mask = Ipv4Addr::UNSPECIFIED;
        }),
        Ok(())
    );
    // Host names (§1.6: 0 bytes, more than 63, invalid characters).
    assert_eq!(with(&|c| c.host_name = b""), Err(E::HostNameEmpty));
    assert_eq!(
        with(&|c| c.host_name = &[b'a'; 64]),
        Err(E::HostNameTooLong(64))
    );
    assert_eq!(with(&|c| c.host_name = &[b'a'; 63]), Ok(()));
    assert_eq!(
        with(&|c| c.host_name = b"io device"),
        Err(E::HostNameChar { byte: b' ', at: 2 })
    );
    assert_eq!(
        with(&|c| c.host_name = b"io_dev"),
        Err(E::HostNameChar { byte: b'_', at: 2 })
    );
    for bad in [&b"-io"[..], b"io-", b"io..dev", b".io"] {
        assert_eq!(
            with(&|c| c.host_name = bad),
            Err(E::HostNameLabel),
            "{bad:?}"
        );
    }
    for reserved in [&b"port-001"[..], b"Port-001-00002.x", b"192.168.0.1"] {
        assert_eq!(
            with(&|c| c.host_name = reserved),
            Err(E::HostNameReserved),
            "{reserved:?}"
        );
    }
    assert_eq!(with(&|c| c.host_name = b"port-1"), Ok(()));
    assert!(E::HostNameTooLong(64).to_string().contains("at most 63"));
}

// The round trips: every frame type, emitted, framed, parsed as itself and as a frame of
// either direction, is what it was.

fn ipv4() -> impl Strategy<Value = Ipv4Addr> {
    any::<u32>().prop_map(Ipv4Addr::from)
}

fn mode() -> impl Strategy<Value = Mode> {
    (0u8..4).prop_map(|m| Mode::from_u8(m).unwrap())
}

fn bytes(max: usize) -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        4 => proptest::collection::vec(any::<u8>(), 0..=max.min(32)),
        1 => proptest::collection::vec(any::<u8>(), 0..=max),
    ]
}

macro_rules! round_trip {
    ($ty:ty, $m:expr) => {{
        let m: $ty = $m;
        let v = m.to_vec().unwrap();
        prop_assert_eq!(v.len(), m.buffer_len());
        let frame = FrameRepr::parse_bytes(&v).unwrap();
        prop_assert_eq!(frame.id, <$ty as Message>::ID);
        prop_assert_eq!(<$ty as Message>::parse(&frame), Ok(m));
        let any = AnyMessage::parse(&frame).unwrap();
        prop_assert_eq!(any.id(), <$ty as Message>::ID);
        prop_assert_eq!(any.to_vec().unwrap(), v);
    }};
}

proptest! {
    #[test]
    fn config_commands_round_trip(a in any::<u16>(), b in any::<u32>(), mac in any::<[u8; 6]>()) {
        round_trip!(AddBasket, AddBasket { basket_id: a });
        round_trip!(AddDevice, AddDevice { device_id: a });
        round_trip!(AddItem, AddItem { item_id: a, position: b });
        round_trip!(SetMac, SetMac { mac: MacAddress(mac) });
        round_trip!(SetSerialNumber, SetSerialNumber { serial: b });
        round_trip!(RequestStatus, RequestStatus);
        round_trip!(RequestReset, RequestReset);
        round_trip!(RequestStart, RequestStart);
    }

    #[test]
    fn network_configuration_round_trips(
        m in any::<u8>(), ip in ipv4(), mask in ipv4(), gw in ipv4(), d1 in ipv4(), d2 in ipv4(),
        name in bytes(255 - 21),
    ) {
        round_trip!(SetNetworkConfig, SetNetworkConfig {
            mode: AddressMode::from_raw(m), ip, mask, gateway: gw, dns1: d1, dns2: d2,
            host_name: &name,
        });
        // Checking never panics.
        let c = SetNetworkConfig {
            mode: AddressMode::from_raw(m), ip, mask, gateway: gw, dns1: d1, dns2: d2,
            host_name: &name,
        };
        let _ = (c.validate(), c.station_name());
    }

    #[test]
    fn data_frames_round_trip(data in bytes(MAX_IO_DATA)) {
        round_trip!(SetBusData, SetBusData { data: &data });
        round_trip!(AdapterData, AdapterData { data: &data });
    }

    #[test]
    fn adapter_responses_round_trip(m in mode(), flags in any::<u16>(), errors in any::<u16>(),
                                    protocol in any::<u8>(), version in any::<u8>()) {
        round_trip!(AdapterResponse, AdapterResponse {
            status: StatusWord {
                mode: m,
                flags: StatusFlags::from_bits_retain(flags & !StatusWord::MODE_MASK),
            },
            errors: ErrorBits::from_bits_retain(errors),
            protocol: Protocol::from_raw(protocol),
            version,
        });
        // The status word round-trips through its raw value whatever the bits.
        prop_assert_eq!(StatusWord::from_u16(flags).to_u16(), flags);
    }

    #[test]
    fn adapter_events_round_trip(
        m in mode(), am in any::<u8>(), a in ipv4(), b in ipv4(), c in ipv4(), d in ipv4(),
        reset_type in any::<u8>(), code in prop_oneof![Just(0u16), 7u16..], info in bytes(252),
        which in 0..8,
    ) {
        let event = match which {
            0 => Event::LinkUp,
            1 => Event::LinkDown,
            2 => Event::NetworkUp(NetworkUp {
                mode: AddressMode::from_raw(am), ip: a, mask: b, gateway: c, dns: d,
            }),
            3 => Event::PlcConnected,
            4 => Event::PlcLost,
            5 => Event::PlcReset { reset_type },
            _ => Event::Reserved { code, info: &info },
        };
        round_trip!(AdapterEvent, AdapterEvent { mode: m, event });
    }

    #[test]
    fn socket_requests_round_trip(
        role in any::<u8>(), protocol in any::<u8>(), port in any::<u16>(), ip in ipv4(),
        handle in any::<u8>(), option in any::<u8>(), data in bytes(253),
        payload in bytes(MAX_SOCKET_DATA),
    ) {
        round_trip!(OpenSocket, OpenSocket {
            role: SocketRole::from_raw(role),
            protocol: SocketProtocol::from_raw(protocol),
            port,
            ip,
        });
        round_trip!(SetSocketOption, SetSocketOption {
            handle, option: SocketOption::from_raw(option), data: &data,
        });
        round_trip!(RequestSocketStatus, RequestSocketStatus { handle });
        round_trip!(CloseSocket, CloseSocket { handle });
        round_trip!(SendSocketData, SendSocketData { handle, data: &payload });
        round_trip!(AdapterSocketData, AdapterSocketData { handle, data: &payload });
    }

    #[test]
    fn socket_answers_round_trip(
        handle in any::<u8>(), status in any::<u16>(), errors in any::<u16>(),
        ip in ipv4(), port in any::<u16>(), child in any::<u8>(),
        code in 5u8.., info in bytes(MAX_SOCKET_EVENT_INFO), which in 0..5,
    ) {
        round_trip!(SocketResponse, SocketResponse {
            handle,
            status: SocketStatus::from_bits_retain(status),
            errors: SocketErrors::from_bits_retain(errors),
        });
        let remote = SocketAddrV4::new(ip, port);
        let event = match which {
            0 => SocketEventKind::Connected { remote },
            1 => SocketEventKind::Accepted { child, remote },
            2 => SocketEventKind::Disconnected,
            3 => SocketEventKind::Failed,
            _ => SocketEventKind::Other { code, info: &info },
        };
        round_trip!(SocketEvent, SocketEvent {
            handle,
            status: SocketStatus::from_bits_retain(status),
            event,
        });
    }

    /// Any data of a length its frame type allows: parsing never panics, and what parses
    /// emits back to the same bytes (parsing keeps every bit).
    #[test]
    fn any_data_parses_or_fails_cleanly((id, payload) in crate::frame::tests::any_frame()) {
        let bytes = FrameRepr { id, payload: &payload }.to_vec().unwrap();
        let frame = FrameRepr::parse_bytes(&bytes).unwrap();
        if let Ok(m) = AnyMessage::parse(&frame) {
            prop_assert_eq!(m.to_vec().unwrap(), bytes);
        }
    }
}
