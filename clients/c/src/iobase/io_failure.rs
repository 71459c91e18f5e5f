// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO-Base code and text of a failed access to procimgd's IO data, for the
//! controller's data functions and the device's alike: one code per `IoError`, and a text
//! that names the instance and tells the program what to do. What differs between the
//! roles is only in the texts, given as an [`IoContext`].

use super::errors::*;
use procimg_client::IoError;
use procimg_client::access::AccessError;
use std::time::Duration;

/// What the texts of one role say.
pub(crate) struct IoContext<'a> {
    /// The procimgd instance the handle is attached to.
    pub instance: &'a str,
    /// Who the handle is in the texts: "the controller", "the device".
    pub owner: &'a str,
    /// How the program owns its outputs again once another client took them.
    pub reclaim: &'a str,
    /// How the program writes less often when the server's buffer for it is full.
    pub fewer_writes: &'a str,
    /// How long a write waited for room in that buffer before it gave up, if it waits.
    pub delivery_wait: Option<Duration>,
}

/// The code of an address or length that breaks IO-Base's rules.
pub(crate) fn access_failure(f: &str, e: AccessError) -> u32 {
    match e {
        AccessError::UnknownAddress { .. } => fail(f, PNIO_ERR_UNKNOWN_ADDR, e),
        AccessError::ValueLength { .. } => fail(f, PNIO_ERR_VALUE_LEN, e),
    }
}

/// Records why function `f` failed with `e` and returns its code.
pub(crate) fn io_failure(f: &str, ctx: &IoContext<'_>, e: IoError) -> u32 {
    let instance = ctx.instance;
    match e {
        IoError::Access(a) => access_failure(f, a),
        IoError::NotClaimed { .. } => fail(
            f,
            PNIO_ERR_NO_CONNECTION,
            format_args!(
                "{e}; {} does not own them on instance \"{instance}\": another client of it \
                 does (one that claimed them first when the instance restarted; `procimg \
                 status --instance {instance}` names the clients); {}",
                ctx.owner, ctx.reclaim
            ),
        ),
        IoError::NotDelivered(_) => {
            let waited = ctx
                .delivery_wait
                .map(|w| format!(" (waited {w:?})"))
                .unwrap_or_default();
            fail(
                f,
                PNIO_ERR_NO_RESOURCE,
                format_args!("{e}{waited}; {}", ctx.fewer_writes),
            )
        }
        // Both roles check the server's role at open: only a server replaced by one of the
        // other role under the same instance name gets here. The text names the instance.
        IoError::NotDevice { .. } => fail(f, PNIO_ERR_INVALID_CONFIG, e),
        // The texts name the instance and say to wait or retry.
        IoError::NoImage { .. } | IoError::ServerGone { .. } => fail(f, PNIO_ERR_NO_CONNECTION, e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ctx() -> IoContext<'static> {
        IoContext {
            instance: "plant",
            owner: "the device",
            reclaim: "stop and start it again",
            fewer_writes: "write less",
            delivery_wait: None,
        }
    }

    #[test]
    fn one_code_per_error() {
        let gone = || IoError::ServerGone {
            instance: "plant".into(),
        };
        assert_eq!(io_failure("f", &ctx(), gone()), PNIO_ERR_NO_CONNECTION);
        let no_image = IoError::NoImage {
            instance: "plant".into(),
        };
        assert_eq!(io_failure("f", &ctx(), no_image), PNIO_ERR_NO_CONNECTION);
        let not_device = IoError::NotDevice {
            instance: "plant".into(),
        };
        assert_eq!(io_failure("f", &ctx(), not_device), PNIO_ERR_INVALID_CONFIG);
        assert_eq!(
            io_failure("f", &ctx(), IoError::NotDelivered(4)),
            PNIO_ERR_NO_RESOURCE
        );
        let not_claimed = IoError::NotClaimed {
            submodule: 2,
            address: 10,
        };
        assert_eq!(io_failure("f", &ctx(), not_claimed), PNIO_ERR_NO_CONNECTION);
        // SAFETY: this thread's text, valid until its next call into the library.
        let text = unsafe { std::ffi::CStr::from_ptr(crate::ffi::last_error_ptr()) }
            .to_string_lossy()
            .into_owned();
        assert!(text.contains("\"plant\""), "{text}");
        assert!(text.contains("stop and start it again"), "{text}");
    }
}
