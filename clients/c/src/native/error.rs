// SPDX-License-Identifier: MIT OR Apache-2.0
//! The error codes of `procimg.h`, what each Rust error of the client maps to, and the
//! sentences `procimg_strerror` gives.

use crate::ffi::{guard, last_error_ptr, set_last_error};
use procimg_client::{AccessError, AttachError, ControlError, IoError, WaitError};
use std::ffi::c_char;

/// The result of every function of `procimg.h`: `PROCIMG_OK` or one of the `PROCIMG_ERR_*`
/// codes. On an error, `procimg_last_error()` tells this thread what went wrong and what to do.
pub type procimg_error_t = i32;

/// Success.
pub const PROCIMG_OK: procimg_error_t = 0;
/// A required pointer argument was NULL.
pub const PROCIMG_ERR_NULL_POINTER: procimg_error_t = 1;
/// An argument has a bad value: a string that is not UTF-8, an unknown mode, role or flag,
/// `struct_size` too small, an index out of range, a status byte that is neither
/// `PROCIMG_IOXS_GOOD` nor `PROCIMG_IOXS_BAD`.
pub const PROCIMG_ERR_INVALID_ARGUMENT: procimg_error_t = 2;
/// No procimgd serves the instance.
pub const PROCIMG_ERR_NO_SERVER: procimg_error_t = 3;
/// The server (or the operating system) refused: a claim held by another client (the last
/// error names the holder), too many clients, no access to the instance's shared memory, a
/// mode change not confirmed yet.
pub const PROCIMG_ERR_REFUSED: procimg_error_t = 4;
/// The server's shared-memory layout version or layout hash is not the one expected.
pub const PROCIMG_ERR_LAYOUT: procimg_error_t = 5;
/// Nothing arrived within the timeout (STARTOP, the server's answer).
pub const PROCIMG_ERR_TIMEOUT: procimg_error_t = 6;
/// The server went away; the client re-attaches by itself when it returns.
pub const PROCIMG_ERR_SERVER_GONE: procimg_error_t = 7;
/// The call needs an open STARTOP window (`procimg_wait_startop` first), or the window it
/// acted on is over.
pub const PROCIMG_ERR_NOT_IN_CYCLE: procimg_error_t = 8;
/// No submodule has this logical address.
pub const PROCIMG_ERR_UNKNOWN_ADDRESS: procimg_error_t = 9;
/// The length does not fit the submodule at this address.
pub const PROCIMG_ERR_LENGTH: procimg_error_t = 10;
/// This client does not hold the claim on these outputs.
pub const PROCIMG_ERR_NOT_CLAIMED: procimg_error_t = 11;
/// No process image has been received yet.
pub const PROCIMG_ERR_NO_IMAGE: procimg_error_t = 12;
/// The outputs were not delivered: the server's buffer for this client is full.
pub const PROCIMG_ERR_NOT_DELIVERED: procimg_error_t = 13;
/// The call does not fit the client's role (the handshake on an asynchronous client).
pub const PROCIMG_ERR_WRONG_ROLE: procimg_error_t = 14;
/// Not a failure: `procimg_next_event` found no event.
pub const PROCIMG_ERR_NO_EVENT: procimg_error_t = 15;
/// Another thread is inside a call on this handle right now; calls on one handle must not
/// overlap.
pub const PROCIMG_ERR_BUSY: procimg_error_t = 16;
/// A bug in libprocimg (a caught panic); the last error says where.
pub const PROCIMG_ERR_INTERNAL: procimg_error_t = 99;

/// A failed call: its code and the text for `procimg_last_error`.
#[derive(Debug)]
pub(crate) struct Fail {
    pub(crate) code: procimg_error_t,
    /// `None` for an outcome that is no failure (`PROCIMG_ERR_NO_EVENT`): the last error
    /// text stays as it was.
    pub(crate) text: Option<String>,
}

impl Fail {
    /// A failure with its text.
    pub(crate) fn new(code: procimg_error_t, text: impl Into<String>) -> Fail {
        Fail {
            code,
            text: Some(text.into()),
        }
    }

    /// A required pointer argument of `function` was NULL.
    pub(crate) fn null(function: &str, argument: &str) -> Fail {
        Fail::new(
            PROCIMG_ERR_NULL_POINTER,
            format!("{function}: `{argument}` is NULL; pass a valid pointer"),
        )
    }

    /// An argument of `function` has a bad value.
    pub(crate) fn invalid(function: &str, why: impl core::fmt::Display) -> Fail {
        Fail::new(PROCIMG_ERR_INVALID_ARGUMENT, format!("{function}: {why}"))
    }
}

/// What a native function's body returns: `Ok` is `PROCIMG_OK`.
pub(crate) type Outcome = Result<(), Fail>;

/// Runs the body of an exported function: no panic leaves it, and a failure sets this
/// thread's last error text.
pub(crate) fn call(body: impl FnOnce() -> Outcome) -> procimg_error_t {
    guard(PROCIMG_ERR_INTERNAL, || match body() {
        Ok(()) => PROCIMG_OK,
        Err(fail) => {
            if let Some(text) = fail.text {
                set_last_error(text);
            }
            fail.code
        }
    })
}

impl From<AttachError> for Fail {
    fn from(e: AttachError) -> Fail {
        let code = match &e {
            AttachError::NoServer { .. } => PROCIMG_ERR_NO_SERVER,
            AttachError::AccessDenied { .. } | AttachError::ForeignDirectory { .. } => {
                PROCIMG_ERR_REFUSED
            }
            AttachError::LayoutVersion { .. } | AttachError::LayoutHash { .. } => {
                PROCIMG_ERR_LAYOUT
            }
            AttachError::Refused { .. } => PROCIMG_ERR_REFUSED,
            AttachError::Timeout { .. } => PROCIMG_ERR_TIMEOUT,
            // A service of the instance cannot be opened: the server is not (fully) there.
            AttachError::Shm { .. } => PROCIMG_ERR_NO_SERVER,
        };
        Fail::new(code, e.to_string())
    }
}

impl From<WaitError> for Fail {
    fn from(e: WaitError) -> Fail {
        let code = match &e {
            WaitError::Timeout(_) => PROCIMG_ERR_TIMEOUT,
            WaitError::ServerGone { .. } => PROCIMG_ERR_SERVER_GONE,
            WaitError::LayoutChanged { .. } => PROCIMG_ERR_LAYOUT,
        };
        Fail::new(code, e.to_string())
    }
}

impl From<AccessError> for Fail {
    fn from(e: AccessError) -> Fail {
        let code = match &e {
            AccessError::UnknownAddress { .. } => PROCIMG_ERR_UNKNOWN_ADDRESS,
            AccessError::ValueLength { .. } => PROCIMG_ERR_LENGTH,
        };
        Fail::new(code, e.to_string())
    }
}

impl From<IoError> for Fail {
    fn from(e: IoError) -> Fail {
        let code = match &e {
            IoError::Access(a) => return Fail::from(*a),
            IoError::NotClaimed { .. } => PROCIMG_ERR_NOT_CLAIMED,
            IoError::NoImage { .. } => PROCIMG_ERR_NO_IMAGE,
            IoError::NotDelivered(_) => PROCIMG_ERR_NOT_DELIVERED,
            IoError::ServerGone { .. } => PROCIMG_ERR_SERVER_GONE,
            // The native API makes no device-role calls; should one come, the server's role
            // refuses it.
            IoError::NotDevice { .. } => PROCIMG_ERR_REFUSED,
        };
        Fail::new(code, e.to_string())
    }
}

impl From<ControlError> for Fail {
    fn from(e: ControlError) -> Fail {
        let code = match &e {
            ControlError::Refused(_) | ControlError::NotDevice { .. } => PROCIMG_ERR_REFUSED,
            ControlError::NoAnswer { .. } => PROCIMG_ERR_TIMEOUT,
            // Control requests come from an attached client: its server went away.
            ControlError::NoServer { .. } | ControlError::Transport { .. } => {
                PROCIMG_ERR_SERVER_GONE
            }
            // An answer this client cannot read: client and server are different versions.
            ControlError::Protocol { .. } => PROCIMG_ERR_LAYOUT,
        };
        Fail::new(code, e.to_string())
    }
}

/// The sentence for an error code: one per code, static.
fn sentence(code: procimg_error_t) -> &'static std::ffi::CStr {
    match code {
        PROCIMG_OK => c"success",
        PROCIMG_ERR_NULL_POINTER => c"a required pointer argument was NULL",
        PROCIMG_ERR_INVALID_ARGUMENT => c"an argument has a value the function does not accept",
        PROCIMG_ERR_NO_SERVER => c"no procimgd serves this instance",
        PROCIMG_ERR_REFUSED => c"the server refused the request",
        PROCIMG_ERR_LAYOUT => c"the server's process-image layout is not the one expected",
        PROCIMG_ERR_TIMEOUT => c"nothing arrived within the timeout",
        PROCIMG_ERR_SERVER_GONE => c"the server went away",
        PROCIMG_ERR_NOT_IN_CYCLE => {
            c"the call needs an open STARTOP window (call procimg_wait_startop first)"
        }
        PROCIMG_ERR_UNKNOWN_ADDRESS => c"no submodule has this logical address",
        PROCIMG_ERR_LENGTH => c"the length does not fit the submodule at this address",
        PROCIMG_ERR_NOT_CLAIMED => c"this client has not claimed these outputs",
        PROCIMG_ERR_NO_IMAGE => c"no process image has been received yet",
        PROCIMG_ERR_NOT_DELIVERED => c"the outputs were not delivered: the server's buffer is full",
        PROCIMG_ERR_WRONG_ROLE => c"the call does not fit the client's role",
        PROCIMG_ERR_NO_EVENT => c"no event is pending",
        PROCIMG_ERR_BUSY => c"another thread is inside a call on this handle",
        PROCIMG_ERR_INTERNAL => c"internal error in libprocimg (a bug; please report it)",
        _ => c"unknown procimg error code",
    }
}

/// A static sentence for `code`, never NULL ("unknown procimg error code" for a value that
/// is no `procimg_error_t`). For what went wrong in a particular call, see
/// `procimg_last_error`.
#[unsafe(no_mangle)]
pub extern "C" fn procimg_strerror(code: procimg_error_t) -> *const c_char {
    guard(c"unknown procimg error code".as_ptr(), || {
        sentence(code).as_ptr()
    })
}

/// This thread's last failure as text: what went wrong, naming the instance, address or
/// argument involved, and what to do; "" if no call of this thread has failed. Never NULL.
/// The text stays valid until this thread's next call into libprocimg; a successful call
/// does not clear it.
#[unsafe(no_mangle)]
pub extern "C" fn procimg_last_error() -> *const c_char {
    guard(c"".as_ptr(), last_error_ptr)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_has_its_own_sentence() {
        let codes: Vec<procimg_error_t> = (0..=16).chain([99]).collect();
        let mut seen = std::collections::BTreeSet::new();
        for code in codes {
            let s = sentence(code).to_str().unwrap();
            assert!(!s.is_empty() && s != "unknown procimg error code", "{code}");
            assert!(seen.insert(s), "code {code} repeats {s:?}");
        }
        assert_eq!(sentence(17).to_str().unwrap(), "unknown procimg error code");
        assert_eq!(sentence(-1).to_str().unwrap(), "unknown procimg error code");
    }

    #[test]
    fn no_event_leaves_the_last_error_alone() {
        crate::ffi::set_last_error("earlier");
        let code = call(|| {
            Err(Fail {
                code: PROCIMG_ERR_NO_EVENT,
                text: None,
            })
        });
        assert_eq!(code, PROCIMG_ERR_NO_EVENT);
        // SAFETY: this thread's last error, NUL-terminated.
        let text = unsafe { std::ffi::CStr::from_ptr(procimg_last_error()) };
        assert_eq!(text.to_str().unwrap(), "earlier");
    }

    #[test]
    fn a_panicking_body_is_an_internal_error() {
        assert_eq!(call(|| panic!("bug")), PROCIMG_ERR_INTERNAL);
    }
}
