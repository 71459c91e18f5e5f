// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-gs20 run` with a host played over a pty pair and procimgd in the device role
//! with its built-in PLC (`network = "sim"`, whose program writes each submodule's Q data as
//! its I data plus one): the host defines its station (Add Device, two items, a network
//! configuration), starts it, and its input bytes come back as Adapter Data by the PLC's
//! rule; a wrong-length image, garbage and a CRC error get their error bits and change
//! nothing the PLC sees; Request Reset takes the station off the wire. And the host's
//! sockets reach peers on this machine (loopback): a UDP datagram each way, a line each way
//! over a TCP client socket, a connection to a TCP server socket.

mod host;

use host::bridge::{Bridge, synchronise};
use host::{Got, Host};
use procimg_config::gsdml::export::{GsdmlDate, station_gsdml};
use procimg_gs20::messages::{
    AddDevice, AddItem, AddressMode, CloseSocket, ErrorBits, Event, Mode, OpenSocket, RequestReset,
    RequestSocketStatus, RequestStart, RequestStatus, SendSocketData, SetBusData, SetNetworkConfig,
    SocketErrors, SocketProtocol, SocketRole, SocketStatus, StatusFlags,
};
use procimg_testkit::Launch;
use std::io::{BufRead, Write};
use std::net::{Ipv4Addr, TcpListener, TcpStream, UdpSocket};
use std::path::Path;
use std::time::{Duration, Instant};

/// The station's GSDML file: a module for each item the test adds (module ident = the item
/// ID, submodule 1, the item's lengths), as the catalogue has them.
const DESCRIBED: &str = r#"
role = "device"
network = "sim"
[station]
name = "gs20-catalogue"
vendor_id = 0x0493
device_id = 0x0120
[[station.submodule]]
slot = 1
module_ident = 3008
submodule_ident = 1
input_length = 8
output_length = 8
[[station.submodule]]
slot = 2
module_ident = 1004
submodule_ident = 1
input_length = 4
"#;

/// Writes the GSDML file into `dir`; its path.
fn gsdml(dir: &Path) -> std::path::PathBuf {
    let config = procimg_config::parse(DESCRIBED, "the test's catalogue").unwrap();
    let file = station_gsdml(
        config.station.as_ref().unwrap(),
        config.cycle_ns,
        GsdmlDate::new(2026, 11, 28).unwrap(),
    )
    .unwrap();
    let path = dir.join(&file.file_name);
    std::fs::write(&path, file.xml).unwrap();
    path
}

fn network() -> SetNetworkConfig<'static> {
    SetNetworkConfig::static_ip(
        Ipv4Addr::new(192, 168, 0, 50),
        Ipv4Addr::new(255, 255, 255, 0),
        b"gs20-host",
    )
}

/// The host's input image: item 3008's 8 bytes, item 1004's 4.
fn inputs(seed: u8) -> Vec<u8> {
    (0..12).map(|i| seed.wrapping_add(i * 3)).collect()
}

/// What the PLC answers: item 3008's inputs plus one (item 1004 has no outputs).
fn answer(inputs: &[u8]) -> Vec<u8> {
    inputs[..8].iter().map(|b| b.wrapping_add(1)).collect()
}

fn defined_by(server: &procimg_testkit::Procimgd) -> Option<String> {
    server
        .status()
        .station
        .and_then(|s| s.program)
        .and_then(|p| p.defined_by)
}

/// procimgd with a station its program defines (the test's GSDML file), a host on a pty,
/// the bridge between them. Dropped in this order: the bridge, the host's pty, procimgd,
/// the files.
struct Rig {
    bridge: Bridge,
    host: Host,
    server: procimg_testkit::Procimgd,
    _dir: procimg_testkit::files::TempDir,
}

impl Rig {
    fn start(tag: &str) -> Rig {
        let dir = procimg_testkit::files::temp_dir(tag);
        let gsdml = gsdml(dir.path());
        let toml = format!(
            "role = \"device\"\ncycle_time = \"1ms\"\nnetwork = \"sim\"\n[station]\n\
             name = \"procimg-device\"\ngsdml = \"{}\"\n",
            gsdml.display()
        );
        let server = Launch::config(tag, &toml).until_cycling().start();
        assert_eq!(
            defined_by(&server),
            None,
            "the station waits for its program"
        );
        let host = Host::new();
        let bridge = Bridge::start(host.port(), &server.instance);
        Rig {
            bridge,
            host,
            server,
            _dir: dir,
        }
    }

    /// Defines and starts the host's station; returns once it is in Run, on the wire, with
    /// the index of the first frame after Request Start's response.
    fn run(&mut self) -> usize {
        synchronise(&mut self.host, &mut self.bridge);
        self.host.command(AddDevice { device_id: 1 });
        self.host.command(AddItem {
            item_id: 3008,
            position: 1,
        });
        self.host.command(AddItem {
            item_id: 1004,
            position: 2,
        });
        let r = self.host.command(network());
        assert_eq!(r.errors, ErrorBits::empty());
        let from = self.host.mark();
        let r = self.host.command(RequestStart);
        assert_eq!(
            (r.status.mode, r.errors),
            (Mode::Pending, ErrorBits::empty())
        );
        self.host
            .until(from, "Adapter Event link up", |g| g.is_event(Event::LinkUp));
        from
    }
}

#[test]
fn a_host_defines_starts_and_exchanges_data_through_the_bridge() {
    let Rig {
        mut bridge,
        mut host,
        server,
        _dir,
    } = Rig::start("gs20");

    // Standby → Config: the configuration is incomplete (bits 0 and 2); procimgd answers,
    // so the link is known and up.
    let r = synchronise(&mut host, &mut bridge);
    assert_eq!(r.status.mode, Mode::Config);
    assert_eq!(
        r.errors,
        ErrorBits::INCOMPLETE_CONFIG | ErrorBits::NO_NETWORK_CONFIG
    );
    assert!(
        r.status
            .flags
            .contains(StatusFlags::ERROR | StatusFlags::LINK_KNOWN | StatusFlags::LINK_UP)
    );
    assert!(!r.status.flags.contains(StatusFlags::PLC_CONNECTED));

    // The station: a device, two items, a network configuration.
    let r = host.command(AddDevice { device_id: 1 });
    assert_eq!(
        (r.status.mode, r.errors),
        (
            Mode::Config,
            ErrorBits::INCOMPLETE_CONFIG | ErrorBits::NO_NETWORK_CONFIG
        )
    );
    for (item_id, position) in [(3008, 1), (1004, 2)] {
        let r = host.command(AddItem { item_id, position });
        assert_eq!(
            (r.status.mode, r.errors),
            (Mode::Config, ErrorBits::NO_NETWORK_CONFIG)
        );
    }
    let r = host.command(network());
    assert_eq!(
        (r.status.mode, r.errors),
        (Mode::Config, ErrorBits::empty())
    );
    assert!(!r.status.flags.contains(StatusFlags::ERROR));

    // Start: Pending, then Run with the station on the wire under the host's name and
    // address, and the PLC connecting it.
    let started = host.mark();
    let r = host.command(RequestStart);
    assert_eq!(
        (r.status.mode, r.errors),
        (Mode::Pending, ErrorBits::empty())
    );
    let (up, _) = host.until(started, "Adapter Event link up", |g| {
        g.is_event(Event::LinkUp)
    });
    assert!(matches!(
        host.got[up],
        Got::Event {
            mode: Mode::Run,
            ..
        }
    ));
    let (_, net) = host.until(started, "Adapter Event network up", |g| {
        matches!(g, Got::Event { code: 3, .. })
    });
    assert_eq!(
        net,
        Got::Event {
            mode: Mode::Run,
            code: 3,
            ip: Some(Ipv4Addr::new(192, 168, 0, 50))
        }
    );
    let first = inputs(0x10);
    host.send(SetBusData { data: &first });
    host.until(started, "Adapter Event PLC connected", |g| {
        g.is_event(Event::PlcConnected)
    });
    let st = server.status().station.unwrap();
    assert_eq!(
        (st.name.as_str(), st.ip.as_str()),
        ("gs20-host", "192.168.0.50")
    );
    assert!(defined_by(&server).is_some_and(|b| b.contains("procimg-gs20")));
    let want = answer(&first);
    host.until(started, "Adapter Data with the PLC's answer", |g| {
        *g == Got::Data(want.clone())
    });
    let r = host.command(RequestStatus);
    assert_eq!(r.status.mode, Mode::Run);
    assert_eq!(r.errors, ErrorBits::empty());
    assert!(r.status.flags.contains(
        StatusFlags::LINK_UP
            | StatusFlags::IP_OK
            | StatusFlags::NETWORK_OK
            | StatusFlags::PLC_CONNECTED
    ));

    // A wrong length: error bit 7, and the PLC keeps the last whole image: the next
    // Adapter Data frames (one per period at least) still answer it.
    let from = host.mark();
    host.send(SetBusData { data: &first[..11] });
    let (at, r) = host.response(from);
    assert_eq!(
        (r.status.mode, r.errors),
        (Mode::Run, ErrorBits::IO_SIZE_MISMATCH)
    );
    assert!(r.status.flags.contains(StatusFlags::ERROR));
    let mut after = at + 1;
    for _ in 0..5 {
        let (i, g) = host.until(after, "Adapter Data", |g| matches!(g, Got::Data(_)));
        assert_eq!(
            g,
            Got::Data(want.clone()),
            "the wrong-length image reached the PLC"
        );
        after = i + 1;
    }

    // A CRC error right after a good frame: bit 4; garbage between frames: bit 5; the
    // frames after them are taken.
    let from = host.mark();
    host.send_bytes(&[0x20, 0x00, 0x18, 0x71]);
    host.send(RequestStatus);
    let (i, r) = host.response(from);
    assert_eq!(r.errors, ErrorBits::CRC);
    let (_, r) = host.response(i + 1);
    assert_eq!((r.status.mode, r.errors), (Mode::Run, ErrorBits::empty()));
    let from = host.mark();
    host.send_bytes(&[0x00, 0x7F, 0xAA, 0x55]);
    host.send(RequestStatus);
    let (i, r) = host.response(from);
    assert_eq!(r.errors, ErrorBits::FRAME);
    let (_, r) = host.response(i + 1);
    assert_eq!(r.errors, ErrorBits::empty());
    let second = inputs(0x80);
    let from = host.mark();
    host.send(SetBusData { data: &second });
    let want = answer(&second);
    host.until(
        from,
        "Adapter Data with the PLC's answer to the second image",
        |g| *g == Got::Data(want.clone()),
    );
    let connected = host
        .got
        .iter()
        .filter(|g| g.is_event(Event::PlcConnected))
        .count();
    assert_eq!(connected, 1, "{:?}", host.got);
    assert!(!host.got.iter().any(|g| g.is_event(Event::PlcLost)));

    // Request Reset: the AR ends, the station leaves the wire and waits for its program
    // again; the host hears it as PLC lost and link down, then the module is in Standby.
    let from = host.mark();
    host.send(RequestReset);
    let (lost, _) = host.until(from, "Adapter Event PLC lost", |g| {
        g.is_event(Event::PlcLost)
    });
    let (down, _) = host.until(from, "Adapter Event link down", |g| {
        g.is_event(Event::LinkDown)
    });
    assert!(lost < down);
    server.wait_status("the station waiting again", |s| {
        s.station
            .as_ref()
            .and_then(|s| s.program.as_ref())
            .is_some_and(|p| p.defined_by.is_none())
    });
    let r = synchronise(&mut host, &mut bridge);
    assert_eq!(
        (r.status.mode, r.errors),
        (
            Mode::Config,
            ErrorBits::INCOMPLETE_CONFIG | ErrorBits::NO_NETWORK_CONFIG
        )
    );
    assert!(!r.status.flags.contains(StatusFlags::PLC_CONNECTED));
    assert!(
        bridge.0.try_wait().unwrap().is_none(),
        "procimg-gs20 still runs"
    );
    // The host's end of the line goes away (a USB-UART unplugged): the bridge stops with
    // an error rather than spinning on the hung-up port.
    drop(host);
    let deadline = Instant::now() + host::GENEROUS;
    let status = loop {
        if let Some(status) = bridge.0.try_wait().unwrap() {
            break status;
        }
        assert!(
            Instant::now() < deadline,
            "procimg-gs20 did not stop after the hang-up"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(status.code(), Some(1));
    drop((bridge, server));
}

#[test]
fn the_hosts_sockets_reach_peers_on_this_machine() {
    let mut rig = Rig::start("gs20-sockets");
    let _ = rig.run();
    let host = &mut rig.host;
    let loopback = Ipv4Addr::LOCALHOST;

    // UDP: a datagram to a peer, its answer back.
    let peer = UdpSocket::bind((loopback, 0)).unwrap();
    peer.set_read_timeout(Some(host::GENEROUS)).unwrap();
    let port = peer.local_addr().unwrap().port();
    let r = host.socket(OpenSocket {
        role: SocketRole::Client,
        protocol: SocketProtocol::Udp,
        port,
        ip: loopback,
    });
    assert_eq!(
        (r.status, r.errors),
        (SocketStatus::LISTENING, SocketErrors::empty())
    );
    let udp = r.handle;
    assert_ne!(udp, 0);
    let r = host.socket(SendSocketData {
        handle: udp,
        data: b"ping",
    });
    assert_eq!(r.errors, SocketErrors::empty());
    let mut buf = [0u8; 64];
    let (n, from) = peer.recv_from(&mut buf).expect("the host's datagram");
    assert_eq!(&buf[..n], b"ping");
    let mark = host.mark();
    peer.send_to(b"pong", from).unwrap();
    assert_eq!(host.socket_data(mark, udp, b"pong"), b"pong");

    // TCP client: connected, a line each way.
    let server = TcpListener::bind((loopback, 0)).unwrap();
    let port = server.local_addr().unwrap().port();
    let mark = host.mark();
    let r = host.socket(OpenSocket {
        role: SocketRole::Client,
        protocol: SocketProtocol::Tcp,
        port,
        ip: loopback,
    });
    assert_eq!(r.errors, SocketErrors::empty());
    let tcp = r.handle;
    assert!(tcp != 0 && tcp != udp);
    let (_, connected) = host.until(
        mark,
        "Socket Event connected",
        |g| matches!(g, Got::SocketEvent { handle, code: 1, .. } if *handle == tcp),
    );
    assert!(
        matches!(connected, Got::SocketEvent { status, .. } if status == SocketStatus::CONNECTED)
    );
    let (conn, _) = server.accept().unwrap();
    conn.set_read_timeout(Some(host::GENEROUS)).unwrap();
    let r = host.socket(SendSocketData {
        handle: tcp,
        data: b"hello from the host\n",
    });
    assert_eq!(r.errors, SocketErrors::empty());
    let mut line = String::new();
    std::io::BufReader::new(&conn).read_line(&mut line).unwrap();
    assert_eq!(line, "hello from the host\n");
    let mark = host.mark();
    (&conn).write_all(b"and back\n").unwrap();
    assert_eq!(host.socket_data(mark, tcp, b"\n"), b"and back\n");

    // TCP server: a connection is a child socket, announced on the server's handle; the
    // server cannot close while it has one.
    let port = TcpListener::bind((loopback, 0))
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let r = host.socket(OpenSocket {
        role: SocketRole::Server,
        protocol: SocketProtocol::Tcp,
        port,
        ip: loopback,
    });
    assert_eq!(
        (r.status, r.errors),
        (SocketStatus::ACCEPTING, SocketErrors::empty())
    );
    let listening = r.handle;
    let mark = host.mark();
    let client = TcpStream::connect((loopback, port)).unwrap();
    host.until(
        mark,
        "Socket Event accepted",
        |g| matches!(g, Got::SocketEvent { handle, code: 2, .. } if *handle == listening),
    );
    (&client).write_all(b"to the child\n").unwrap();
    let child = host.got[mark..].iter().find_map(|g| match g {
        Got::SocketData { handle, .. } if ![udp, tcp, listening].contains(handle) => Some(*handle),
        _ => None,
    });
    let child = match child {
        Some(c) => c,
        None => {
            let (_, g) = host.until(mark, "data on the child socket", |g| {
                matches!(g, Got::SocketData { handle, .. } if ![udp, tcp, listening].contains(handle))
            });
            match g {
                Got::SocketData { handle, .. } => handle,
                _ => unreachable!(),
            }
        }
    };
    assert_eq!(host.socket_data(mark, child, b"\n"), b"to the child\n");
    let r = host.socket(CloseSocket { handle: listening });
    assert_eq!(r.errors, SocketErrors::CLOSE_FAILED);
    for handle in [child, listening, tcp, udp] {
        let r = host.socket(CloseSocket { handle });
        assert_eq!(r.errors, SocketErrors::empty(), "closing {handle}");
    }
    let r = host.socket(RequestSocketStatus { handle: tcp });
    assert_eq!(r.errors, SocketErrors::NOT_OPEN);
    assert!(
        rig.bridge.0.try_wait().unwrap().is_none(),
        "procimg-gs20 still runs"
    );
}

/// An item the station's GSDML file does not have: procimgd refuses the station, the host
/// gets error bit 6 in Config, and after a Request Reset a station of known items starts.
#[test]
fn a_station_procimgd_refuses_is_start_refused_and_the_host_can_start_again() {
    let Rig {
        mut bridge,
        mut host,
        server,
        _dir,
    } = Rig::start("gs20-refused");
    synchronise(&mut host, &mut bridge);
    host.command(AddDevice { device_id: 1 });
    let r = host.command(AddItem {
        item_id: 3016,
        position: 1,
    });
    assert_eq!(
        r.errors,
        ErrorBits::NO_NETWORK_CONFIG,
        "the catalogue has item 3016"
    );
    host.command(network());
    let r = host.command(RequestStart);
    assert_eq!(r.status.mode, Mode::Pending);
    let r = host.command(RequestStatus);
    assert_eq!(
        (r.status.mode, r.errors),
        (Mode::Config, ErrorBits::START_REFUSED)
    );
    assert_eq!(defined_by(&server), None, "the station still waits");
    // The bit was reported once; the link keeps working.
    let r = host.command(RequestStatus);
    assert_eq!(
        (r.status.mode, r.errors),
        (Mode::Config, ErrorBits::empty())
    );

    host.send(RequestReset);
    let mut rig = Rig {
        bridge,
        host,
        server,
        _dir,
    };
    let _ = rig.run();
    assert!(defined_by(&rig.server).is_some_and(|b| b.contains("procimg-gs20")));
}

/// procimgd stops and starts again while the host is in Run: the host hears PLC lost and
/// link down, stays in Run, and its station is defined again with its last input image,
/// which the PLC answers again.
#[test]
fn the_hosts_station_comes_back_when_procimgd_does() {
    let mut rig = Rig::start("gs20-restart");
    let started = rig.run();
    let image = inputs(0x40);
    let from = rig.host.mark();
    rig.host.send(SetBusData { data: &image });
    let want = answer(&image);
    rig.host
        .until(from, "Adapter Data with the PLC's answer", |g| {
            *g == Got::Data(want.clone())
        });
    rig.host.until(started, "Adapter Event PLC connected", |g| {
        g.is_event(Event::PlcConnected)
    });

    let from = rig.host.mark();
    rig.server.restart();
    let (lost, _) = rig.host.until(from, "Adapter Event PLC lost", |g| {
        g.is_event(Event::PlcLost)
    });
    let (down, _) = rig.host.until(from, "Adapter Event link down", |g| {
        g.is_event(Event::LinkDown)
    });
    assert!(lost < down);
    let (up, _) = rig
        .host
        .until(down, "Adapter Event link up", |g| g.is_event(Event::LinkUp));
    rig.host
        .until(up, "Adapter Event PLC connected again", |g| {
            g.is_event(Event::PlcConnected)
        });
    // No Set Bus Data since: the station got the host's last image.
    rig.host
        .until(up, "Adapter Data with the PLC's answer again", |g| {
            *g == Got::Data(want.clone())
        });
    let r = rig.host.command(RequestStatus);
    assert_eq!((r.status.mode, r.errors), (Mode::Run, ErrorBits::empty()));
    assert!(defined_by(&rig.server).is_some_and(|b| b.contains("procimg-gs20")));
    assert!(
        rig.bridge.0.try_wait().unwrap().is_none(),
        "procimg-gs20 still runs"
    );
}

/// A host that asks for DHCP: its station goes on the wire without an address of its own,
/// the PLC assigns one by DCP (PROFINET's way; the demo PLC does it before its Connect),
/// and the host hears the address in Network Up after link up, then the PLC connects.
#[test]
fn with_dhcp_the_plc_gives_the_station_its_address() {
    let Rig {
        mut bridge,
        mut host,
        server,
        _dir,
    } = Rig::start("gs20-dhcp");
    synchronise(&mut host, &mut bridge);
    host.command(AddDevice { device_id: 1 });
    host.command(AddItem {
        item_id: 3008,
        position: 1,
    });
    let r = host.command(SetNetworkConfig {
        mode: AddressMode::Dhcp,
        ip: Ipv4Addr::UNSPECIFIED,
        mask: Ipv4Addr::UNSPECIFIED,
        ..network()
    });
    assert_eq!(r.errors, ErrorBits::empty());
    let started = host.mark();
    let r = host.command(RequestStart);
    assert_eq!(r.status.mode, Mode::Pending);
    let (up, _) = host.until(started, "Adapter Event link up", |g| {
        g.is_event(Event::LinkUp)
    });
    let (net, got) = host.until(started, "Adapter Event network up", |g| {
        matches!(g, Got::Event { code: 3, .. })
    });
    assert!(up < net, "no address before the PLC gives one");
    let Got::Event { ip: Some(ip), .. } = got else {
        unreachable!()
    };
    assert!(!ip.is_unspecified());
    host.until(started, "Adapter Event PLC connected", |g| {
        g.is_event(Event::PlcConnected)
    });
    let st = server.status().station.unwrap();
    assert_eq!(
        st.ip,
        ip.to_string(),
        "the address the host heard is the station's"
    );
    let r = host.command(RequestStatus);
    assert!(
        r.status
            .flags
            .contains(StatusFlags::IP_OK | StatusFlags::PLC_CONNECTED)
    );
    // The bridge first, procimgd after it (the rig's order).
    drop((bridge, host, server));
}

/// Request Reset in Run and the next station's commands and Request Start right after it,
/// without waiting: the next station starts (the release's waiting station, which procimgd
/// runs in between, is not taken for it).
#[test]
fn a_reset_and_a_new_start_back_to_back() {
    let mut rig = Rig::start("gs20-again");
    let _ = rig.run();
    let host = &mut rig.host;
    let from = host.mark();
    host.send(RequestReset);
    host.send(RequestStatus);
    host.send(AddDevice { device_id: 2 });
    host.send(AddItem {
        item_id: 3008,
        position: 1,
    });
    host.send(network());
    host.send(RequestStart);
    let (config, got) = host.until(
        from,
        "the response to Request Status",
        |g| matches!(g, Got::Response(r) if r.status.mode == Mode::Config),
    );
    let Got::Response(r) = got else {
        unreachable!()
    };
    assert!(
        !r.status
            .flags
            .intersects(StatusFlags::IP_OK | StatusFlags::PLC_CONNECTED),
        "the station left the wire with the reset: {r:?}"
    );
    let (pending, _) = host.until(
        config,
        "the response to Request Start",
        |g| matches!(g, Got::Response(r) if r.status.mode == Mode::Pending),
    );
    let (up, _) = host.until(pending, "Adapter Event link up", |g| {
        g.is_event(Event::LinkUp)
    });
    host.until(up, "Adapter Event PLC connected", |g| {
        g.is_event(Event::PlcConnected)
    });
    let image: Vec<u8> = inputs(0x20)[..8].to_vec();
    let mark = host.mark();
    host.send(SetBusData { data: &image });
    let want = answer(&image);
    host.until(mark, "Adapter Data with the PLC's answer", |g| {
        *g == Got::Data(want.clone())
    });
    assert!(defined_by(&rig.server).is_some_and(|b| b.contains("procimg-gs20")));
}
