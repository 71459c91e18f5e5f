// SPDX-License-Identifier: MIT OR Apache-2.0
//! The answers to the master's requests (RFC 2741 §7.2): Get, GetNext and GetBulk from the
//! MIB view; sets refused, the MIB being read-only.

use crate::mib::{MibView, Snapshot};
use crate::pdu::{Pdu, PduRepr, Response, ResponseError, VarBind};

/// The MIB view of one batch of input, made from a snapshot only when a request needs it.
pub(crate) struct LazyView<'a, F: FnMut() -> Snapshot> {
    snapshot: &'a mut F,
    view: Option<MibView>,
}

impl<'a, F: FnMut() -> Snapshot> LazyView<'a, F> {
    pub(crate) fn new(snapshot: &'a mut F) -> LazyView<'a, F> {
        LazyView {
            snapshot,
            view: None,
        }
    }

    fn get(&mut self) -> &MibView {
        self.view
            .get_or_insert_with(|| MibView::new(&(self.snapshot)()))
    }
}

/// The Response to a request of the master, `None` for CleanupSet (never answered) and
/// for what needs no answer (Responses, a Close).
pub(crate) fn answer<F: FnMut() -> Snapshot>(
    request: &PduRepr,
    view: &mut LazyView<'_, F>,
) -> Option<PduRepr> {
    let ok = |varbinds: Vec<VarBind>| (ResponseError::NoError, 0, varbinds);
    let (error, index, varbinds) = match &request.pdu {
        // Only the default context is registered: the master sends no other.
        _ if request.context.is_some() => (ResponseError::UnsupportedContext, 0, Vec::new()),
        Pdu::Get(ranges) => ok(ranges
            .iter()
            .map(|r| VarBind::new(r.start.clone(), view.get().get(&r.start)))
            .collect()),
        Pdu::GetNext(ranges) => ok(ranges.iter().map(|r| view.get().get_next(r)).collect()),
        Pdu::GetBulk(bulk) => ok(view.get().get_bulk(bulk)),
        // Read-only: the first VarBind (index 1) is not writable, which fails the set.
        Pdu::TestSet(varbinds) => (
            ResponseError::NotWritable,
            u16::from(!varbinds.is_empty()),
            Vec::new(),
        ),
        // A TestSet of ours never succeeds, so neither comes; if one does, nothing was
        // written, committed or undone.
        Pdu::CommitSet => (ResponseError::CommitFailed, 0, Vec::new()),
        Pdu::UndoSet => (ResponseError::UndoFailed, 0, Vec::new()),
        Pdu::Ping => ok(Vec::new()),
        Pdu::CleanupSet | Pdu::Response(_) | Pdu::Close(_) => return None,
        // The subagent's own PDUs, coming the wrong way.
        Pdu::Open(_)
        | Pdu::Register(_)
        | Pdu::Unregister(_)
        | Pdu::Notify(_)
        | Pdu::IndexAllocate(_)
        | Pdu::IndexDeallocate(_)
        | Pdu::AddAgentCaps(_)
        | Pdu::RemoveAgentCaps(_) => (ResponseError::ProcessingError, 0, Vec::new()),
    };
    Some(response(request, error, index, varbinds))
}

/// A Response to `request` with its session, transaction and packet IDs.
pub(crate) fn response(
    request: &PduRepr,
    error: ResponseError,
    index: u16,
    varbinds: Vec<VarBind>,
) -> PduRepr {
    PduRepr::new(
        request.session_id,
        request.transaction_id,
        request.packet_id,
        Pdu::Response(Response {
            // The master ignores a subagent's sysUpTime (RFC 2741 §6.2.16).
            sys_up_time: 0,
            error,
            index,
            varbinds,
        }),
    )
}
