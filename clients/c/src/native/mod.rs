// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg.h: the native C API of procimg, a thin layer over the Rust client.
//!
//! A client attaches to the procimgd serving an instance (`procimg_attach`), finds its
//! submodules in the layout (`procimg_submodules`, `procimg_find_submodule`), claims the
//! outputs it writes (`procimg_claim`, `procimg_claim_device`) and then either
//! - takes part in the cycle handshake (synchronous role): `procimg_wait_startop` opens the
//!   cycle's window, the inputs are read and the outputs written in place in shared memory
//!   (`procimg_inputs`, `procimg_outputs`, ...), `procimg_set_opdone` sends them; or
//! - reads the newest image and writes outputs whenever it likes (asynchronous role), by
//!   logical address as IO-Base does (`procimg_data_read`, `procimg_data_write`, the caches).
//!
//! Types and constants of the shared memory (`procimg_cycle_info_t`,
//! `procimg_submodule_entry_t`, `PROCIMG_MODE_*`, `PROCIMG_IOXS_*`) come from procimg_shm.h.
//!
//! Errors: every function returns `PROCIMG_OK` (0) or a `PROCIMG_ERR_*` code;
//! `procimg_last_error()` then tells the calling thread what went wrong and what to do.
//! Every pointer argument is checked: a required one that is NULL gives
//! `PROCIMG_ERR_NULL_POINTER`. Out arguments are written only on success (`procimg_attach`
//! sets `*out` to NULL on failure). Nothing a caller passes makes the library abort or
//! unwind.
//!
//! Threads: a handle may move between threads and be used from any of them, one call at a
//! time. A call that starts while another thread is inside a call on the same handle returns
//! `PROCIMG_ERR_BUSY` at once; the library never blocks on a lock. The layout queries
//! (`procimg_submodules`, `procimg_find_submodule`, `procimg_device_name`,
//! `procimg_layout_hash`) take no lock and are never busy.
//!
//! How long returned pointers stay valid:
//! - the submodule table and device names: until `procimg_detach`;
//! - output data (`procimg_outputs`, `procimg_output`): until `procimg_set_opdone`, the next
//!   `procimg_wait_startop` or `procimg_detach`;
//! - input data (`procimg_inputs`, `procimg_input`): until the next `procimg_wait_startop`,
//!   `procimg_detach` or call that takes a newer image. Outside a STARTOP window every call
//!   on the handle may take a newer image except the layout queries, `procimg_claim`,
//!   `procimg_release`, `procimg_claim_device`, `procimg_set_mode`, `procimg_event_fd`,
//!   `procimg_read_cache` and `procimg_write_cache_flush`. Inside a window only
//!   `procimg_read_cache_refresh` and `procimg_write_cache` may (IO-Base's buffered access
//!   works on the newest image), and they find one only when the server has already begun a
//!   later cycle or is gone: this cycle's inputs stay put for the whole window, also after
//!   `procimg_set_opdone`, until the next call that takes a newer image;
//! - `procimg_last_error()`: until the thread's next call; `procimg_strerror()`: forever.
//!
//! The STARTOP window: `procimg_wait_startop` opens it, `procimg_set_opdone` sends the
//! outputs and closes it, the next `procimg_wait_startop` drops a window still open with its
//! outputs unsent. Inside it, `procimg_data_read`, `procimg_output_data_read`,
//! `procimg_data_write` and `procimg_submodule_status` act on the window (this cycle's image
//! and output sample). If a newer image was taken meanwhile, the window is over: the output
//! calls and `procimg_set_opdone` return `PROCIMG_ERR_NOT_IN_CYCLE`.
//!
//! Status bytes passed in are `PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`; others are refused.
//!
//! A synchronous cycle, in short:
//!
//! ```c
//! procimg_client_t *c;
//! size_t echo, n;
//! uint8_t *out;
//! const uint8_t *in;
//! procimg_attach("procimg", "my-plc", NULL, &c);
//! procimg_find_submodule(c, "echo", 1, 1, &echo);
//! procimg_claim(c, &echo, 1);
//! for (;;) {
//!     if (procimg_wait_startop(c, 100, NULL) != PROCIMG_OK) continue;
//!     procimg_input(c, echo, &in, &n);      // in place, no copy
//!     procimg_output(c, echo, &out, &n);    // in place, no copy
//!     out[0] = in[0] + 1;
//!     procimg_set_opdone(c, NULL);
//! }
//! ```
#![allow(non_camel_case_types)]

// One module per job, in the order the header presents them (cbindgen keeps source order).
pub mod error;

pub mod attach;

pub mod layout;

pub mod claims;

pub mod cycle;

pub mod access;

pub mod events;

mod args;
pub mod handle;
