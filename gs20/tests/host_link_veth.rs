// SPDX-License-Identifier: MIT OR Apache-2.0
//! As root: a GS20-PN host on a pty, the bridge, procimgd's station in one network
//! namespace and procimg's own controller as its PLC in another, over a veth pair, both
//! configured with the catalogue's GSDML file ([`host::plant`]). The host's input images
//! reach the controller's client whole, the controller's outputs reach the host as Adapter
//! Data whole, the host hears the PLC go when the controller is killed and come back when
//! it restarts, and tshark finds nothing wrong with any frame on the wire.

mod host;

use host::Got;
use host::plant::{INPUT_LEN, OUTPUT_LEN, Plant, STATION_NAME};
use procimg_client::{AttachOptions, Client, Ioxs};
use procimg_gs20::catalogue::ITEM_SUBSLOT;
use procimg_gs20::messages::{Event, SetBusData};
use procimg_testkit::exchange::at;
use procimg_testkit::tshark::{flagged, frames_matching};
use procimg_testkit::{pattern, pattern_value};
use std::time::{Duration, Instant};

/// The host's input image `j`: item 3032's bytes a pattern of `j` (torn shows), item
/// 1004's the low 32 bits of `j` (an image mixed from two of the host's shows too).
fn image(j: u64) -> Vec<u8> {
    let mut image = pattern(j, OUTPUT_LEN);
    image.extend_from_slice(&(j as u32).to_le_bytes());
    assert_eq!(image.len(), INPUT_LEN);
    image
}

/// The host image `j` the PLC's inputs of the two items carry, if they carry a whole one.
fn image_of(item_3032: &[u8], item_1004: &[u8]) -> Option<u64> {
    let j = pattern_value(item_3032)?;
    (item_1004 == (j as u32).to_le_bytes()).then_some(j)
}

/// What the PLC's program saw.
#[derive(Debug, Default)]
struct PlcSaw {
    /// The host's images its inputs carried, each once, in the order they came.
    images: Vec<u64>,
    /// Valid inputs that carried no whole host image.
    wrong: Vec<Vec<u8>>,
    /// Cycles run.
    cycles: u64,
}

/// The PLC's program on `instance`, a client of the controller: writes the pattern of its
/// cycle `k` into item 3032's outputs, up to `k = outputs_to`, where it stays; reads the
/// host's images from its inputs; ends once it wrote `outputs_to` and read `inputs_to`, or
/// after a minute.
fn plc_program(
    instance: String,
    outputs_to: u64,
    inputs_to: u64,
) -> std::thread::JoinHandle<PlcSaw> {
    std::thread::spawn(move || {
        let _ = procimg_client::realtime::make_current_thread_realtime(60);
        let mut client = Client::attach(&instance, AttachOptions::synchronous("gs20-plc"))
            .expect("attach to the controller");
        client
            .claim_device(STATION_NAME)
            .expect("claim the outputs");
        let (big, small) = (at(&client, 1, ITEM_SUBSLOT), at(&client, 2, ITEM_SUBSLOT));
        let mut saw = PlcSaw::default();
        let until = Instant::now() + Duration::from_secs(60);
        while Instant::now() < until {
            let mut cycle = client
                .wait_startop(Duration::from_secs(5))
                .expect("STARTOP");
            saw.cycles += 1;
            let valid = [big, small].iter().all(|&s| {
                cycle
                    .status(s)
                    .is_some_and(|st| st.input_remote == Ioxs::Good)
            });
            let inputs = (
                cycle.input(big).unwrap_or(&[]).to_vec(),
                cycle.input(small).unwrap_or(&[]).to_vec(),
            );
            cycle
                .output_mut(big)
                .expect("outputs")
                .copy_from_slice(&pattern(saw.cycles.min(outputs_to), OUTPUT_LEN));
            cycle.set_opdone().expect("OPDONE");
            if valid {
                match image_of(&inputs.0, &inputs.1) {
                    Some(j) if saw.images.last() != Some(&j) => saw.images.push(j),
                    Some(_) => {}
                    None => saw.wrong.push([inputs.0, inputs.1].concat()),
                }
            }
            if saw.cycles >= outputs_to && saw.images.last() == Some(&inputs_to) {
                break;
            }
        }
        saw
    })
}

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET"]
fn procimg_controller_is_the_plc_of_a_gs20_host_over_a_veth_pair() {
    let Plant {
        bridge,
        mut host,
        mut plc,
        station,
        capture,
        net,
        dir,
    } = Plant::start("g2", true, &image(0));
    let station_mac = station.status().station.unwrap().mac;

    // Both ways at once for a few seconds: the host sends an image every 3 ms (the UART's
    // pace for a 36-byte image is about 4 ms), the PLC new outputs every cycle.
    const HOST_IMAGES: u64 = 1_000;
    const PLC_CYCLES: u64 = 3_000;
    let from = host.mark();
    let program = plc_program(plc.instance.clone(), PLC_CYCLES, HOST_IMAGES);
    for j in 1..=HOST_IMAGES {
        host.send(SetBusData { data: &image(j) });
        host.read(Duration::from_millis(3));
    }
    let last = pattern(PLC_CYCLES, OUTPUT_LEN);
    host.until(from, "Adapter Data with the PLC's last outputs", |g| {
        *g == Got::Data(last.clone())
    });
    let saw = program.join().expect("the PLC's program");

    // The PLC: the host's images whole, in order, the last among them.
    assert!(
        saw.wrong.is_empty(),
        "torn or made-up inputs: {:02x?}",
        saw.wrong
    );
    assert!(
        saw.images.windows(2).all(|w| w[0] < w[1]),
        "images out of order: {:?}",
        saw.images
    );
    assert_eq!(saw.images.last(), Some(&HOST_IMAGES));
    assert!(
        saw.images.len() > 100,
        "the PLC saw {} of the host's {HOST_IMAGES} images",
        saw.images.len()
    );
    // The host: the PLC's outputs whole, in order, never a cycle's that the PLC had not
    // written yet. Zeros are the outputs before the program's first cycle.
    let mut outputs = Vec::new();
    for g in &host.got[from..] {
        match g {
            Got::Data(d) if d.iter().all(|&b| b == 0) => {}
            Got::Data(d) => outputs.push(pattern_value(d).unwrap_or_else(|| {
                panic!(
                    "torn Adapter Data {d:02x?}; received: {}",
                    host.describe(from)
                )
            })),
            Got::Broken(e) => panic!("a broken frame from the module: {e}"),
            Got::Event { .. } => panic!("an event in data exchange: {}", host.describe(from)),
            _ => {}
        }
    }
    assert!(outputs.windows(2).all(|w| w[0] <= w[1]), "{outputs:?}");
    assert!(outputs.len() > 100, "{} Adapter Data frames", outputs.len());
    let statuses = plc.status();
    assert_eq!(statuses.network.watchdog_expiries, 0);

    // The PLC killed: the station's watchdog ends the AR, the host hears PLC lost.
    let from = host.mark();
    plc.kill();
    host.until(from, "Adapter Event PLC lost", |g| {
        g.is_event(Event::PlcLost)
    });
    // The PLC back: the host hears it connect again and its image reaches it.
    let from = host.mark();
    plc.restart();
    host.until(from, "Adapter Event PLC connected again", |g| {
        g.is_event(Event::PlcConnected)
    });
    plc.wait_devices_running(Duration::from_secs(30));
    let again = plc_program(plc.instance.clone(), 10, HOST_IMAGES + 1);
    host.send(SetBusData {
        data: &image(HOST_IMAGES + 1),
    });
    let saw = again.join().expect("the PLC's program, again");
    assert_eq!(saw.images.last(), Some(&(HOST_IMAGES + 1)), "{saw:?}");

    drop((bridge, host, plc, station));
    let (capture, pcap) = capture.expect("the capture");
    capture.stop();
    let bad = flagged(&pcap);
    assert!(bad.is_empty(), "tshark flags frames on the wire:\n{bad}");
    let cyclic =
        format!("eth.src == {station_mac} && pn_rt.frame_id >= 0x0100 && pn_rt.frame_id < 0xfc00");
    let frames = frames_matching(&pcap, &cyclic).lines().count();
    assert!(frames > 3_000, "{frames} cyclic frames from the station");
    drop((net, dir));
}
