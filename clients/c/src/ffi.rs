// SPDX-License-Identifier: MIT OR Apache-2.0
//! What both C interfaces need at the boundary: no unwinding, the thread's last error text,
//! and millisecond timeouts.

use std::cell::RefCell;
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Duration;

/// Runs `f`; a panic inside becomes `on_panic` (and the thread's last error text) instead of
/// unwinding into C, which would be undefined behaviour.
pub fn guard<R>(on_panic: R, f: impl FnOnce() -> R) -> R {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            set_last_error(format!(
                "internal error in libprocimg ({what}); please report it with the call that \
                 caused it"
            ));
            on_panic
        }
    }
}

thread_local! {
    static LAST_ERROR: RefCell<Option<CString>> = const { RefCell::new(None) };
}

/// Records the text of this thread's last failure (what went wrong and what to do).
pub fn set_last_error(message: impl Into<String>) {
    let text = message.into().replace('\0', " ");
    let c = CString::new(text).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = Some(c));
}

/// Clears this thread's last failure text.
pub fn clear_last_error() {
    LAST_ERROR.with(|e| *e.borrow_mut() = None);
}

/// This thread's last failure text, or an empty string; valid until this thread's next call
/// into the library.
pub fn last_error_ptr() -> *const c_char {
    LAST_ERROR.with(|e| match &*e.borrow() {
        Some(c) => c.as_ptr(),
        None => c"".as_ptr(),
    })
}

/// A C timeout in milliseconds.
pub fn millis(ms: u32) -> Duration {
    Duration::from_millis(u64::from(ms))
}

/// Reads a C string argument; `None` for NULL or text that is not UTF-8.
///
/// # Safety
/// `p` is NULL or points to a NUL-terminated string that stays valid during the call.
pub unsafe fn c_str<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        return None;
    }
    // SAFETY: not NULL, and NUL-terminated by the caller's contract.
    unsafe { std::ffi::CStr::from_ptr(p) }.to_str().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_the_fallback_value_and_an_error_text() {
        let r = guard(-1, || -> i32 { panic!("boom") });
        assert_eq!(r, -1);
        // SAFETY: the pointer is this thread's current last error, NUL-terminated.
        let text = unsafe { std::ffi::CStr::from_ptr(last_error_ptr()) };
        assert!(text.to_str().unwrap().contains("boom"));
    }
}
