// SPDX-License-Identifier: MIT OR Apache-2.0
//! A host's plant over a veth pair (root only): procimgd's station in one network namespace,
//! configured with the catalogue's GSDML file as `procimg-gs20 gsdml` writes it; procimg's
//! own controller as its PLC in the other, with the same file and the host's items in its
//! project; the host on a pty with the bridge between it and the station. Brought up to
//! where a user's host would be after its start: the host in Run, the PLC's AR in data
//! exchange.

use super::bridge::{Bridge, synchronise};
use super::{Got, Host};
use procimg_config::gsdml::export::{module_item_id, submodule_item_id};
use procimg_gs20::catalogue::ITEM_SUBSLOT;
use procimg_gs20::messages::{
    AddDevice, AddItem, ErrorBits, Event, ItemId, Mode, RequestStart, SetBusData, SetNetworkConfig,
};
use procimg_testkit::files::TempDir;
use procimg_testkit::netns::TestNet;
use procimg_testkit::tshark::LiveCapture;
use procimg_testkit::{Launch, Procimgd};
use std::net::Ipv4Addr;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// The host's items and their positions: 32 bytes in and out at slot 1 (room for
/// [`procimg_testkit::pattern`], which shows a torn image), 4 bytes in at slot 2.
pub const ITEMS: [(u16, u16); 2] = [(3032, 1), (1004, 2)];

/// The host's input image: item 3032's 32 bytes, then item 1004's 4.
pub const INPUT_LEN: usize = 36;

/// The host's output image: item 3032's 32 bytes.
pub const OUTPUT_LEN: usize = 32;

/// The station's name and address, as the host's Set Network Configuration gives them.
pub const STATION_NAME: &str = "gs20-host";
/// See [`STATION_NAME`].
pub const STATION_IP: Ipv4Addr = Ipv4Addr::new(10, 47, 0, 50);

/// Generous: a loaded machine is slow to connect.
const BRING_UP: Duration = Duration::from_secs(30);

/// The plant, dropped in field order: the bridge, the host's pty, the PLC, the station, the
/// capture, the namespaces, the files.
pub struct Plant {
    /// The bridge.
    pub bridge: Bridge,
    /// The host.
    pub host: Host,
    /// procimg's controller: the PLC.
    pub plc: Procimgd,
    /// procimgd in the device role: the module's PROFINET side.
    pub station: Procimgd,
    /// Every frame on the PLC's end of the pair, if asked for.
    pub capture: Option<(LiveCapture, PathBuf)>,
    /// The namespaces and the pair.
    pub net: TestNet,
    /// The GSDML file and the capture.
    pub dir: TempDir,
}

/// The catalogue's GSDML file, written by `procimg-gs20 gsdml -d DIR` as a user would.
fn catalogue(dir: &Path) -> PathBuf {
    let out = Command::new(env!("CARGO_BIN_EXE_procimg-gs20"))
        .args(["gsdml", "--date", "2026-11-28", "-d"])
        .arg(dir)
        .output()
        .expect("run procimg-gs20 gsdml");
    assert!(
        out.status.success(),
        "procimg-gs20 gsdml failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    PathBuf::from(String::from_utf8(out.stdout).unwrap().trim())
}

/// The station's configuration: a station its program (the bridge) defines, from the
/// catalogue. Its name here is a placeholder: the host's network configuration replaces it.
fn station_toml(network: &str, gsdml: &Path) -> String {
    format!(
        "role = \"device\"\ncycle_time = \"1ms\"\nnetwork = \"{network}\"\n[station]\n\
         name = \"gs20-pn\"\ngsdml = \"{}\"\n",
        gsdml.display()
    )
}

/// The PLC's project: the host's station by the host's name and address, its items as the
/// catalogue's modules at their positions.
///
/// The watchdog allows 100 frames (100 ms), for both sides (the station takes its data hold
/// time from the Connect): two cycle threads of a test build, the bridge and the test share
/// two virtual CPUs here, whose stalls reach several ms; the default 3 ms would count those
/// stalls, where the test counts what the bridge does.
fn controller_toml(network: &str, gsdml: &Path) -> String {
    let mut toml = format!(
        "cycle_time = \"1ms\"\nnetwork = \"{network}\"\n[[device]]\nname = \"{STATION_NAME}\"\n\
         ip = \"{STATION_IP}\"\ngsdml = \"{}\"\nwatchdog_factor = 100\n",
        gsdml.display()
    );
    for (id, slot) in ITEMS {
        let module = ItemId::from_u16(id).unwrap().module_ident();
        toml += &format!(
            "[[device.submodule]]\nslot = {slot}\nsubslot = {ITEM_SUBSLOT}\nmodule = \"{}\"\n\
             submodule = \"{}\"\n",
            module_item_id(module),
            submodule_item_id(module, ITEM_SUBSLOT)
        );
    }
    toml
}

/// The host's network configuration: [`STATION_NAME`] at [`STATION_IP`]/24.
fn network() -> SetNetworkConfig<'static> {
    SetNetworkConfig::static_ip(
        STATION_IP,
        Ipv4Addr::new(255, 255, 255, 0),
        STATION_NAME.as_bytes(),
    )
}

impl Plant {
    /// Brings the plant up (`tag`: a few letters that keep it apart from other tests'):
    /// returns once the host is in Run, its first input image `first` sent, and both the
    /// host and the PLC say the AR is up. With `capture`, tshark records the PLC's end of
    /// the pair from before the station starts.
    pub fn start(tag: &str, capture: bool, first: &[u8]) -> Plant {
        let net = TestNet::new(tag, true);
        net.address(0, "10.47.0.1/24");
        let dir = procimg_testkit::files::temp_dir(&format!("gs20-{tag}"));
        let gsdml = catalogue(dir.path());
        let capture = capture.then(|| {
            let pcap = dir.path().join("wire.pcapng");
            (LiveCapture::start(&net.ns[0], &net.ifs[0], &pcap), pcap)
        });
        let station = Launch::config(&format!("{tag}d"), &station_toml(&net.ifs[1], &gsdml))
            .netns(&net.ns[1])
            .until_cycling()
            .start();

        // The host defines and starts its station, as in the reference's sequence.
        let mut host = Host::new();
        let mut bridge = Bridge::start(host.port(), &station.instance);
        synchronise(&mut host, &mut bridge);
        host.command(AddDevice { device_id: 1 });
        for (item_id, position) in ITEMS {
            host.command(AddItem {
                item_id,
                position: position.into(),
            });
        }
        let r = host.command(network());
        assert_eq!(r.errors, ErrorBits::empty());
        let started = host.mark();
        let r = host.command(RequestStart);
        assert_eq!(
            (r.status.mode, r.errors),
            (Mode::Pending, ErrorBits::empty())
        );
        host.until(started, "Adapter Event link up", |g| {
            g.is_event(Event::LinkUp)
        });
        host.send(SetBusData { data: first });

        let plc = Launch::config(&format!("{tag}c"), &controller_toml(&net.ifs[0], &gsdml))
            .netns(&net.ns[0])
            .until_cycling()
            .start();
        host.until(started, "Adapter Event PLC connected", |g| {
            g.is_event(Event::PlcConnected)
        });
        plc.wait_devices_running(BRING_UP);
        assert!(matches!(
            host.got[started..]
                .iter()
                .find(|g| matches!(g, Got::Event { .. })),
            Some(Got::Event {
                mode: Mode::Run,
                ..
            })
        ));
        Plant {
            bridge,
            host,
            plc,
            station,
            capture,
            net,
            dir,
        }
    }
}
