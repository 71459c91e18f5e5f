// SPDX-License-Identifier: MIT OR Apache-2.0
//! The host link's modes and rules, driven frame by frame as a host would.

use std::net::Ipv4Addr;
use std::time::Instant;

use super::*;
use crate::messages::{
    AddBasket, AddDevice, AddItem, CloseSocket, ItemId, RequestReset, RequestStart, RequestStatus,
    SetBusData, SetMac, SetNetworkConfig, SetSerialNumber,
};
use crate::stream::Decoder;
use proptest::prelude::*;

/// Add Item 3008 at slot 1 and the reference's response to it (§1.4).
static ADD_ITEM_3008_SLOT_1: [u8; 10] =
    [0x03, 0x06, 0x0B, 0xC0, 0x00, 0x00, 0x00, 0x01, 0xA6, 0xB4];
static RESPONSE_NO_NETWORK: [u8; 10] = [0xF0, 0x06, 0x00, 0x03, 0x00, 0x04, 0x02, 0x01, 0xEC, 0x2E];

fn send<'a>(link: &mut Link, m: impl Message<'a>) -> Step {
    let bytes = m.to_vec().unwrap();
    link.handle(Ok(FrameRepr::parse_bytes(&bytes).unwrap()))
}

/// The one Adapter Response of a step.
fn response(step: &Step) -> AdapterResponse {
    assert_eq!(step.send.len(), 1, "{step:?}");
    let frame = FrameRepr::parse_bytes(&step.send[0]).unwrap();
    <AdapterResponse as Message>::parse(&frame).unwrap()
}

fn network() -> SetNetworkConfig<'static> {
    SetNetworkConfig::static_ip(
        Ipv4Addr::new(192, 168, 0, 50),
        Ipv4Addr::new(255, 255, 255, 0),
        b"GS20-Host",
    )
}

fn warnings(step: &Step) -> Vec<&Warning> {
    step.actions
        .iter()
        .filter_map(|a| match a {
            Action::Warn(w) => Some(w),
            _ => None,
        })
        .collect()
}

/// A link in Config with a device and the items 3002, 3004, 2002 (the layout of §1.7:
/// 2 + 4 input bytes, 2 + 4 + 2 output bytes) and a network configuration.
fn configured() -> Link {
    let mut link = Link::new(Baskets::new());
    send(&mut link, RequestStatus);
    send(&mut link, AddDevice { device_id: 1 });
    for (item_id, position) in [(3002, 1), (3004, 2), (2002, 3)] {
        let r = response(&send(&mut link, AddItem { item_id, position }));
        assert_eq!(r.errors, ErrorBits::NO_NETWORK_CONFIG);
    }
    let r = response(&send(&mut link, network()));
    assert_eq!(r.errors, ErrorBits::empty());
    assert!(!r.status.flags.contains(StatusFlags::ERROR));
    link
}

fn running() -> Link {
    let mut link = configured();
    link.set_flags(StatusFlags::LINK_KNOWN | StatusFlags::LINK_UP);
    send(&mut link, RequestStart);
    link.started();
    assert_eq!(link.mode(), Mode::Run);
    link
}

#[test]
fn standby_answers_only_request_status() {
    let mut link = Link::new(Baskets::new());
    let step = send(&mut link, AddDevice { device_id: 1 });
    assert!(step.send.is_empty());
    assert_eq!(
        warnings(&step),
        [&Warning::Standby {
            id: FrameId::AddDevice
        }]
    );
    let step = link.handle(Err(StreamError::UnknownId(0x99)));
    assert!(step.send.is_empty());
    assert_eq!(link.mode(), Mode::Standby);
    // Request Status: Config, and the configuration is incomplete (bits 0 and 2).
    let r = response(&send(&mut link, RequestStatus));
    assert_eq!(link.mode(), Mode::Config);
    assert_eq!(r.status.mode, Mode::Config);
    assert_eq!(
        r.errors,
        ErrorBits::INCOMPLETE_CONFIG | ErrorBits::NO_NETWORK_CONFIG
    );
    assert!(r.status.flags.contains(StatusFlags::ERROR));
}

#[test]
fn the_reference_exchange_byte_for_byte() {
    // Request Status, Add Device, then the reference's Add Item and its response.
    let mut link = Link::new(Baskets::new());
    let mut decoder = Decoder::new();
    let wire = [
        &RequestStatus.to_vec().unwrap()[..],
        &AddDevice { device_id: 7 }.to_vec().unwrap(),
        &ADD_ITEM_3008_SLOT_1,
    ]
    .concat();
    let mut sent = Vec::new();
    decoder.feed(&wire, Instant::now(), |item| {
        sent.extend(link.handle(item).send);
    });
    assert_eq!(sent.len(), 3);
    assert_eq!(sent[2], RESPONSE_NO_NETWORK);
}

#[test]
fn a_host_brings_the_station_up() {
    let mut link = configured();
    // Set MAC and Set Serial Number are taken.
    let mac = MacAddress([0x02, 0, 0, 0, 0, 1]);
    assert_eq!(
        response(&send(&mut link, SetMac { mac })).errors,
        ErrorBits::empty()
    );
    send(&mut link, SetSerialNumber { serial: 42 });
    // Without a link, Start is refused with its reason.
    let step = send(&mut link, RequestStart);
    assert_eq!(response(&step).errors, ErrorBits::START_REFUSED);
    assert_eq!(
        warnings(&step),
        [&Warning::StartRefused(StartRefusal::NoLink)]
    );
    assert_eq!(link.mode(), Mode::Config);
    // The bit was reported once.
    assert_eq!(
        response(&send(&mut link, RequestStatus)).errors,
        ErrorBits::empty()
    );

    link.set_flags(StatusFlags::LINK_KNOWN | StatusFlags::LINK_UP);
    let step = send(&mut link, RequestStart);
    let r = response(&step);
    assert_eq!(
        (r.status.mode, r.errors),
        (Mode::Pending, ErrorBits::empty())
    );
    assert!(r.status.flags.contains(StatusFlags::LINK_UP));
    let [Action::Start(station)] = &step.actions[..] else {
        panic!("{step:?}")
    };
    let slots: Vec<(u16, u16)> = station
        .items
        .iter()
        .map(|i| (i.item.to_u16(), i.slot))
        .collect();
    assert_eq!(slots, [(3002, 1), (3004, 2), (2002, 3)]);
    assert_eq!((station.input_len(), station.output_len()), (6, 8));
    let offsets = |o: Vec<(ItemSlot, usize)>| o.into_iter().map(|(_, at)| at).collect::<Vec<_>>();
    assert_eq!(offsets(station.input_offsets()), [0, 2, 6]);
    assert_eq!(offsets(station.output_offsets()), [0, 2, 6]);
    let net = station.network.as_ref().unwrap();
    assert_eq!(net.station_name, "gs20-host");
    assert_eq!(net.ip, Ipv4Addr::new(192, 168, 0, 50));
    assert_eq!((station.mac, station.serial), (Some(mac), Some(42)));

    // Nothing unsolicited before Run.
    assert_eq!(link.adapter_data(&[0; 8]), None);
    assert_eq!(link.event(Event::PlcConnected), None);
    // Pending: only status and reset.
    let r = response(&send(&mut link, SetBusData { data: &[0; 6] }));
    assert_eq!(r.errors, ErrorBits::FRAME);
    link.started();
    assert_eq!(
        response(&send(&mut link, RequestStatus)).status.mode,
        Mode::Run
    );

    // Run: the host's data of the right length goes to the PLC, unacknowledged.
    let step = send(
        &mut link,
        SetBusData {
            data: &[1, 2, 3, 4, 5, 6],
        },
    );
    assert!(step.send.is_empty());
    assert_eq!(step.actions, [Action::SetInputs(vec![1, 2, 3, 4, 5, 6])]);
    assert_eq!(
        link.adapter_data(&[9; 8]).unwrap(),
        AdapterData { data: &[9; 8] }.to_vec().unwrap()
    );
    assert_eq!(link.adapter_data(&[9; 7]), None);
    let ev = link.event(Event::PlcConnected).unwrap();
    assert_eq!(&ev[..5], [0xF1, 3, 3, 0, 4]);
}

#[test]
fn wrong_length_bus_data_reaches_nothing() {
    let mut link = running();
    let step = send(&mut link, SetBusData { data: &[1; 5] });
    assert_eq!(response(&step).errors, ErrorBits::IO_SIZE_MISMATCH);
    assert_eq!(
        step.actions,
        [Action::Warn(Warning::IoSize {
            expected: 6,
            received: 5
        })]
    );
    // The next good frame goes through.
    let step = send(&mut link, SetBusData { data: &[1; 6] });
    assert_eq!(step.actions, [Action::SetInputs(vec![1; 6])]);
}

#[test]
fn frames_in_the_wrong_mode_get_bit_5() {
    let mut link = configured();
    for step in [
        send(&mut link, SetBusData { data: &[0; 6] }),
        send(&mut link, CloseSocket { handle: 1 }),
    ] {
        assert_eq!(response(&step).errors, ErrorBits::FRAME);
    }
    let mut link = running();
    for step in [
        send(
            &mut link,
            AddItem {
                item_id: 1001,
                position: 9,
            },
        ),
        send(&mut link, network()),
        send(&mut link, RequestStart),
    ] {
        let r = response(&step);
        assert_eq!((r.status.mode, r.errors), (Mode::Run, ErrorBits::FRAME));
    }
    // Sockets work in Run: the bridge gets them.
    let step = send(&mut link, CloseSocket { handle: 1 });
    assert_eq!(
        step.actions,
        [Action::Socket(SocketRequest::Close { handle: 1 })]
    );
    assert!(step.send.is_empty());
}

#[test]
fn a_module_frame_from_the_host_is_a_frame_error() {
    let mut link = configured();
    let bytes = RESPONSE_NO_NETWORK;
    let step = link.handle(Ok(FrameRepr::parse_bytes(&bytes).unwrap()));
    assert_eq!(response(&step).errors, ErrorBits::FRAME);
}

#[test]
fn line_errors_are_answered_at_once_and_reported_once() {
    let mut link = configured();
    let crc = StreamError::Crc {
        id: FrameId::AddItem,
        computed: 1,
        received: 2,
    };
    assert_eq!(response(&link.handle(Err(crc))).errors, ErrorBits::CRC);
    assert_eq!(
        response(&link.handle(Err(StreamError::UnknownId(0x77)))).errors,
        ErrorBits::FRAME
    );
    assert_eq!(
        response(&link.handle(Err(StreamError::BadLen {
            id: FrameId::RequestStart,
            len: 2
        })))
        .errors,
        ErrorBits::FRAME
    );
    assert_eq!(
        response(&send(&mut link, RequestStatus)).errors,
        ErrorBits::empty()
    );
}

#[test]
fn basket_and_device_exclude_each_other() {
    let mut baskets = Baskets::new();
    let item = |id, slot| ItemSlot {
        item: ItemId::from_u16(id).unwrap(),
        slot,
    };
    baskets.insert(5, vec![item(1008, 1), item(2008, 2)]);
    baskets.insert(6, vec![]);

    // Device first: Add Basket is locked out.
    let mut link = Link::new(baskets.clone());
    send(&mut link, RequestStatus);
    send(&mut link, AddDevice { device_id: 1 });
    send(
        &mut link,
        AddItem {
            item_id: 1001,
            position: 1,
        },
    );
    let step = send(&mut link, AddBasket { basket_id: 5 });
    assert_eq!(
        response(&step).errors & ErrorBits::LOCKOUT,
        ErrorBits::LOCKOUT
    );
    assert_eq!(link.station().items.len(), 1);

    // Basket first: Add Device and Add Item are locked out; a second basket is an error.
    let mut link = Link::new(baskets);
    send(&mut link, RequestStatus);
    let r = response(&send(&mut link, AddBasket { basket_id: 9 }));
    assert!(r.errors.contains(ErrorBits::ADD_ERROR));
    let r = response(&send(&mut link, AddBasket { basket_id: 6 }));
    assert!(r.errors.contains(ErrorBits::ADD_ERROR), "an empty basket");
    let r = response(&send(&mut link, AddBasket { basket_id: 5 }));
    assert_eq!(r.errors, ErrorBits::NO_NETWORK_CONFIG);
    assert_eq!(
        (link.station().input_len(), link.station().output_len()),
        (8, 8)
    );
    for step in [
        send(&mut link, AddDevice { device_id: 1 }),
        send(
            &mut link,
            AddItem {
                item_id: 1001,
                position: 3,
            },
        ),
    ] {
        assert!(response(&step).errors.contains(ErrorBits::LOCKOUT));
    }
    let r = response(&send(&mut link, AddBasket { basket_id: 5 }));
    assert!(
        r.errors.contains(ErrorBits::ADD_ERROR),
        "Add Basket is valid once"
    );
    // A reset lifts the lock.
    send(&mut link, RequestReset);
    send(&mut link, RequestStatus);
    let r = response(&send(&mut link, AddDevice { device_id: 1 }));
    assert_eq!(
        r.errors,
        ErrorBits::INCOMPLETE_CONFIG | ErrorBits::NO_NETWORK_CONFIG
    );
}

#[test]
fn add_rules() {
    let mut link = Link::new(Baskets::new());
    send(&mut link, RequestStatus);
    let add = |link: &mut Link, item_id, position| {
        response(&send(link, AddItem { item_id, position })).errors
    };
    // No device yet.
    assert!(add(&mut link, 1001, 1).contains(ErrorBits::ADD_ERROR));
    send(&mut link, AddDevice { device_id: 1 });
    // The same device again is a retry; another one is an error.
    assert!(
        !response(&send(&mut link, AddDevice { device_id: 1 }))
            .errors
            .contains(ErrorBits::ADD_ERROR)
    );
    assert!(
        response(&send(&mut link, AddDevice { device_id: 2 }))
            .errors
            .contains(ErrorBits::ADD_ERROR)
    );
    // Invalid item ID, slot 0.
    assert!(add(&mut link, 3512, 1).contains(ErrorBits::ADD_ERROR));
    assert!(add(&mut link, 1001, 0).contains(ErrorBits::ADD_ERROR));
    // A retry of the same item at the same slot; another item there is an error.
    assert!(!add(&mut link, 3008, 1).contains(ErrorBits::ADD_ERROR));
    assert!(!add(&mut link, 3008, 1).contains(ErrorBits::ADD_ERROR));
    assert!(add(&mut link, 1001, 1).contains(ErrorBits::ADD_ERROR));
    assert_eq!(link.station().items.len(), 1);
    // 384 bytes each way at most: 8 + 256 + 64 + 32 + 16 + 8 = 384, then one more is too many.
    for (id, slot) in [(3256, 2), (3064, 3), (3032, 4), (3016, 5), (3008, 6)] {
        assert!(
            !add(&mut link, id, slot).contains(ErrorBits::ADD_ERROR),
            "{id}"
        );
    }
    assert_eq!(link.station().input_len(), 384);
    assert!(add(&mut link, 2001, 7).contains(ErrorBits::ADD_ERROR));
    assert!(add(&mut link, 1001, 7).contains(ErrorBits::ADD_ERROR));
}

#[test]
fn network_configuration_and_mac_checks() {
    let mut link = Link::new(Baskets::new());
    send(&mut link, RequestStatus);
    let mut bad = network();
    bad.host_name = b"";
    let step = send(&mut link, bad);
    let r = response(&step);
    // Refused, so there is still none.
    assert!(r.errors.contains(ErrorBits::NETWORK_CONFIG_INVALID));
    assert!(r.errors.contains(ErrorBits::NO_NETWORK_CONFIG));
    assert_eq!(
        warnings(&step),
        [&Warning::Network(NetworkConfigError::HostNameEmpty)]
    );
    let r = response(&send(&mut link, network()));
    assert!(!r.errors.contains(ErrorBits::NO_NETWORK_CONFIG));
    let r = response(&send(
        &mut link,
        SetMac {
            mac: MacAddress([1, 0, 0x5E, 0, 0, 1]),
        },
    ));
    assert!(r.errors.contains(ErrorBits::NETWORK_CONFIG_INVALID));
    assert_eq!(link.station().mac, None);
}

#[test]
fn reset_goes_back_to_standby_from_any_mode() {
    let mut link = running();
    let step = send(&mut link, RequestReset);
    assert!(step.send.is_empty());
    assert_eq!(step.actions, [Action::Reset]);
    assert_eq!(link.mode(), Mode::Standby);
    assert_eq!(link.station(), &Station::default());
    // And up again.
    send(&mut link, RequestStatus);
    assert_eq!(link.mode(), Mode::Config);
    // A start that fails in Pending goes back to Config with bit 6.
    let mut link = configured();
    link.set_flags(StatusFlags::LINK_UP);
    send(&mut link, RequestStart);
    assert_eq!(link.mode(), Mode::Pending);
    link.start_failed(StartRefusal::NoLink);
    assert_eq!(link.mode(), Mode::Config);
    assert_eq!(
        response(&send(&mut link, RequestStatus)).errors,
        ErrorBits::START_REFUSED
    );
}

proptest! {
    /// Any host frames (and line errors) in any order: the link never panics, answers only
    /// with Adapter Responses of its mode, and hands out input data of the configured length.
    #[test]
    fn any_host_traffic_keeps_the_rules(
        frames in proptest::collection::vec(crate::frame::tests::any_frame(), 0..40),
        errors in proptest::collection::vec(any::<bool>(), 40),
    ) {
        let mut link = Link::new(Baskets::new());
        link.set_flags(StatusFlags::LINK_UP);
        for ((id, payload), error) in frames.iter().zip(&errors) {
            let item = if *error {
                Err(StreamError::UnknownId(0xFF))
            } else {
                Ok(FrameRepr { id: *id, payload })
            };
            let before = link.mode();
            let step = link.handle(item);
            for bytes in &step.send {
                let r = <AdapterResponse as Message>::parse(&FrameRepr::parse_bytes(bytes).unwrap());
                prop_assert_eq!(r.unwrap().status.mode, link.mode());
            }
            if before == Mode::Standby {
                prop_assert!(step.send.len() <= 1);
            }
            for a in &step.actions {
                match a {
                    Action::Start(_) => link.started(),
                    Action::SetInputs(d) => prop_assert_eq!(d.len(), link.station().input_len()),
                    _ => {}
                }
            }
            prop_assert_eq!(link.adapter_data(&vec![0; link.station().output_len()]).is_some(),
                            link.mode() == Mode::Run);
        }
    }
}
