// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the callbacks receive, built from the server's notifications, its diagnosis and the
//! layout: PNIO_ERR_STAT, PNIO_CTRL_ALARM_DATA, and the answers of `PNIO_ctrl_diag_req`.
//!
//! Numbering: IO-Base names a device by its station number, which STEP 7 gives from 1 (0 is
//! the controller). procimg has no such number, so a device's station number is its index in
//! the layout + 1, the same in `PNIO_CTRL_ALARM_DATA::DeviceNum`, in
//! `PNIO_ALARM_TINFO::CompatDevGeoaddr` and in `PNIO_CTRL_DIAG_CONFIG_SUBMODULE::StatNo`.

use super::address;
use crate::iobase::types::{
    PNIO_ADDR, PNIO_ALARM_DEV_FAILURE, PNIO_ALARM_DEV_RETURN, PNIO_ALARM_INFO, PNIO_ALARM_INFO_u,
    PNIO_ALARM_TINFO, PNIO_APRIO_HIGH, PNIO_APRIO_LOW, PNIO_COM_UNICAST, PNIO_CTRL_ALARM_DATA,
    PNIO_CTRL_COMM_COUNTER_DATA, PNIO_CTRL_COMM_PORT_COUNTER_DATA, PNIO_CTRL_DEV_DIAG_ADDR_INFO_OK,
    PNIO_CTRL_DEV_DIAG_AR_CONNECTING, PNIO_CTRL_DEV_DIAG_AR_IN_DATA, PNIO_CTRL_DEV_DIAG_AR_OFFLINE,
    PNIO_CTRL_DEV_DIAG_OFFLINE, PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA,
    PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE, PNIO_CTRL_DIAG_CONFIG_SUBMODULE, PNIO_CTRL_DIAG_DEVICE,
    PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA, PNIO_CTRL_REASON_IOC_ABORTED,
    PNIO_CTRL_REASON_IOD_ABORTED, PNIO_CTRL_REASON_IOD_NOT_FOUND, PNIO_CTRL_REASON_IP_SET_ABORTED,
    PNIO_CTRL_REASON_MISS, PNIO_CTRL_REASON_MP_DEVICE_DISABLED, PNIO_CTRL_REASON_NONE,
    PNIO_CTRL_REASON_PNIO_CONFIGURATION, PNIO_CTRL_REASON_RPC_ERROR, PNIO_CTRL_REASON_RPC_TIMEOUT,
    PNIO_DA_FALSE, PNIO_DA_TRUE, PNIO_DATA_IRT, PNIO_DATA_RT, PNIO_ERR_STAT, PNIO_IO_IN,
    PNIO_IO_OUT, PNIO_MAX_ALARM_DATA_LEN,
};
use procimg_client::{
    AlarmReport, ControllerReport, DeviceDiagnosis, DeviceState, FailureCause, Layout, RecordStatus,
};

use procimg_shm_layout::{CYCLE_COUNT_UNIT_NS, NO_ADDRESS, RT_CLASS_3};

/// BlockType of an AlarmNotification: high priority.
const BLOCK_ALARM_HIGH: u16 = 0x0001;
/// BlockType of an AlarmNotification: low priority.
const BLOCK_ALARM_LOW: u16 = 0x0002;
/// BlockVersion of an AlarmNotification (1.0).
const BLOCK_VERSION: u16 = 0x0100;

/// The status IO-Base reports when a record job could not reach the device: no connection,
/// or it broke during the job (0xC0, 0x80, 0xA3, 0).
pub(crate) const NO_CONNECTION: PNIO_ERR_STAT = PNIO_ERR_STAT {
    ErrCode: 0xC0,
    ErrDecode: 0x80,
    ErrCode1: 0xA3,
    ErrCode2: 0,
    AddValue1: 0,
    AddValue2: 0,
};

/// The station number of device `device` (see the module documentation).
pub(crate) fn station_number(device: u32) -> u16 {
    u16::try_from(device.saturating_add(1)).unwrap_or(u16::MAX)
}

/// A record job's status as IO-Base reports it. A failure without a PNIOStatus of its own
/// (ErrorCode 0 although the job failed) is reported as [`NO_CONNECTION`].
pub(crate) fn err_stat(s: &RecordStatus, failed: bool) -> PNIO_ERR_STAT {
    if failed && s.error_code == 0 {
        return NO_CONNECTION;
    }
    PNIO_ERR_STAT {
        ErrCode: s.error_code,
        ErrDecode: s.error_decode,
        ErrCode1: s.error_code1,
        ErrCode2: s.error_code2,
        AddValue1: s.add_value1,
        AddValue2: s.add_value2,
    }
}

fn empty_alarm_info() -> PNIO_ALARM_INFO {
    PNIO_ALARM_INFO {
        BlockType: 0,
        BlockVersion: 0,
        Api: 0,
        AlarmSpecifier: 0,
        ModIdent: 0,
        SubIdent: 0,
        UserStrucIdent: 0,
        UserAlarmDataLen: 0,
        UAData: PNIO_ALARM_INFO_u {
            UserAlarmData: [0; PNIO_MAX_ALARM_DATA_LEN as usize],
        },
    }
}

/// The configuration details of an alarm of device `device`.
fn tinfo(layout: &Layout, device: u32) -> PNIO_ALARM_TINFO {
    let d = layout.devices.get(device as usize);
    PNIO_ALARM_TINFO {
        // Bits 0-10 the device number, 11-14 the IO subsystem (0: procimg has one), 15: PNIO.
        CompatDevGeoaddr: (station_number(device) & 0x07FF) | 0x8000,
        // PNIO profile, transparent alarm info.
        ProfileType: 0x08,
        AinfoType: 0,
        ControllerFlags: 0,
        DeviceFlag: 0,
        PnioVendorIdent: d.map_or(0, |d| d.vendor_id),
        PnioDevIdent: d.map_or(0, |d| d.device_id),
        PnioDevInstance: d.map_or(0, |d| d.instance),
    }
}

/// An alarm from a device, with the address it is reported at (the module's).
pub(crate) fn alarm(layout: &Layout, a: &AlarmReport) -> (PNIO_ADDR, Box<PNIO_CTRL_ALARM_DATA>) {
    let data = alarm_data(a, station_number(a.device), tinfo(layout, a.device));
    let addr = address::module_address(layout, a.device, a.api, a.slot, a.subslot);
    (addr, Box::new(data))
}

/// An alarm of the controller's own interface (`PNIO_CBE_IFC_ALARM_IND`): station number 0,
/// no device of the IO system behind it.
pub(crate) fn interface_alarm(a: &AlarmReport) -> Box<PNIO_CTRL_ALARM_DATA> {
    Box::new(alarm_data(a, 0, PNIO_ALARM_TINFO::default()))
}

/// The alarm data of `a`, for station `station` described by `tinfo`.
fn alarm_data(a: &AlarmReport, station: u16, tinfo: PNIO_ALARM_TINFO) -> PNIO_CTRL_ALARM_DATA {
    let mut info = empty_alarm_info();
    info.BlockType = if a.high_priority {
        BLOCK_ALARM_HIGH
    } else {
        BLOCK_ALARM_LOW
    };
    info.BlockVersion = BLOCK_VERSION;
    info.Api = a.api;
    info.AlarmSpecifier = a.specifier;
    info.ModIdent = a.module_ident;
    info.SubIdent = a.submodule_ident;
    if let Some(usi) = a.usi() {
        info.UserStrucIdent = usi;
        let user = a.payload.get(2..).unwrap_or_default();
        let n = user.len().min(PNIO_MAX_ALARM_DATA_LEN as usize);
        // SAFETY: writing into a union field of plain bytes: every bit pattern is valid.
        unsafe { info.UAData.UserAlarmData[..n].copy_from_slice(&user[..n]) };
        info.UserAlarmDataLen = n as u16;
    }
    PNIO_CTRL_ALARM_DATA {
        AlarmType: u32::from(a.alarm_type),
        AlarmPriority: if a.high_priority {
            PNIO_APRIO_HIGH
        } else {
            PNIO_APRIO_LOW
        },
        DeviceNum: station,
        SlotNum: a.slot,
        SubslotNum: a.subslot,
        CpuAlarmPriority: 0,
        PnioCompatModtype: 0,
        AlarmTinfo: tinfo,
        DiagDs: [0; 4],
        PrAlarmInfo: [0; 4],
        AlarmAinfo: info,
    }
}

/// The station failure (`failure`) or return alarm IO-Base makes of a device leaving or
/// entering data exchange, reported at the device's address.
pub(crate) fn station_alarm(
    layout: &Layout,
    device: u32,
    failure: bool,
) -> (PNIO_ADDR, Box<PNIO_CTRL_ALARM_DATA>) {
    let data = PNIO_CTRL_ALARM_DATA {
        AlarmType: if failure {
            PNIO_ALARM_DEV_FAILURE
        } else {
            PNIO_ALARM_DEV_RETURN
        },
        AlarmPriority: PNIO_APRIO_HIGH,
        DeviceNum: station_number(device),
        SlotNum: 0,
        SubslotNum: 0,
        CpuAlarmPriority: 0,
        PnioCompatModtype: 0,
        AlarmTinfo: tinfo(layout, device),
        DiagDs: [0; 4],
        PrAlarmInfo: [0; 4],
        // "Only relevant if not device failure/return alarm": left empty.
        AlarmAinfo: empty_alarm_info(),
    };
    (address::device_address(layout, device), Box::new(data))
}

/// The CONFIG_SUBMODULE_LIST answer: one element per data direction of every submodule
/// with data, in layout order (inputs before outputs of the same submodule).
pub(crate) fn submodule_list(layout: &Layout) -> Vec<PNIO_CTRL_DIAG_CONFIG_SUBMODULE> {
    let cycle = u32::try_from(layout.header.cycle_ns / CYCLE_COUNT_UNIT_NS).unwrap_or(u32::MAX);
    let mut list = Vec::new();
    for e in &layout.submodules {
        let reduction = layout
            .devices
            .get(usize::from(e.device))
            .map_or(1, |d| u32::from(d.reduction_ratio.max(1)));
        let element = |io, address, length: u16| PNIO_CTRL_DIAG_CONFIG_SUBMODULE {
            Address: PNIO_ADDR::logical(io, address),
            DataLength: u32::from(length),
            DataType: if e.rt_class == RT_CLASS_3 {
                PNIO_DATA_IRT
            } else {
                PNIO_DATA_RT
            },
            ComType: PNIO_COM_UNICAST,
            Api: e.api,
            ReductionFactor: reduction,
            // procimg sends every device's frames in the first cycle of its reduction
            // ratio (PROFINET phase 1, IO-Base phase 0).
            Phase: 0,
            CycleTime: cycle,
            Reserved1: [0; 2],
            StatNo: u32::from(station_number(u32::from(e.device))),
            Slot: u32::from(e.slot),
            Subslot: u32::from(e.subslot),
            Reserved2: [0; 2],
        };
        if e.input_length > 0 && e.input_address != NO_ADDRESS {
            list.push(element(PNIO_IO_IN, e.input_address, e.input_length));
        }
        if e.output_length > 0 && e.output_address != NO_ADDRESS {
            list.push(element(PNIO_IO_OUT, e.output_address, e.output_length));
        }
        // "Input length 0 ⇒ diagnostic address".
        if let Some(a) = e.diagnostic_address() {
            list.push(element(PNIO_IO_IN, a, 0));
        }
    }
    list
}

/// The CONFIG_OUTPUT_SLICE_LIST answer: procimg has no IO router, so every output bit of
/// every output submodule is this program's to write.
pub(crate) fn output_slices(layout: &Layout) -> Vec<PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE> {
    layout
        .submodules
        .iter()
        .filter(|e| e.output_length > 0 && e.output_address != NO_ADDRESS)
        .map(|e| PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE {
            Address: PNIO_ADDR::logical(PNIO_IO_OUT, e.output_address),
            BitOffset: 0,
            BitLength: e.output_length.saturating_mul(8),
        })
        .collect()
}

/// The `PNIO_CTRL_REASON_*` of a kind of failure the server reports.
fn reason(cause: FailureCause) -> u32 {
    match cause {
        FailureCause::None | FailureCause::Unknown => PNIO_CTRL_REASON_NONE,
        FailureCause::NotFound => PNIO_CTRL_REASON_IOD_NOT_FOUND,
        FailureCause::IpSetFailed => PNIO_CTRL_REASON_IP_SET_ABORTED,
        FailureCause::RpcTimeout | FailureCause::NoApplicationReady => PNIO_CTRL_REASON_RPC_TIMEOUT,
        FailureCause::RpcError => PNIO_CTRL_REASON_RPC_ERROR,
        FailureCause::Refused | FailureCause::Internal => PNIO_CTRL_REASON_PNIO_CONFIGURATION,
        FailureCause::NoCyclicData => PNIO_CTRL_REASON_MISS,
        FailureCause::DeviceAborted => PNIO_CTRL_REASON_IOD_ABORTED,
        FailureCause::ControllerAborted | FailureCause::Released => PNIO_CTRL_REASON_IOC_ABORTED,
        FailureCause::Deactivated => PNIO_CTRL_REASON_MP_DEVICE_DISABLED,
    }
}

/// The DEVICE_STATE answer for a device as the server's diagnosis reports it.
pub(crate) fn device_state(d: &DeviceDiagnosis) -> PNIO_CTRL_DIAG_DEVICE {
    let (state, why) = match d.state {
        DeviceState::Running => (
            PNIO_CTRL_DEV_DIAG_ADDR_INFO_OK | PNIO_CTRL_DEV_DIAG_AR_IN_DATA,
            PNIO_CTRL_REASON_NONE,
        ),
        DeviceState::Connecting
        | DeviceState::Parameterizing
        | DeviceState::WaitingForApplicationReady => (
            PNIO_CTRL_DEV_DIAG_ADDR_INFO_OK | PNIO_CTRL_DEV_DIAG_AR_CONNECTING,
            PNIO_CTRL_REASON_NONE,
        ),
        // Found by name, its address being set.
        DeviceState::SettingIp => (PNIO_CTRL_DEV_DIAG_AR_CONNECTING, PNIO_CTRL_REASON_NONE),
        // Looked for again after a failure: not reachable, for the reason of the failure.
        DeviceState::Searching if d.cause != FailureCause::None => (
            PNIO_CTRL_DEV_DIAG_OFFLINE | PNIO_CTRL_DEV_DIAG_AR_OFFLINE,
            reason(d.cause),
        ),
        DeviceState::Searching => (PNIO_CTRL_DEV_DIAG_AR_CONNECTING, PNIO_CTRL_REASON_NONE),
        DeviceState::Failed => (PNIO_CTRL_DEV_DIAG_AR_OFFLINE, reason(d.cause)),
        DeviceState::Deactivated => (
            PNIO_CTRL_DEV_DIAG_AR_OFFLINE,
            PNIO_CTRL_REASON_MP_DEVICE_DISABLED,
        ),
        // The controller is OFFLINE, or a newer server reports a state this library does
        // not know: not reachable, for no reason it could name.
        DeviceState::Offline | DeviceState::Unknown => {
            (PNIO_CTRL_DEV_DIAG_AR_OFFLINE, PNIO_CTRL_REASON_NONE)
        }
    };
    PNIO_CTRL_DIAG_DEVICE {
        Mode: if d.active {
            PNIO_DA_TRUE
        } else {
            PNIO_DA_FALSE
        },
        DiagState: state,
        Reason: why,
        Reserved1: [0; 12],
    }
}

/// An address as IO-Base's structures hold it: `struct in_addr`'s `s_addr`, network byte
/// order in memory; 0 for text that is not an address.
pub(crate) fn in_addr(text: &str) -> u32 {
    text.parse::<std::net::Ipv4Addr>()
        .map_or(0, |ip| u32::from_ne_bytes(ip.octets()))
}

/// `text` NUL-terminated in `buf`, cut to fit.
pub(crate) fn c_string(buf: &mut [u8], text: &str) {
    let n = text.len().min(buf.len() - 1);
    buf[..n].copy_from_slice(&text.as_bytes()[..n]);
    buf[n..].fill(0);
}

/// CONFIG_NAME_ADDR_INFO: the controller's station name, type and address.
pub(crate) fn name_addr_info(c: &ControllerReport) -> PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA {
    let mut d = PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA {
        name: [0; 256],
        TypeOfStation: [0; 256],
        ip_addr: in_addr(&c.ip),
        ip_mask: in_addr(&c.netmask),
        default_router: in_addr(&c.gateway),
    };
    c_string(&mut d.name, &c.station_name);
    c_string(&mut d.TypeOfStation, &c.type_of_station);
    d
}

/// GET/RESET_COMM_COUNTERS: the interface's counters as its one port's (IO-Base counts 32
/// bits, which wrap); no port on the simulated network.
pub(crate) fn comm_counters(c: &ControllerReport) -> PNIO_CTRL_COMM_COUNTER_DATA {
    let mut d = PNIO_CTRL_COMM_COUNTER_DATA::default();
    if let Some(n) = c.counters {
        let low = |v: u64| v as u32;
        d.Port[0] = PNIO_CTRL_COMM_PORT_COUNTER_DATA {
            SndNoError: low(n.frames_sent.saturating_sub(n.send_errors)),
            SndCollision: low(n.send_collisions),
            SndOtherError: low(n.send_errors),
            RcvNoError: low(n.frames_received),
            RcvResError: low(n.receive_errors),
            RcvRejected: low(n.received_dropped),
        };
        d.NumberOfPorts = 1;
    }
    d
}

/// The DEVICE_DIAGNOSTIC answer, of the device's last failure (all 0 but Mode while it runs):
/// * ErrorCause: the CM error cause, the low byte of the failure's `PNIO_CTRL_REASON_*`
///   (0x07xx) + 1, 0 without one; big-endian in memory, as PN Driver gives it;
/// * ReasonCode: the abort reason of an AR ended by an ERR-RTA of either side (ErrorCode2 of
///   its `CF 81 FD xx` status), else 0;
/// * AdditionalInfo\[0..4\]: the failure's PNIO status (ErrorCode, ErrorDecode, ErrorCode1,
///   ErrorCode2) when it has one (a refusal's, an abort's), the rest 0.
pub(crate) fn device_diagnostic(d: &DeviceDiagnosis) -> PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA {
    let mut info = [0u8; 10];
    if let Some(st) = d.pnio_status {
        info[..4].copy_from_slice(&st);
    }
    PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA {
        Mode: if d.active {
            PNIO_DA_TRUE
        } else {
            PNIO_DA_FALSE
        },
        // Big-endian in memory, as PN Driver gives it.
        ErrorCause: error_cause(reason(d.cause)).to_be(),
        ReasonCode: abort_reason(d.pnio_status),
        AdditionalInfo: info,
    }
}

/// The CM error cause of a `PNIO_CTRL_REASON_*` of the 0x07xx range: its low byte + 1
/// (0x0700 MULTIPLE_IP_USE is 1, … 0x070D IOD_ABORTED is 14); 0 for the others (NONE).
fn error_cause(reason: u32) -> u16 {
    if reason & 0xFF00 == 0x0700 {
        (reason & 0xFF) as u16 + 1
    } else {
        0
    }
}

/// The abort reason of an AR ended by an ERR-RTA (ErrorCode2 of `CF 81 FD xx`), else 0.
fn abort_reason(status: Option<[u8; 4]>) -> u8 {
    match status {
        Some([0xCF, 0x81, 0xFD, code]) => code,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::iobase::services::address::tests::demo_layout;

    #[test]
    fn the_controllers_station_and_counters() {
        let mut c = ControllerReport {
            station_name: "procimgd-plant".into(),
            type_of_station: "procimg controller".into(),
            interface: "eth1".into(),
            mac: "02:00:00:00:00:01".into(),
            ip: "10.0.0.1".into(),
            netmask: "255.255.0.0".into(),
            gateway: "0.0.0.0".into(),
            ..ControllerReport::default()
        };
        let na = name_addr_info(&c);
        assert_eq!(&na.name[..15], b"procimgd-plant\0");
        assert_eq!(na.ip_addr.to_ne_bytes(), [10, 0, 0, 1]);
        assert_eq!(na.ip_mask.to_ne_bytes(), [255, 255, 0, 0]);
        assert_eq!(comm_counters(&c).NumberOfPorts, 0);
        c.counters = Some(procimg_client::InterfaceCounters {
            frames_sent: 100,
            send_collisions: 1,
            send_errors: 2,
            frames_received: 90,
            receive_errors: 3,
            received_dropped: 4,
        });
        let cc = comm_counters(&c);
        assert_eq!(cc.NumberOfPorts, 1);
        assert_eq!(
            (
                cc.Port[0].SndNoError,
                cc.Port[0].SndOtherError,
                cc.Port[0].RcvRejected
            ),
            (98, 2, 4)
        );
    }

    fn diagnosis(state: DeviceState, active: bool, cause: FailureCause) -> DeviceDiagnosis {
        DeviceDiagnosis {
            device: 2,
            name: "dio".into(),
            state,
            active,
            last_error: String::new(),
            cause,
            failures: 0,
            module_diff: Vec::new(),
            pnio_status: None,
        }
    }

    #[test]
    fn record_status_passes_through_and_a_bare_failure_means_no_connection() {
        let s = RecordStatus {
            error_code: 0xDE,
            error_decode: 0x80,
            error_code1: 0xB0,
            error_code2: 0,
            add_value1: 0,
            add_value2: 0,
        };
        let e = err_stat(&s, true);
        assert_eq!((e.ErrCode, e.ErrDecode, e.ErrCode1), (0xDE, 0x80, 0xB0));
        let more = RecordStatus {
            add_value1: 1,
            ..RecordStatus::OK
        };
        assert_eq!(err_stat(&more, false).AddValue1, 1);
        assert_eq!(err_stat(&RecordStatus::OK, true), NO_CONNECTION);
        assert_eq!(err_stat(&RecordStatus::OK, false), PNIO_ERR_STAT::default());
    }

    #[test]
    fn a_process_alarm_carries_its_module_address_and_user_data() {
        let l = demo_layout();
        let report = AlarmReport {
            id: 7,
            device: 0,
            device_name: "echo".into(),
            high_priority: true,
            alarm_type: 2,
            api: 0,
            slot: 1,
            subslot: 1,
            module_ident: 0x20,
            submodule_ident: 1,
            specifier: 0x0801,
            payload: vec![0x00, 0x01, 0xab, 0xcd],
            text: String::new(),
        };
        let (addr, a) = alarm(&l, &report);
        assert_eq!((addr.IODataType, addr.addr()), (PNIO_IO_IN, 0));
        assert_eq!((a.AlarmType, a.AlarmPriority), (2, PNIO_APRIO_HIGH));
        assert_eq!((a.DeviceNum, a.SlotNum, a.SubslotNum), (1, 1, 1));
        let i = &a.AlarmAinfo;
        assert_eq!((i.BlockType, i.BlockVersion), (0x0001, 0x0100));
        assert_eq!(
            (i.ModIdent, i.SubIdent, i.AlarmSpecifier),
            (0x20, 1, 0x0801)
        );
        assert_eq!((i.UserStrucIdent, i.UserAlarmDataLen), (1, 2));
        // SAFETY: reading a union of plain bytes.
        assert_eq!(unsafe { &i.UAData.UserAlarmData[..2] }, [0xab, 0xcd]);
        assert_eq!(a.AlarmTinfo.PnioVendorIdent, 0x0493);
        assert_eq!(a.AlarmTinfo.CompatDevGeoaddr, 0x8001);
    }

    #[test]
    fn too_much_user_data_is_cut_to_what_the_struct_holds() {
        let l = demo_layout();
        let report = AlarmReport {
            id: 1,
            device: 1,
            device_name: "counter".into(),
            high_priority: false,
            alarm_type: 1,
            api: 0,
            slot: 1,
            subslot: 1,
            module_ident: 0x30,
            submodule_ident: 1,
            specifier: 0,
            payload: vec![0x80; 2 + 2000],
            text: String::new(),
        };
        let (_, a) = alarm(&l, &report);
        assert_eq!(a.AlarmAinfo.UserAlarmDataLen, 1472);
        assert_eq!(a.AlarmPriority, PNIO_APRIO_LOW);
        assert_eq!(a.AlarmAinfo.BlockType, 0x0002);
    }

    #[test]
    fn station_failure_and_return_name_the_device() {
        let l = demo_layout();
        // The DAP's diagnostic address.
        let (addr, a) = station_alarm(&l, 2, true);
        assert_eq!((addr.IODataType, addr.addr()), (PNIO_IO_IN, 24));
        assert_eq!((a.AlarmType, a.DeviceNum), (PNIO_ALARM_DEV_FAILURE, 3));
        let (_, a) = station_alarm(&l, 2, false);
        assert_eq!(a.AlarmType, PNIO_ALARM_DEV_RETURN);
    }

    #[test]
    fn the_submodule_list_has_one_element_per_direction_and_diagnostic_address() {
        let l = demo_layout();
        let list = submodule_list(&l);
        let seen: Vec<(u32, u32, u32, u32)> = list
            .iter()
            .map(|e| {
                (
                    e.Address.IODataType,
                    e.Address.addr(),
                    e.DataLength,
                    e.StatNo,
                )
            })
            .collect();
        assert_eq!(
            seen,
            [
                (PNIO_IO_IN, 22, 0, 1),
                (PNIO_IO_IN, 0, 16, 1),
                (PNIO_IO_OUT, 0, 16, 1),
                (PNIO_IO_IN, 23, 0, 2),
                (PNIO_IO_IN, 16, 4, 2),
                (PNIO_IO_IN, 24, 0, 3),
                (PNIO_IO_IN, 20, 2, 3),
                (PNIO_IO_OUT, 16, 2, 3),
            ]
        );
        assert!(list.iter().all(|e| e.CycleTime == 32
            && e.ReductionFactor == 1
            && e.Phase == 0
            && e.ComType == PNIO_COM_UNICAST));
        // The echo's data is IRT (RT class 3), the others' RT.
        let types: Vec<u32> = list.iter().map(|e| e.DataType).collect();
        assert_eq!(
            types,
            [
                PNIO_DATA_RT,
                PNIO_DATA_IRT,
                PNIO_DATA_IRT,
                PNIO_DATA_RT,
                PNIO_DATA_RT,
                PNIO_DATA_RT,
                PNIO_DATA_RT,
                PNIO_DATA_RT
            ]
        );
        let slices = output_slices(&l);
        assert_eq!(slices.len(), 2);
        assert_eq!((slices[1].Address.addr(), slices[1].BitLength), (16, 16));
    }

    #[test]
    fn device_states_map_to_the_diag_bits() {
        let s = device_state(&diagnosis(DeviceState::Running, true, FailureCause::None));
        assert_eq!(s.Mode, PNIO_DA_TRUE);
        assert_ne!(s.DiagState & PNIO_CTRL_DEV_DIAG_AR_IN_DATA, 0);
        assert_eq!(s.Reason, PNIO_CTRL_REASON_NONE);
        let s = device_state(&diagnosis(
            DeviceState::Deactivated,
            false,
            FailureCause::Deactivated,
        ));
        assert_eq!(
            (s.Mode, s.DiagState, s.Reason),
            (
                PNIO_DA_FALSE,
                PNIO_CTRL_DEV_DIAG_AR_OFFLINE,
                PNIO_CTRL_REASON_MP_DEVICE_DISABLED
            )
        );
        let s = device_state(&diagnosis(
            DeviceState::Parameterizing,
            true,
            FailureCause::None,
        ));
        assert_ne!(s.DiagState & PNIO_CTRL_DEV_DIAG_AR_CONNECTING, 0);
        let s = device_state(&diagnosis(
            DeviceState::Searching,
            true,
            FailureCause::NotFound,
        ));
        assert_ne!(s.DiagState & PNIO_CTRL_DEV_DIAG_OFFLINE, 0);
        assert_eq!(s.Reason, PNIO_CTRL_REASON_IOD_NOT_FOUND);
        let s = device_state(&diagnosis(
            DeviceState::Failed,
            true,
            FailureCause::NoCyclicData,
        ));
        assert_eq!(
            (s.DiagState, s.Reason),
            (PNIO_CTRL_DEV_DIAG_AR_OFFLINE, PNIO_CTRL_REASON_MISS)
        );
        for (cause, want) in [
            (FailureCause::DeviceAborted, PNIO_CTRL_REASON_IOD_ABORTED),
            (
                FailureCause::ControllerAborted,
                PNIO_CTRL_REASON_IOC_ABORTED,
            ),
            (FailureCause::Refused, PNIO_CTRL_REASON_PNIO_CONFIGURATION),
            (FailureCause::RpcTimeout, PNIO_CTRL_REASON_RPC_TIMEOUT),
            (FailureCause::RpcError, PNIO_CTRL_REASON_RPC_ERROR),
            (FailureCause::IpSetFailed, PNIO_CTRL_REASON_IP_SET_ABORTED),
        ] {
            assert_eq!(
                device_state(&diagnosis(DeviceState::Failed, true, cause)).Reason,
                want
            );
        }
        assert_eq!(
            device_diagnostic(&diagnosis(DeviceState::Failed, false, FailureCause::None)).Mode,
            PNIO_DA_FALSE
        );
    }

    #[test]
    fn a_state_only_a_newer_server_knows_reads_as_offline_without_a_reason() {
        let s = device_state(&diagnosis(DeviceState::Unknown, true, FailureCause::None));
        assert_eq!(
            (s.Mode, s.DiagState, s.Reason),
            (
                PNIO_DA_TRUE,
                PNIO_CTRL_DEV_DIAG_AR_OFFLINE,
                PNIO_CTRL_REASON_NONE
            )
        );
    }

    #[test]
    fn device_diagnostic_tells_the_cause_the_abort_reason_and_the_status() {
        let with = |cause, status| DeviceDiagnosis {
            pnio_status: status,
            ..diagnosis(DeviceState::Failed, true, cause)
        };
        let info = |st: [u8; 4]| {
            let mut a = [0u8; 10];
            a[..4].copy_from_slice(&st);
            a
        };
        // Running: nothing but the mode.
        let d = device_diagnostic(&diagnosis(DeviceState::Running, true, FailureCause::None));
        assert_eq!(
            d,
            PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA {
                Mode: PNIO_DA_TRUE,
                ..Default::default()
            }
        );
        // procimgd's watchdog expired: MISS (0x070A, cause 11), it aborted with 0x05.
        let d = device_diagnostic(&with(
            FailureCause::NoCyclicData,
            Some([0xCF, 0x81, 0xFD, 0x05]),
        ));
        assert_eq!(u16::from_be(d.ErrorCause), 11);
        assert_eq!(d.ErrorCause.to_ne_bytes(), [0, 11], "big-endian in memory");
        assert_eq!(d.ReasonCode, 0x05);
        assert_eq!(d.AdditionalInfo, info([0xCF, 0x81, 0xFD, 0x05]));
        // The device aborted (IOD_ABORTED 0x070D, cause 14) with its own code.
        let d = device_diagnostic(&with(
            FailureCause::DeviceAborted,
            Some([0xCF, 0x81, 0xFD, 0x1B]),
        ));
        assert_eq!((u16::from_be(d.ErrorCause), d.ReasonCode), (14, 0x1B));
        // A refused Connect (PNIO_CONFIGURATION 0x0705, cause 6): no abort reason, its status.
        let d = device_diagnostic(&with(FailureCause::Refused, Some([0xDB, 0x81, 0x3F, 0x04])));
        assert_eq!((u16::from_be(d.ErrorCause), d.ReasonCode), (6, 0));
        assert_eq!(d.AdditionalInfo, info([0xDB, 0x81, 0x3F, 0x04]));
        // Not found (IOD_NOT_FOUND 0x0708, cause 9), no answer (RPC_TIMEOUT 0x0706, cause
        // 7), the controller's abort (IOC_ABORTED 0x070C, cause 13): no status.
        for (cause, want) in [
            (FailureCause::NotFound, 9),
            (FailureCause::RpcTimeout, 7),
            (FailureCause::ControllerAborted, 13),
        ] {
            let d = device_diagnostic(&with(cause, None));
            assert_eq!(
                (u16::from_be(d.ErrorCause), d.ReasonCode, d.AdditionalInfo),
                (want, 0, [0; 10]),
                "{cause:?}"
            );
        }
        // The constants the rule is stated for.
        assert_eq!(error_cause(0x0700), 1);
        assert_eq!(error_cause(PNIO_CTRL_REASON_NONE), 0);
        assert_eq!(error_cause(0x0401), 0);
    }
}
