// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFINET IO, sans-IO: wire formats as checked views over byte buffers plus `Repr`s that
//! parse and emit them, the layout of an IO CR's frame, the acyclic RTA channel, the DCP
//! client, the IO controller's state machines and the IO device's protocol engine. No
//! socket, no clock, no random source (randomness comes in as a seed): bytes and timestamps
//! in, bytes and actions out. procimgd's cycle thread and acyclic side drive it; tests drive
//! it directly, from real captures (`tests/fixtures/captures`).
//!
//! An IO controller brings a device up and exchanges data with it, both in memory: the
//! caller moves the frames and datagrams between them, gives them the time, and runs the
//! cyclic exchange that [`controller::ControllerAction::Start`] hands over (in procimgd the cycle
//! thread does that part). The device echoes its outputs; the controller reads them back.
//!
//! ```
//! use procimg_profinet::controller::plan::{
//!     ControllerIdentity, DevicePlan, DeviceSpec, SubmoduleSpec,
//! };
//! use procimg_profinet::controller::{ControllerAction, Controller};
//! use procimg_profinet::cyclic::{Consumer, ProducedData, Verdict};
//! use procimg_profinet::wire::rt::{cycle_counter_at, data_status};
//! use procimg_profinet::device::{
//!     Application, DeviceAction, Device, DeviceSetup,
//! };
//! use procimg_profinet::wire::{MacAddress, ethernet, rpc::RPC_PORT};
//! use std::net::{Ipv4Addr, SocketAddrV4};
//!
//! /// The device's program: its inputs are its outputs.
//! struct Echo;
//! impl Application for Echo {
//!     fn fill_inputs(&mut self, _k: u64, inputs: &mut [u8], own: &[u8], _: &[u8], _: bool) {
//!         let n = inputs.len().min(own.len());
//!         inputs[..n].copy_from_slice(&own[..n]);
//!     }
//! }
//!
//! /// The controller's program: the same value to every output, every status GOOD.
//! struct Constant([u8; 4]);
//! impl ProducedData for Constant {
//!     fn data(&self, _submodule: usize) -> &[u8] { &self.0 }
//!     fn iops(&self, _submodule: usize) -> u8 { 0x80 }
//!     fn iocs(&self, _submodule: usize) -> u8 { 0x80 }
//! }
//!
//! // A device with its access point (slot 0) and a module of 4 input and 4 output bytes.
//! let (dap, io) = ((0u16, 0u16, 0u16), (1u16, 4u16, 4u16));
//! let device_ip = Ipv4Addr::new(192, 168, 0, 11);
//! let spec = DeviceSpec {
//!     name: "echo".into(), ip: Some(device_ip), vendor_id: 0x0493, device_id: 1, instance: 1,
//!     reduction_ratio: 1, watchdog_factor: 3,
//!     submodules: [dap, io].iter().map(|&(slot, input_length, output_length)| SubmoduleSpec {
//!         api: 0, slot, subslot: 1, module_ident: 0x10 + u32::from(slot), submodule_ident: 1,
//!         input_length, output_length, records: vec![],
//!     }).collect(),
//!     ..Default::default()
//! };
//! let mut device = Device::new(DeviceSetup {
//!     name: spec.name.clone(), mac: MacAddress([2, 0, 0, 0, 0, 11]), ip: Some(device_ip.octets()),
//!     vendor_id: spec.vendor_id, device_id: spec.device_id, instance: 1,
//!     submodules: spec.submodules.iter().map(SubmoduleSpec::plugged).collect(),
//!     application: Echo,
//!     im0: Default::default(),
//! });
//! let id = ControllerIdentity {
//!     mac: MacAddress([2, 0, 0, 0, 0, 1]), ip: Ipv4Addr::new(192, 168, 0, 1),
//!     station_name: "plc".into(), vendor_id: 0x0493, device_id: 2, instance: 1,
//! };
//! let controller_rpc = SocketAddrV4::new(id.ip, RPC_PORT);
//! let plans = DevicePlan::all(&[spec], 1_000_000).expect("a 1 ms cycle suits the device");
//! let mut controller = Controller::new(id, plans, 0, 42);
//!
//! let (mut to_device, mut to_controller) = (Vec::new(), Vec::new());
//! controller.set_online(true, 0, &mut to_device);
//! const VALUE: [u8; 4] = [0xc0, 0xff, 0xee, 0x01];
//! let mut cyclic = None;
//! let mut echoed = None;
//! for k in 1..2_000u64 {
//!     let now = k * 1_000_000;
//!     // What the controller wants sent goes to the device; what it answers comes back.
//!     while !to_device.is_empty() || !to_controller.is_empty() {
//!         for action in std::mem::take(&mut to_device) {
//!             match action {
//!                 ControllerAction::Frame(f) => device.on_frame(&f, now, &mut to_controller),
//!                 ControllerAction::Datagram { to, payload } => {
//!                     let port = to.port();
//!                     device.on_datagram(controller_rpc, port, &payload, now, &mut to_controller)
//!                 }
//!                 ControllerAction::Start(ar) => cyclic = Some((Consumer::of(&ar, now), ar)),
//!                 ControllerAction::Stop { .. } => cyclic = None,
//!                 ControllerAction::Neighbour { .. } | ControllerAction::Event(_) => {}
//!             }
//!         }
//!         for action in std::mem::take(&mut to_controller) {
//!             match action {
//!                 DeviceAction::Frame(f) => {
//!                     let eth = ethernet::Frame::new_checked(&f[..]).unwrap();
//!                     let verdict = match cyclic.as_mut() {
//!                         Some((consumer, _)) => consumer.consume(eth.src(), eth.payload(), now),
//!                         None => Verdict::Foreign,
//!                     };
//!                     match (verdict, &cyclic) {
//!                         // An input frame of the exchange: read the module's inputs.
//!                         (Verdict::Accepted { c_sdu, first, .. }, Some((_, ar))) => {
//!                             if first {
//!                                 controller.on_data_started(ar.device, ar.epoch);
//!                             }
//!                             let o = ar.input.objects.iter().find(|o| o.len == 4).unwrap();
//!                             echoed = Some(c_sdu[o.data..o.data + 4].to_vec());
//!                         }
//!                         (Verdict::Foreign, _) => controller.on_frame(&f, now, &mut to_device),
//!                         _ => {}
//!                     }
//!                 }
//!                 DeviceAction::Datagram { to: _, from_port, payload } => {
//!                     let from = SocketAddrV4::new(device_ip, from_port);
//!                     controller.on_datagram(from, &payload, now, &mut to_device)
//!                 }
//!                 // This device exchanges its cyclic data itself.
//!                 DeviceAction::StartCyclic(_)
//!                 | DeviceAction::StopCyclic { .. }
//!                 | DeviceAction::Record(_)
//!                 | DeviceAction::ArCheck(_)
//!                 | DeviceAction::DcpSetCheck(_) => {}
//!             }
//!         }
//!     }
//!     device.poll(now, &mut to_controller);
//!     controller.poll(now, &mut to_device);
//!     // The cycle's part: the output frame with 0xC0FFEE01 for the module, everything GOOD.
//!     if let Some((_, ar)) = cyclic.as_mut() {
//!         ar.fill(&Constant(VALUE));
//!         let frame = ar.seal(cycle_counter_at(now), data_status::OPERATE);
//!         device.on_frame(frame, now, &mut to_controller);
//!     }
//!     if echoed.as_deref() == Some(&VALUE[..]) {
//!         break;
//!     }
//! }
//! assert_eq!(echoed.as_deref(), Some(&VALUE[..]), "the device echoed the value");
//! ```
#![forbid(unsafe_code)]

#[macro_use]
extern crate coded_enum;

pub mod controller;
pub mod cyclic;
pub mod dcp_client;
pub mod device;
pub mod iocr_layout;
pub mod port;
pub mod rta;
#[cfg(test)]
pub(crate) mod test_fixtures;
pub mod wire;
