// SPDX-License-Identifier: MIT OR Apache-2.0
//! What a device tells about its ARs: ARData (block 0x0018 v1.1, record 0xF820), APIData
//! (0x001A, record 0xF821) and LogBookData (0x0019, record 0xF830).
//!
//! ```text
//! ARData v1.1   NumberOfARs (ARUUID CMInitiatorObjectUUID ParameterServerObjectUUID ARProperties
//!               ARType AlarmCRType LocalAlarmReference RemoteAlarmReference InitiatorUDPRTPort
//!               ResponderUDPRTPort StationNameLength CMInitiatorStationName pad
//!               StationNameLength ParameterServerStationName pad
//!               NumberOfIOCRs pad(2) (IOCRProperties IOCRType FrameID CycleCounter DataStatus
//!               TransferStatus)* NumberOfAPIs pad(2) API* NumberOfARDataInfo pad(2))*
//! APIData       NumberOfAPIs API*
//! LogBookData   ActualLocalTimeStamp NumberOfLogEntries (LocalTimeStamp ARUUID PNIOStatus EntryDetail)*
//! ```
//!
//! ARData's padding aligns on the block's start (it starts aligned in a record), so an AR's
//! entry ends aligned. No ARDataInfo blocks are written: they describe isochronous, system
//! redundancy and fast start-up features this device does not have.

use super::super::cursor::{Reader, Writer};
use super::pdev::align4;
use super::{BlockHeader, BlockType, EmitResult, Error, Result, emit_block};
use crate::wire::{PnioStatus, Uuid};

/// Record index of ARData (all the device's ARs).
pub const INDEX_AR_DATA: u16 = 0xf820;
/// Record index of APIData.
pub const INDEX_API_DATA: u16 = 0xf821;
/// Record index of LogBookData.
pub const INDEX_LOG_BOOK_DATA: u16 = 0xf830;

/// An IOCR of an AR as ARData reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ArDataIocr {
    /// IOCRProperties (bits 0–3 the RT class).
    pub properties: u32,
    /// IOCRType (1 input, 2 output).
    pub iocr_type: u16,
    /// FrameID.
    pub frame_id: u16,
    /// APDU status: the CycleCounter of the last frame (sent or received).
    pub cycle_counter: u16,
    /// APDU status: its DataStatus.
    pub data_status: u8,
    /// APDU status: its TransferStatus.
    pub transfer_status: u8,
}

/// One AR as ARData reports it.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ArDataEntry {
    /// ARUUID.
    pub ar_uuid: Uuid,
    /// CMInitiatorObjectUUID.
    pub initiator_object_uuid: Uuid,
    /// ParameterServerObjectUUID (nil: none).
    pub parameter_server_object_uuid: Uuid,
    /// ARProperties.
    pub ar_properties: u32,
    /// ARType.
    pub ar_type: u16,
    /// AlarmCRType (0: the AR has no alarm CR).
    pub alarm_cr_type: u16,
    /// LocalAlarmReference.
    pub local_alarm_reference: u16,
    /// RemoteAlarmReference.
    pub remote_alarm_reference: u16,
    /// InitiatorUDPRTPort.
    pub initiator_udp_rt_port: u16,
    /// ResponderUDPRTPort.
    pub responder_udp_rt_port: u16,
    /// CMInitiatorStationName.
    pub initiator_station_name: String,
    /// ParameterServerStationName (empty: none).
    pub parameter_server_station_name: String,
    /// The IOCRs.
    pub iocrs: Vec<ArDataIocr>,
    /// The APIs of its submodules.
    pub apis: Vec<u32>,
}

impl ArDataEntry {
    fn len(&self) -> usize {
        let name = align4(66 + self.initiator_station_name.len());
        let server = align4(2 + self.parameter_server_station_name.len());
        name + server + 4 + 12 * self.iocrs.len() + 4 + 4 * self.apis.len() + 4
    }
}

/// ARData (version 1.1): the device's ARs.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct ArData {
    /// The ARs.
    pub ars: Vec<ArDataEntry>,
}

impl ArData {
    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        self.ars
            .iter()
            .fold(8usize, |n, a| n.saturating_add(a.len()))
    }

    /// Writes the block into the first [`buffer_len`](Self::buffer_len) bytes of `buf`.
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<usize> {
        let body = self.buffer_len() - 6;
        emit_block("ARData", BlockType::ArData, 1, body, buf, |w| {
            w.count("NumberOfARs", self.ars.len())?;
            for a in &self.ars {
                write_entry(w, a)?;
            }
            Ok(())
        })
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b).map(|_| ()))
    }

    /// Parses the block (version 1.1) at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<ArData> {
        let h = BlockHeader::parse(b)?;
        if h.block_type != BlockType::ArData || (h.version_high, h.version_low) != (1, 1) {
            return Err(Error);
        }
        let mut r = Reader::new(h.body(b));
        let ars = r.list(read_entry)?;
        r.end()?;
        Ok(ArData { ars })
    }
}

/// The u16 length and bytes of `s`, padded to 4 from `start` (the entry's aligned start
/// lies `before` bytes earlier).
fn padded_name(w: &mut Writer<'_>, field: &'static str, s: &str, before: usize) -> EmitResult<()> {
    w.string(field, s)?;
    let at = before + 2 + s.len();
    w.zeros(align4(at) - at)
}

fn write_entry(w: &mut Writer<'_>, a: &ArDataEntry) -> EmitResult<()> {
    w.put(&a.ar_uuid.0)?;
    w.put(&a.initiator_object_uuid.0)?;
    w.put(&a.parameter_server_object_uuid.0)?;
    w.u32(a.ar_properties)?;
    for v in [
        a.ar_type,
        a.alarm_cr_type,
        a.local_alarm_reference,
        a.remote_alarm_reference,
        a.initiator_udp_rt_port,
        a.responder_udp_rt_port,
    ] {
        w.u16(v)?;
    }
    // The entry starts 4-aligned (block offset 8, or after an aligned entry): the name
    // starts 64 bytes in.
    padded_name(w, "CMInitiatorStationName", &a.initiator_station_name, 64)?;
    padded_name(
        w,
        "ParameterServerStationName",
        &a.parameter_server_station_name,
        0,
    )?;
    w.count("NumberOfIOCRs", a.iocrs.len())?;
    w.zeros(2)?;
    for c in &a.iocrs {
        w.u32(c.properties)?;
        w.u16(c.iocr_type)?;
        w.u16(c.frame_id)?;
        w.u16(c.cycle_counter)?;
        w.u8(c.data_status)?;
        w.u8(c.transfer_status)?;
    }
    w.count("NumberOfAPIs", a.apis.len())?;
    w.zeros(2)?;
    for api in &a.apis {
        w.u32(*api)?;
    }
    // No ARDataInfo entries.
    w.u16(0)?;
    w.zeros(2)
}

fn read_name(r: &mut Reader<'_>, before: usize) -> Result<String> {
    let s = r.string()?;
    let at = before + 2 + s.len();
    r.take(align4(at) - at)?;
    Ok(s)
}

fn read_entry(r: &mut Reader<'_>) -> Result<ArDataEntry> {
    let ar_uuid = r.uuid()?;
    let initiator_object_uuid = r.uuid()?;
    let parameter_server_object_uuid = r.uuid()?;
    let ar_properties = r.u32()?;
    let mut v = [0u16; 6];
    for x in &mut v {
        *x = r.u16()?;
    }
    let initiator_station_name = read_name(r, 64)?;
    let parameter_server_station_name = read_name(r, 0)?;
    let n = r.u16()?;
    r.take(2)?;
    let mut iocrs = Vec::new();
    for _ in 0..n {
        iocrs.push(ArDataIocr {
            properties: r.u32()?,
            iocr_type: r.u16()?,
            frame_id: r.u16()?,
            cycle_counter: r.u16()?,
            data_status: r.u8()?,
            transfer_status: r.u8()?,
        });
    }
    let n = r.u16()?;
    r.take(2)?;
    let mut apis = Vec::new();
    for _ in 0..n {
        apis.push(r.u32()?);
    }
    // ARDataInfo blocks are not decoded: a reader of ours never meets any.
    if r.u16()? != 0 {
        return Err(Error);
    }
    r.take(2)?;
    Ok(ArDataEntry {
        ar_uuid,
        initiator_object_uuid,
        parameter_server_object_uuid,
        ar_properties,
        ar_type: v[0],
        alarm_cr_type: v[1],
        local_alarm_reference: v[2],
        remote_alarm_reference: v[3],
        initiator_udp_rt_port: v[4],
        responder_udp_rt_port: v[5],
        initiator_station_name,
        parameter_server_station_name,
        iocrs,
        apis,
    })
}

/// APIData: the APIs the device has submodules in.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct ApiData {
    /// The APIs.
    pub apis: Vec<u32>,
}

impl ApiData {
    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        8usize.saturating_add(self.apis.len().saturating_mul(4))
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        let body = self.buffer_len() - 6;
        crate::wire::emit_to_vec(self.buffer_len(), |b| {
            emit_block("APIData", BlockType::ApiData, 0, body, b, |w| {
                w.count("NumberOfAPIs", self.apis.len())?;
                self.apis.iter().try_for_each(|a| w.u32(*a))
            })
            .map(|_| ())
        })
    }

    /// Parses the block at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<ApiData> {
        let h = BlockHeader::parse(b)?;
        if h.block_type != BlockType::ApiData || (h.version_high, h.version_low) != (1, 0) {
            return Err(Error);
        }
        let mut r = Reader::new(h.body(b));
        let apis = r.list(|r| r.u32())?;
        r.end()?;
        Ok(ApiData { apis })
    }
}

/// An entry of the log book.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LogEntry {
    /// LocalTimeStamp: when it happened, in the device's clock (ns since it started).
    pub time_stamp: u64,
    /// The AR it concerns (nil: none).
    pub ar_uuid: Uuid,
    /// What happened, as a PNIOStatus (an AR's abort: its ERR-RTA reason).
    pub status: PnioStatus,
    /// EntryDetail: more about it (manufacturer-specific).
    pub detail: u32,
}

/// LogBookData: the device's log of what happened to its ARs.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct LogBookData {
    /// ActualLocalTimeStamp: the device's clock now, in the entries' unit.
    pub now: u64,
    /// The entries, oldest first.
    pub entries: Vec<LogEntry>,
}

impl LogBookData {
    /// Bytes of the block.
    pub fn buffer_len(&self) -> usize {
        16usize.saturating_add(self.entries.len().saturating_mul(32))
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        let body = self.buffer_len() - 6;
        crate::wire::emit_to_vec(self.buffer_len(), |b| {
            emit_block("LogBookData", BlockType::LogBookData, 0, body, b, |w| {
                w.put(&self.now.to_be_bytes())?;
                w.count("NumberOfLogEntries", self.entries.len())?;
                for e in &self.entries {
                    w.put(&e.time_stamp.to_be_bytes())?;
                    w.put(&e.ar_uuid.0)?;
                    w.put(&e.status.to_bytes())?;
                    w.u32(e.detail)?;
                }
                Ok(())
            })
            .map(|_| ())
        })
    }

    /// Parses the block at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<LogBookData> {
        let h = BlockHeader::parse(b)?;
        if h.block_type != BlockType::LogBookData || (h.version_high, h.version_low) != (1, 0) {
            return Err(Error);
        }
        let mut r = Reader::new(h.body(b));
        let now = u64::from_be_bytes(r.array()?);
        let entries = r.list(|r| {
            Ok(LogEntry {
                time_stamp: u64::from_be_bytes(r.array()?),
                ar_uuid: r.uuid()?,
                status: PnioStatus::from_bytes(r.array()?),
                detail: r.u32()?,
            })
        })?;
        r.end()?;
        Ok(LogBookData { now, entries })
    }
}

#[cfg(test)]
mod tests;
