// SPDX-License-Identifier: MIT OR Apache-2.0
//! A small station to show and test the MIB with: two ports, an IO device heard on port 1.

use std::net::Ipv4Addr;

use super::snapshot::{
    Capabilities, ChassisId, LldpView, LocalPort, LocalSystem, ManagementAddress, PnoPort, PortId,
    PortStatistics, RemoteSystem, RtClass2Status, RtClass3Status, Snapshot, Statistics,
};

/// The enterprise OID that p-net serves as sysObjectID for PROFINET (1.3.6.1.4.1.24686).
const PROFINET_ENTERPRISE: [u32; 7] = [1, 3, 6, 1, 4, 1, 24686];

impl Snapshot {
    /// An example station: `plc-station` at 192.168.0.50 with ports 1 and 2, the IO device
    /// `io-device-1` (192.168.0.60) its neighbour on port 1, and LLDP counters. The tests
    /// and the documentation use it; a real station fills a snapshot from its state.
    pub fn example() -> Snapshot {
        let station_only = Capabilities {
            supported: Capabilities::STATION_ONLY,
            enabled: Capabilities::STATION_ONLY,
        };
        let descr = "procimg PROFINET station, example";
        let port = |num: u32, pno: Option<PnoPort>| LocalPort {
            num,
            id: PortId::local(&format!("port-{num:03}")),
            description: format!("procimg port {num}"),
            pno,
        };
        Snapshot {
            sys_descr: descr.into(),
            sys_object_id: PROFINET_ENTERPRISE.to_vec(),
            sys_up_time_centis: 4242,
            sys_contact: "maintenance@example.invalid".into(),
            sys_name: "plc-station".into(),
            sys_location: "hall 3".into(),
            sys_services: 78,
            lldp: LldpView {
                local: LocalSystem {
                    chassis_id: ChassisId::local("plc-station"),
                    sys_name: "plc-station".into(),
                    sys_desc: descr.into(),
                    capabilities: station_only,
                },
                ports: vec![
                    port(
                        1,
                        Some(PnoPort {
                            line_delay_ns: 50,
                            tx_delay_ns: 100,
                            rx_delay_ns: 200,
                            rt_class2: RtClass2Status::Running,
                            rt_class3: RtClass3Status::Off,
                            name_of_station: "plc-station".into(),
                        }),
                    ),
                    port(2, None),
                ],
                management_addresses: vec![ManagementAddress {
                    object_id: PROFINET_ENTERPRISE.to_vec(),
                    ..ManagementAddress::on_if_index(Ipv4Addr::new(192, 168, 0, 50), 1)
                }],
                remotes: vec![RemoteSystem {
                    time_mark: 300,
                    local_port: 1,
                    index: 1,
                    chassis_id: ChassisId::local("io-device-1"),
                    port_id: PortId::local("port-001.io-device-1"),
                    port_description: Some("io-device-1 port 1".into()),
                    sys_name: Some("io-device-1".into()),
                    sys_desc: None,
                    capabilities: Some(station_only),
                    management_addresses: vec![ManagementAddress::on_if_index(
                        Ipv4Addr::new(192, 168, 0, 60),
                        1,
                    )],
                    pno: Some(PnoPort {
                        line_delay_ns: 50,
                        tx_delay_ns: 120,
                        rx_delay_ns: 240,
                        rt_class2: RtClass2Status::Running,
                        rt_class3: RtClass3Status::Off,
                        name_of_station: "io-device-1".into(),
                    }),
                }],
                statistics: Some(Statistics {
                    rem_tables_last_change: 300,
                    rem_tables_inserts: 1,
                    rem_tables_deletes: 0,
                    rem_tables_drops: 0,
                    rem_tables_ageouts: 0,
                    ports: vec![
                        PortStatistics {
                            num: 1,
                            tx_frames: 12,
                            rx_frames: 11,
                            ..PortStatistics::default()
                        },
                        PortStatistics {
                            num: 2,
                            tx_frames: 12,
                            ..PortStatistics::default()
                        },
                    ],
                }),
            },
        }
    }
}
