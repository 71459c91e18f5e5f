// SPDX-License-Identifier: MIT OR Apache-2.0
//! The configuration procimgd runs with for a measurement: an image of the size asked for,
//! spread over devices the way PROFINET allows (one frame per device and direction), with
//! nobody answering on the network, so the cycle does nothing but the handshake.

pub use procimg_runtime::config::MAX_DEVICES;
use std::fmt::Write as _;

/// Most IO data one device's submodule carries each way here: a submodule's most
/// ([`procimg_shm_layout::MAX_SUBMODULE_DATA_LEN`], 1439) less one, because its input frame
/// (1440 bytes of data and status) also carries the IOPS of its inputs and the IOCS of its
/// outputs.
pub const BYTES_PER_DEVICE: usize = procimg_shm_layout::MAX_SUBMODULE_DATA_LEN as usize - 1;
/// The largest image a configuration can have, per direction.
pub const MAX_IMAGE_BYTES: usize = BYTES_PER_DEVICE * MAX_DEVICES;

/// How the measured server is set up.
#[derive(Clone, Debug)]
pub struct Plant {
    /// iceoryx2 instance name.
    pub instance: String,
    /// Bytes of input data, and as many of output data.
    pub image_bytes: usize,
    /// Cycle time in ns (a multiple of 31.25 µs, as procimgd takes it).
    pub interval_ns: u64,
    /// The cycle thread's SCHED_FIFO priority.
    pub priority: u8,
    /// CPU of the cycle thread.
    pub cpu: Option<usize>,
    /// The cycle thread polls for OPDONE instead of sleeping.
    pub busy_poll: bool,
}

impl Plant {
    /// The plant of the tools that measure procimgd beside its cycle rather than the
    /// handshake: `image_bytes` each way, a 1 ms cycle at SCHED_FIFO 80, nothing pinned, the
    /// server sleeping for OPDONE.
    pub fn at_one_ms(instance: &str, image_bytes: usize) -> Plant {
        Plant {
            instance: instance.to_string(),
            image_bytes,
            interval_ns: 1_000_000,
            priority: 80,
            cpu: None,
            busy_poll: false,
        }
    }

    /// The IO data bytes of each device: `image_bytes` cut into frames.
    pub fn device_sizes(&self) -> Vec<usize> {
        let mut left = self.image_bytes.max(1);
        let mut sizes = Vec::new();
        while left > 0 {
            let n = left.min(BYTES_PER_DEVICE);
            sizes.push(n);
            left -= n;
        }
        sizes
    }

    /// The procimgd configuration file's text.
    pub fn toml(&self) -> String {
        let mut t = String::new();
        let _ = writeln!(
            t,
            "# procimg-handshake: {} bytes each way",
            self.image_bytes
        );
        let _ = writeln!(t, "instance = \"{}\"", self.instance);
        let _ = writeln!(t, "cycle_time = \"{}ns\"", self.interval_ns);
        let _ = writeln!(t, "network = \"sim\"");
        let _ = writeln!(t, "[cycle_thread]");
        let _ = writeln!(t, "priority = {}", self.priority);
        if let Some(cpu) = self.cpu {
            let _ = writeln!(t, "cpu = {cpu}");
        }
        let wait = if self.busy_poll { "busy-poll" } else { "event" };
        let _ = writeln!(t, "opdone_wait = \"{wait}\"");
        for (d, n) in self.device_sizes().into_iter().enumerate() {
            // Absent from the simulated network: nothing answers, the devices stay
            // unconnected and the cycle carries no PROFINET work; the image is published and
            // merged all the same. (Simulated, 256 devices of 1438 bytes would take most of
            // both CPUs of a small machine, and the measurement would be of them.)
            let _ = writeln!(t, "\n[[device]]");
            let _ = writeln!(t, "name = \"{}\"", device_name(d));
            let _ = writeln!(t, "sim = \"absent\"");
            // Host parts 1..=250: never a network's or a broadcast address.
            let _ = writeln!(t, "ip = \"10.1.{}.{}\"", d / 250, 1 + d % 250);
            let _ = writeln!(t, "vendor_id = 0x0493\ndevice_id = 0x0001");
            let _ = writeln!(t, "[[device.submodule]]\nslot = 1\nsubslot = 1");
            let _ = writeln!(t, "module_ident = 0x20\nsubmodule_ident = 0x01");
            let _ = writeln!(t, "input_length = {n}\noutput_length = {n}");
        }
        t
    }
}

/// procimgd's built-in demo (`procimgd --demo`: simulated devices that answer, so the cycle
/// carries their PROFINET work) with instance `instance` and a cycle of `interval_ns`, the
/// OPDONE deadline at half the cycle (the demo's own proportion). `Err` when the demo
/// configuration no longer has the lines this replaces.
pub fn demo_toml(instance: &str, interval_ns: u64) -> Result<String, String> {
    let demo = procimg_runtime::config::DEMO_TOML;
    let mut replaced = [false; 3];
    let mut out = String::with_capacity(demo.len());
    for line in demo.lines() {
        let key = line.split('=').next().unwrap_or("").trim();
        let new = match key {
            "instance" => Some((0, format!("instance = \"{instance}\""))),
            "cycle_time" => Some((1, format!("cycle_time = \"{interval_ns}ns\""))),
            "opdone_deadline" => Some((2, format!("opdone_deadline = \"{}ns\"", interval_ns / 2))),
            _ => None,
        };
        match new {
            Some((i, text)) if !line.starts_with('#') && !replaced[i] => {
                replaced[i] = true;
                out += &text;
            }
            _ => out += line,
        }
        out.push('\n');
    }
    if replaced.contains(&false) {
        return Err(
            "procimgd's demo configuration has no top-level instance, cycle_time or \
             opdone_deadline line any more: update procimg-handshake's plant.rs"
                .into(),
        );
    }
    Ok(out)
}

/// The name of device `d`.
pub fn device_name(d: usize) -> String {
    format!("dev{d}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plant(bytes: usize) -> Plant {
        Plant {
            instance: "x".into(),
            image_bytes: bytes,
            interval_ns: 1_000_000,
            priority: 80,
            cpu: None,
            busy_poll: false,
        }
    }

    #[test]
    fn the_image_is_cut_into_frames() {
        assert_eq!(plant(64).device_sizes(), vec![64]);
        assert_eq!(plant(4096).device_sizes(), vec![1438, 1438, 1220]);
        assert_eq!(plant(MAX_IMAGE_BYTES).device_sizes().len(), MAX_DEVICES);
    }

    #[test]
    fn the_demo_runs_at_the_cycle_asked_for() {
        let text = demo_toml("short", 187_500).unwrap();
        let config = procimg_runtime::config::parse(&text, "demo.toml")
            .unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(config.instance, "short");
        assert_eq!(config.cycle_ns, 187_500);
        assert_eq!(config.opdone_deadline_ns, 93_750);
        assert_eq!(
            config.devices.len(),
            procimg_runtime::config::Config::demo().devices.len()
        );
    }

    #[test]
    fn the_configuration_is_one_procimgd_accepts() {
        let text = plant(4096).toml();
        let config = procimg_runtime::config::parse(&text, "handshake.toml")
            .unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(config.devices.len(), 3);
    }
}
