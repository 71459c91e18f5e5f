// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg interface`: the controller's own interface, as IO-Base's `PNIO_interface_*`
//! functions use it: a record of the interface or its port, and the station's name and IP
//! suite where `[interface]` lets programs change them.

use crate::services::{RECORD_TIMEOUT, open, parse_u16};
use crate::text::hex;
use anyhow::Context;
use clap::Subcommand;
use procimg_client::{ControllerAddress, INTERFACE_SUBSLOT, PORT_SUBSLOT};
use std::net::Ipv4Addr;

#[derive(Subcommand)]
pub enum InterfaceCommand {
    /// Read a record of the interface (or, with --port, of its port) and print it in hex:
    /// 0x8080 PDInterfaceDataReal, 0x802A PDPortDataReal, 0x8072 PDPortStatistic, 0xF841
    /// PDRealData, 0x800C the diagnosis.
    Record {
        /// Record index (decimal or 0x hex).
        #[arg(long, value_parser = parse_u16)]
        index: u16,
        /// The port's record instead of the interface's.
        #[arg(long)]
        port: bool,
        /// The most bytes to read.
        #[arg(long, default_value_t = 4096)]
        max_len: u32,
    },
    /// Give the controller's station a NameOfStation (`[interface] name_by_program`).
    SetName {
        /// The name.
        name: String,
        /// Keep it across a restart.
        #[arg(long)]
        permanent: bool,
    },
    /// Give the controller's station an IP suite (`[interface] address_by_program`): the
    /// network interface carries it from then on.
    SetIp {
        /// Address.
        ip: Ipv4Addr,
        /// Netmask.
        mask: Ipv4Addr,
        /// Gateway (default: none).
        gateway: Option<Ipv4Addr>,
        /// Keep it across a restart.
        #[arg(long)]
        permanent: bool,
    },
}

pub fn run(instance: &str, op: InterfaceCommand) -> anyhow::Result<()> {
    let mut s = open(instance, "procimg-interface", false)?;
    let change = match op {
        InterfaceCommand::Record {
            index,
            port,
            max_len,
        } => {
            let subslot = if port {
                PORT_SUBSLOT
            } else {
                INTERFACE_SUBSLOT
            };
            let data = s
                .read_interface_record(subslot, index, max_len, RECORD_TIMEOUT)
                .with_context(|| {
                    format!(
                        "reading record {index:#06x} of the controller's subslot {subslot:#06x}"
                    )
                })?;
            println!("{}", hex(&data));
            return Ok(());
        }
        InterfaceCommand::SetName { name, permanent } => ControllerAddress {
            name: Some(name),
            ip_suite: None,
            permanent,
        },
        InterfaceCommand::SetIp {
            ip,
            mask,
            gateway,
            permanent,
        } => ControllerAddress {
            name: None,
            ip_suite: Some([ip, mask, gateway.unwrap_or(Ipv4Addr::UNSPECIFIED)]),
            permanent,
        },
    };
    s.change_controller_address(&change, RECORD_TIMEOUT)
        .context("changing the controller's station")?;
    let now = s.control().status()?.controller.context("no controller")?;
    println!(
        "the controller's station is \"{}\" at {} (netmask {}, gateway {})",
        now.station_name, now.ip, now.netmask, now.gateway
    );
    Ok(())
}
