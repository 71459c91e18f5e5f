// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg capture`: records the PROFINET frames on an interface, both directions, into a
//! pcap file that Wireshark opens.

use anyhow::Context;
use procimg_nic::af_packet::AfPacket;
use procimg_nic::capture::CaptureWriter;
use procimg_nic::{Nic, RecvError};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

pub fn run(
    iface: &str,
    output: &Path,
    count: Option<u64>,
    seconds: Option<f64>,
) -> anyhow::Result<()> {
    let mut nic = AfPacket::open_capture(iface, Duration::from_millis(100))
        .map_err(crate::dcp::iface_error)?;
    let mut writer = CaptureWriter::create(output)?;
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, stop.clone())
            .with_context(|| format!("cannot install the handler for signal {sig}"))?;
    }
    let until = seconds.map(|s| Instant::now() + Duration::from_secs_f64(s.max(0.0)));
    eprintln!(
        "capturing PROFINET frames on {iface} into {}; Ctrl-C stops",
        output.display()
    );
    let mut frames = 0u64;
    let mut too_long = 0u64;
    while !stop.load(Ordering::Relaxed)
        && until.is_none_or(|u| Instant::now() < u)
        && count.is_none_or(|c| frames < c)
    {
        let mut written = Ok(());
        let received = nic.receive(&mut |frame| {
            let now = SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .unwrap_or_default();
            written = writer.write(now, frame);
        });
        match received {
            Ok(true) => {
                written?;
                frames += 1;
            }
            Ok(false) => {}
            // Not recorded (the interface dropped it); said once, counted at the end.
            Err(e @ RecvError::TooLong { .. }) => {
                if too_long == 0 {
                    eprintln!("warning: {e}");
                }
                too_long += 1;
            }
            Err(e) => return Err(e.into()),
        }
    }
    writer.finish()?;
    println!("{frames} frames written to {}", output.display());
    if too_long > 0 {
        eprintln!("{too_long} frames longer than a PROFINET frame were not recorded");
    }
    Ok(())
}
