// SPDX-License-Identifier: MIT OR Apache-2.0
//! The host's sockets (reference §1.5, 0x40–0x43 and 0x50).
//!
//! Not carried out yet: every request is answered with a Socket Response that says so by
//! its error bits — Open Socket with "open failed" (bit 1), the others with "socket not
//! open" (bit 0), Send Socket Data also with "send failed" (bit 4) — and the socket status
//! "dead" (bit 4). Never a success: a host that checks its responses learns that no socket
//! exists.

use procimg_gs20::link::SocketRequest;
use procimg_gs20::messages::{Message, SocketErrors, SocketResponse, SocketStatus};

/// The answer to a socket request.
pub fn answer(req: &SocketRequest) -> Option<Vec<u8>> {
    let (handle, errors) = match req {
        SocketRequest::Open(_) => (0, SocketErrors::OPEN_FAILED),
        SocketRequest::SetOption { handle, .. }
        | SocketRequest::Status { handle }
        | SocketRequest::Close { handle } => (*handle, SocketErrors::NOT_OPEN),
        SocketRequest::Send { handle, .. } => {
            (*handle, SocketErrors::NOT_OPEN | SocketErrors::SEND_FAILED)
        }
    };
    SocketResponse {
        handle,
        status: SocketStatus::DEAD,
        errors,
    }
    .to_vec()
    .ok()
}
