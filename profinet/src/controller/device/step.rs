// SPDX-License-Identifier: MIT OR Apache-2.0
//! Where a device's bring-up stands, and the AR it holds from the Connect on: the steps that
//! have an AR carry it, so a step without one cannot hold one and no AR outlives its step.

use super::*;

/// The AR of a device, from the Connect on.
pub(super) struct Ar {
    pub(super) uuid: Uuid,
    pub(super) session_key: u16,
    pub(super) activity: Uuid,
    /// Sequence number of the last call on the activity.
    pub(super) seq: u32,
    /// The device's address the AR was connected to.
    pub(super) ip: Ipv4Addr,
    pub(super) peer_mac: MacAddress,
    pub(super) alarm_high: RtaChannel,
    pub(super) alarm_low: RtaChannel,
    /// WriteMultiple/Read sequence number (IODHeader SeqNumber).
    pub(super) record_seq: u16,
    /// The delivered alarm of each priority whose AlarmAck waits for the clients
    /// (`[high, low]`).
    pub(super) unacked: [Option<Box<AlarmNotification>>; 2],
    /// The submodules the Connect response's ModuleDiffBlock says are missing or wrong:
    /// their parameter records are not written.
    pub(super) absent: Vec<(u32, u16, u16)>,
    /// The controller's MAC address (source of the AR's alarm frames).
    pub(super) own_mac: MacAddress,
}

impl Ar {
    /// The device's RPC server.
    pub(super) fn rpc_server(&self) -> SocketAddrV4 {
        SocketAddrV4::new(self.ip, rpc::RPC_PORT)
    }

    /// The next call of the AR's activity to the device object `object`, carrying `blocks`
    /// (see [`RpcCall::new`] for `more`); `None` when it does not fit an RPC call.
    pub(super) fn next_call(
        &mut self,
        object: Uuid,
        op: u16,
        blocks: &[u8],
        more: u32,
        now: u64,
    ) -> Option<RpcCall> {
        self.seq += 1;
        RpcCall::new(object, self.activity, self.seq, op, blocks, more, now).ok()
    }

    /// Tells the device that this AR, which it accepted, is given up: an ERR-RTA with `code`
    /// on the low-priority alarm channel (where aborts go), so that it frees the AR at once
    /// for the next Connect instead of holding it until its CMI timeout refuses every
    /// Connect meanwhile. Nothing when the channel was aborted already (by either side).
    /// Whether the ERR-RTA went out.
    pub(super) fn abort(
        &mut self,
        code: rta_pdu::AbortCode,
        out: &mut Vec<ControllerAction>,
    ) -> bool {
        let mut events = Vec::new();
        self.alarm_low.abort(code, &mut events);
        let mut sent = false;
        for e in events {
            if let RtaEvent::Send(pdu) = e
                && let Some(f) = alarms::rta_frame(self.own_mac, self.peer_mac, &pdu)
            {
                out.push(ControllerAction::Frame(f));
                sent = true;
            }
        }
        sent
    }

    /// The alarm channel of a priority.
    pub(super) fn channel(&mut self, p: Priority) -> &mut RtaChannel {
        match p {
            Priority::High => &mut self.alarm_high,
            Priority::Low => &mut self.alarm_low,
        }
    }
}

/// The slot of a priority in [`Ar::unacked`].
pub(super) const fn priority_slot(p: Priority) -> usize {
    match p {
        Priority::High => 0,
        Priority::Low => 1,
    }
}

/// A submodule the device plugged during data exchange (a Plug alarm the clients
/// acknowledged), whose parameters the controller writes before its PlugPrmEnd.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Plug {
    pub(super) api: u32,
    pub(super) slot: u16,
    pub(super) subslot: u16,
    /// The plug alarm's AlarmSequenceNumber, which the PlugPrmEnd carries.
    pub(super) seq: u16,
}

/// What an AR is doing.
pub(super) enum Phase {
    /// Connect sent.
    Connect(RpcCall),
    /// The parameter records are being written.
    Write(RpcCall),
    /// PrmEnd sent.
    PrmEnd(RpcCall),
    /// Waiting for the device's ApplicationReady.
    WaitAppReady { since: u64 },
    /// Data exchange.
    Running,
    /// Data exchange, with a client's record job on the wire.
    Record {
        call: RpcCall,
        request: RecordRequest,
    },
    /// Data exchange, writing the parameters of a plugged submodule.
    PlugWrite { call: RpcCall, plug: Plug },
    /// Data exchange, PlugPrmEnd of a plugged submodule sent.
    PlugPrmEnd { call: RpcCall, plug: Plug },
}

impl Phase {
    /// The call waiting for its answer, in the phases that have one.
    pub(super) fn call(&self) -> Option<&RpcCall> {
        match self {
            Phase::Connect(c)
            | Phase::Write(c)
            | Phase::PrmEnd(c)
            | Phase::Record { call: c, .. }
            | Phase::PlugWrite { call: c, .. }
            | Phase::PlugPrmEnd { call: c, .. } => Some(c),
            Phase::WaitAppReady { .. } | Phase::Running => None,
        }
    }

    /// [`call`](Self::call), mutable.
    pub(super) fn call_mut(&mut self) -> Option<&mut RpcCall> {
        match self {
            Phase::Connect(c)
            | Phase::Write(c)
            | Phase::PrmEnd(c)
            | Phase::Record { call: c, .. }
            | Phase::PlugWrite { call: c, .. }
            | Phase::PlugPrmEnd { call: c, .. } => Some(c),
            Phase::WaitAppReady { .. } | Phase::Running => None,
        }
    }
}

/// Where a device's bring-up stands.
pub(super) enum Step {
    /// Nothing under way: not wanted, or released.
    Idle,
    /// Looking for the device by name.
    Identify { since: u64, id: Identify },
    /// Giving the device its IP address.
    SetIp { since: u64, set: Set },
    /// Reading the device's RealIdentificationData before the Connect.
    Learn { call: RpcCall },
    /// From the Connect on: the AR and what it is doing.
    Ar { ar: Box<Ar>, phase: Phase },
    /// After a failure, until the next attempt.
    Backoff { until: u64 },
}

impl Step {
    /// The AR, in the step that has one.
    pub(super) fn ar(&self) -> Option<&Ar> {
        match self {
            Step::Ar { ar, .. } => Some(ar),
            _ => None,
        }
    }

    /// [`ar`](Self::ar), mutable.
    pub(super) fn ar_mut(&mut self) -> Option<&mut Ar> {
        match self {
            Step::Ar { ar, .. } => Some(ar),
            _ => None,
        }
    }
}
