// SPDX-License-Identifier: MIT OR Apache-2.0
//! The payloads of the AgentX PDUs (RFC 2741 §6.2), after the header and the optional
//! context. Each layout is written above its type; `(n)` is a field's size in bytes.

use super::codec::{Reader, Writer, octets_len};
use super::{
    CloseReason, EmitError, Oid, ParseError, PduType, ResponseError, SearchRange, VarBind,
};

/// agentx-Open-PDU (§6.2.1): `o.timeout (1), reserved (3), o.id (OID), o.descr (octets)`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Open {
    /// Seconds the master waits for this subagent's answers; 0 leaves the master's
    /// default.
    pub timeout: u8,
    /// An OID naming the subagent; null when it has none.
    pub id: Oid,
    /// A text describing the subagent.
    pub description: Vec<u8>,
}

/// agentx-Close-PDU (§6.2.2): `c.reason (1), reserved (3)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Close {
    /// Why.
    pub reason: CloseReason,
}

/// agentx-Register-PDU (§6.2.3): `r.timeout (1), r.priority (1), r.range_subid (1),
/// reserved (1), r.subtree (OID), r.upper_bound (4, only when r.range_subid is not 0)`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Register {
    /// Seconds the master waits for answers in this subtree; 0 for the session's.
    pub timeout: u8,
    /// Lower values win over the same subtree registered by others (default 127).
    pub priority: u8,
    /// With `upper_bound`: the 1-based subidentifier of `subtree` that ranges up to
    /// `upper_bound`, registering several subtrees at once.
    pub range_subid: u8,
    /// The subtree (or instance, with INSTANCE_REGISTRATION).
    pub subtree: Oid,
    /// The last value of the ranging subidentifier; `Some` exactly when `range_subid` is
    /// not 0.
    pub upper_bound: Option<u32>,
}

/// agentx-Unregister-PDU (§6.2.4): `reserved (1), u.priority (1), u.range_subid (1),
/// reserved (1), u.subtree (OID), u.upper_bound (4, only when u.range_subid is not 0)`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Unregister {
    /// The priority it was registered with.
    pub priority: u8,
    /// As registered.
    pub range_subid: u8,
    /// As registered.
    pub subtree: Oid,
    /// As registered.
    pub upper_bound: Option<u32>,
}

/// agentx-GetBulk-PDU (§6.2.7): `g.non_repeaters (2), g.max_repetitions (2),
/// SearchRangeList`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct GetBulk {
    /// How many of the first ranges are searched once.
    pub non_repeaters: u16,
    /// How often the other ranges are searched on.
    pub max_repetitions: u16,
    /// The ranges.
    pub ranges: Vec<SearchRange>,
}

/// agentx-AddAgentCaps-PDU (§6.2.14): `a.id (OID), a.descr (octets)`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct AddAgentCaps {
    /// The capabilities' OID.
    pub id: Oid,
    /// Their description.
    pub description: Vec<u8>,
}

/// agentx-Response-PDU (§6.2.16): `res.sysUpTime (4), res.error (2), res.index (2),
/// VarBindList`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Response {
    /// The master's sysUpTime; a subagent sends 0 (the master ignores it).
    pub sys_up_time: u32,
    /// The outcome.
    pub error: ResponseError,
    /// The 1-based VarBind the error is about; 0 when none.
    pub index: u16,
    /// The values (for Get, GetNext, GetBulk).
    pub varbinds: Vec<VarBind>,
}

/// The payload of a PDU, by type.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Pdu {
    /// A subagent asks for a session.
    Open(Open),
    /// Either side ends the session.
    Close(Close),
    /// A subagent registers a subtree.
    Register(Register),
    /// A subagent withdraws one.
    Unregister(Unregister),
    /// agentx-Get-PDU (§6.2.5): SearchRangeList (each end null).
    Get(Vec<SearchRange>),
    /// agentx-GetNext-PDU (§6.2.6): SearchRangeList.
    GetNext(Vec<SearchRange>),
    /// The master asks for repeated next values.
    GetBulk(GetBulk),
    /// agentx-TestSet-PDU (§6.2.8): VarBindList.
    TestSet(Vec<VarBind>),
    /// agentx-CommitSet-PDU (§6.2.9): no payload.
    CommitSet,
    /// agentx-UndoSet-PDU (§6.2.9): no payload.
    UndoSet,
    /// agentx-CleanupSet-PDU (§6.2.9): no payload; never answered.
    CleanupSet,
    /// agentx-Notify-PDU (§6.2.10): VarBindList.
    Notify(Vec<VarBind>),
    /// agentx-Ping-PDU (§6.2.11): no payload.
    Ping,
    /// agentx-IndexAllocate-PDU (§6.2.12): VarBindList.
    IndexAllocate(Vec<VarBind>),
    /// agentx-IndexDeallocate-PDU (§6.2.13): VarBindList.
    IndexDeallocate(Vec<VarBind>),
    /// A subagent adds agent capabilities.
    AddAgentCaps(AddAgentCaps),
    /// agentx-RemoveAgentCaps-PDU (§6.2.15): `a.id (OID)`.
    RemoveAgentCaps(Oid),
    /// The answer.
    Response(Response),
}

impl Pdu {
    /// h.type of this payload.
    pub const fn pdu_type(&self) -> PduType {
        match self {
            Pdu::Open(_) => PduType::Open,
            Pdu::Close(_) => PduType::Close,
            Pdu::Register(_) => PduType::Register,
            Pdu::Unregister(_) => PduType::Unregister,
            Pdu::Get(_) => PduType::Get,
            Pdu::GetNext(_) => PduType::GetNext,
            Pdu::GetBulk(_) => PduType::GetBulk,
            Pdu::TestSet(_) => PduType::TestSet,
            Pdu::CommitSet => PduType::CommitSet,
            Pdu::UndoSet => PduType::UndoSet,
            Pdu::CleanupSet => PduType::CleanupSet,
            Pdu::Notify(_) => PduType::Notify,
            Pdu::Ping => PduType::Ping,
            Pdu::IndexAllocate(_) => PduType::IndexAllocate,
            Pdu::IndexDeallocate(_) => PduType::IndexDeallocate,
            Pdu::AddAgentCaps(_) => PduType::AddAgentCaps,
            Pdu::RemoveAgentCaps(_) => PduType::RemoveAgentCaps,
            Pdu::Response(_) => PduType::Response,
        }
    }

    /// The payload's length (without header and context).
    pub(crate) fn wire_len(&self) -> usize {
        match self {
            Pdu::Open(o) => 4 + o.id.wire_len() + octets_len(o.description.len()),
            Pdu::Close(_) => 4,
            Pdu::Register(r) => 4 + r.subtree.wire_len() + 4 * usize::from(r.range_subid != 0),
            Pdu::Unregister(u) => 4 + u.subtree.wire_len() + 4 * usize::from(u.range_subid != 0),
            Pdu::Get(ranges) | Pdu::GetNext(ranges) => SearchRange::list_len(ranges),
            Pdu::GetBulk(g) => 4 + SearchRange::list_len(&g.ranges),
            Pdu::TestSet(list)
            | Pdu::Notify(list)
            | Pdu::IndexAllocate(list)
            | Pdu::IndexDeallocate(list) => VarBind::list_len(list),
            Pdu::CommitSet | Pdu::UndoSet | Pdu::CleanupSet | Pdu::Ping => 0,
            Pdu::AddAgentCaps(a) => a.id.wire_len() + octets_len(a.description.len()),
            Pdu::RemoveAgentCaps(id) => id.wire_len(),
            Pdu::Response(r) => 8 + VarBind::list_len(&r.varbinds),
        }
    }

    /// Reads the payload of a PDU of type `pdu_type`: all of the reader, to its end.
    pub(crate) fn read(pdu_type: PduType, r: &mut Reader<'_>) -> Result<Pdu, ParseError> {
        let pdu = match pdu_type {
            PduType::Open => {
                let timeout = r.u8("Open timeout")?;
                r.take(3, "Open timeout")?;
                let (id, _) = Oid::read(r)?;
                let description = r.octets("Open description")?.to_vec();
                Pdu::Open(Open {
                    timeout,
                    id,
                    description,
                })
            }
            PduType::Close => {
                let reason = CloseReason::from_raw(r.u8("Close reason")?);
                r.take(3, "Close reason")?;
                Pdu::Close(Close { reason })
            }
            PduType::Register => {
                let timeout = r.u8("Register fields")?;
                let (priority, range_subid, subtree, upper_bound) = read_registration(r)?;
                Pdu::Register(Register {
                    timeout,
                    priority,
                    range_subid,
                    subtree,
                    upper_bound,
                })
            }
            PduType::Unregister => {
                r.u8("Unregister fields")?;
                let (priority, range_subid, subtree, upper_bound) = read_registration(r)?;
                Pdu::Unregister(Unregister {
                    priority,
                    range_subid,
                    subtree,
                    upper_bound,
                })
            }
            PduType::Get => Pdu::Get(SearchRange::read_list(r)?),
            PduType::GetNext => Pdu::GetNext(SearchRange::read_list(r)?),
            PduType::GetBulk => {
                let non_repeaters = r.u16("GetBulk non_repeaters")?;
                let max_repetitions = r.u16("GetBulk max_repetitions")?;
                Pdu::GetBulk(GetBulk {
                    non_repeaters,
                    max_repetitions,
                    ranges: SearchRange::read_list(r)?,
                })
            }
            PduType::TestSet => Pdu::TestSet(VarBind::read_list(r)?),
            PduType::CommitSet => Pdu::CommitSet,
            PduType::UndoSet => Pdu::UndoSet,
            PduType::CleanupSet => Pdu::CleanupSet,
            PduType::Notify => Pdu::Notify(VarBind::read_list(r)?),
            PduType::Ping => Pdu::Ping,
            PduType::IndexAllocate => Pdu::IndexAllocate(VarBind::read_list(r)?),
            PduType::IndexDeallocate => Pdu::IndexDeallocate(VarBind::read_list(r)?),
            PduType::AddAgentCaps => {
                let (id, _) = Oid::read(r)?;
                let description = r.octets("AddAgentCaps description")?.to_vec();
                Pdu::AddAgentCaps(AddAgentCaps { id, description })
            }
            PduType::RemoveAgentCaps => Pdu::RemoveAgentCaps(Oid::read(r)?.0),
            PduType::Response => {
                let sys_up_time = r.u32("Response sysUpTime")?;
                let error = ResponseError::from_raw(r.u16("Response error")?);
                let index = r.u16("Response index")?;
                Pdu::Response(Response {
                    sys_up_time,
                    error,
                    index,
                    varbinds: VarBind::read_list(r)?,
                })
            }
            PduType::Unknown(raw) => return Err(ParseError::PduType(raw)),
        };
        if r.is_empty() {
            Ok(pdu)
        } else {
            Err(ParseError::TrailingBytes(pdu_type))
        }
    }

    /// Writes the payload.
    pub(crate) fn write(&self, w: &mut Writer<'_>) -> Result<(), EmitError> {
        match self {
            Pdu::Open(o) => {
                w.u8(o.timeout)?;
                w.put(&[0; 3])?;
                o.id.write(false, w)?;
                w.octets(&o.description)
            }
            Pdu::Close(c) => {
                w.u8(c.reason.raw())?;
                w.put(&[0; 3])
            }
            Pdu::Register(r) => {
                w.u8(r.timeout)?;
                write_registration(r.priority, r.range_subid, &r.subtree, r.upper_bound, w)
            }
            Pdu::Unregister(u) => {
                w.u8(0)?;
                write_registration(u.priority, u.range_subid, &u.subtree, u.upper_bound, w)
            }
            Pdu::Get(ranges) | Pdu::GetNext(ranges) => SearchRange::write_list(ranges, w),
            Pdu::GetBulk(g) => {
                w.u16(g.non_repeaters)?;
                w.u16(g.max_repetitions)?;
                SearchRange::write_list(&g.ranges, w)
            }
            Pdu::TestSet(list)
            | Pdu::Notify(list)
            | Pdu::IndexAllocate(list)
            | Pdu::IndexDeallocate(list) => VarBind::write_list(list, w),
            Pdu::CommitSet | Pdu::UndoSet | Pdu::CleanupSet | Pdu::Ping => Ok(()),
            Pdu::AddAgentCaps(a) => {
                a.id.write(false, w)?;
                w.octets(&a.description)
            }
            Pdu::RemoveAgentCaps(id) => id.write(false, w),
            Pdu::Response(r) => {
                w.u32(r.sys_up_time)?;
                w.u16(r.error.raw())?;
                w.u16(r.index)?;
                VarBind::write_list(&r.varbinds, w)
            }
        }
    }
}

/// The fields Register and Unregister share after their first byte: priority,
/// range_subid, reserved, subtree, and the upper bound when range_subid is not 0.
fn read_registration(r: &mut Reader<'_>) -> Result<(u8, u8, Oid, Option<u32>), ParseError> {
    const FIELD: &str = "registration fields";
    let priority = r.u8(FIELD)?;
    let range_subid = r.u8(FIELD)?;
    r.u8(FIELD)?;
    let (subtree, _) = Oid::read(r)?;
    let upper_bound = if range_subid != 0 {
        Some(r.u32("upper_bound")?)
    } else {
        None
    };
    Ok((priority, range_subid, subtree, upper_bound))
}

/// Writes what [`read_registration`] reads. A range_subid of 0 sends no upper bound; one
/// that is not 0 sends the bound (0 when `upper_bound` is `None`).
fn write_registration(
    priority: u8,
    range_subid: u8,
    subtree: &Oid,
    upper_bound: Option<u32>,
    w: &mut Writer<'_>,
) -> Result<(), EmitError> {
    w.u8(priority)?;
    w.u8(range_subid)?;
    w.u8(0)?;
    subtree.write(false, w)?;
    if range_subid != 0 {
        w.u32(upper_bound.unwrap_or(0))?;
    }
    Ok(())
}
