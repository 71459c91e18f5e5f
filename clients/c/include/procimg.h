/* SPDX-License-Identifier: MIT OR Apache-2.0 */

#ifndef PROCIMG_H
#define PROCIMG_H

/* Generated from clients/c/src/native by cbindgen: do not edit. Regenerate with
 * PROCIMG_BLESS=1 cargo test -p procimg-c --test native_header */

#include "procimg_shm.h"
/*
 * procimg.h: the native C API of procimg, a thin layer over the Rust client.
 *
 * A client attaches to the procimgd serving an instance (`procimg_attach`), finds its
 * submodules in the layout (`procimg_submodules`, `procimg_find_submodule`), claims the
 * outputs it writes (`procimg_claim`, `procimg_claim_device`) and then either
 * - takes part in the cycle handshake (synchronous role): `procimg_wait_startop` opens the
 *   cycle's window, the inputs are read and the outputs written in place in shared memory
 *   (`procimg_inputs`, `procimg_outputs`, ...), `procimg_set_opdone` sends them; or
 * - reads the newest image and writes outputs whenever it likes (asynchronous role), by
 *   logical address as IO-Base does (`procimg_data_read`, `procimg_data_write`, the caches).
 *
 * Types and constants of the shared memory (`procimg_cycle_info_t`,
 * `procimg_submodule_entry_t`, `PROCIMG_MODE_*`, `PROCIMG_IOXS_*`) come from procimg_shm.h.
 *
 * Errors: every function returns `PROCIMG_OK` (0) or a `PROCIMG_ERR_*` code;
 * `procimg_last_error()` then tells the calling thread what went wrong and what to do.
 * Every pointer argument is checked: a required one that is NULL gives
 * `PROCIMG_ERR_NULL_POINTER`. Out arguments are written only on success (`procimg_attach`
 * sets `*out` to NULL on failure). Nothing a caller passes makes the library abort or
 * unwind.
 *
 * Threads: a handle may move between threads and be used from any of them, one call at a
 * time. A call that starts while another thread is inside a call on the same handle returns
 * `PROCIMG_ERR_BUSY` at once; the library never blocks on a lock. The layout queries
 * (`procimg_submodules`, `procimg_find_submodule`, `procimg_device_name`,
 * `procimg_layout_hash`) take no lock and are never busy.
 *
 * How long returned pointers stay valid:
 * - the submodule table and device names: until `procimg_detach`;
 * - output data (`procimg_outputs`, `procimg_output`): until `procimg_set_opdone`, the next
 *   `procimg_wait_startop` or `procimg_detach`;
 * - input data (`procimg_inputs`, `procimg_input`): until the next `procimg_wait_startop`,
 *   `procimg_detach` or call that takes a newer image. Outside a STARTOP window every call
 *   on the handle may take a newer image except the layout queries, `procimg_claim`,
 *   `procimg_release`, `procimg_claim_device`, `procimg_set_mode`, `procimg_event_fd`,
 *   `procimg_read_cache` and `procimg_write_cache_flush`. Inside a window only
 *   `procimg_read_cache_refresh` and `procimg_write_cache` may (IO-Base's buffered access
 *   works on the newest image), and they find one only when the server has already begun a
 *   later cycle or is gone: this cycle's inputs stay put for the whole window, also after
 *   `procimg_set_opdone`, until the next call that takes a newer image;
 * - `procimg_last_error()`: until the thread's next call; `procimg_strerror()`: forever.
 *
 * The STARTOP window: `procimg_wait_startop` opens it, `procimg_set_opdone` sends the
 * outputs and closes it, the next `procimg_wait_startop` drops a window still open with its
 * outputs unsent. Inside it, `procimg_data_read`, `procimg_output_data_read`,
 * `procimg_data_write` and `procimg_submodule_status` act on the window (this cycle's image
 * and output sample). If a newer image was taken meanwhile, the window is over: the output
 * calls and `procimg_set_opdone` return `PROCIMG_ERR_NOT_IN_CYCLE`.
 *
 * Status bytes passed in are `PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`; others are refused.
 *
 * A synchronous cycle, in short:
 *
 * ```c
 * procimg_client_t *c;
 * size_t echo, n;
 * uint8_t *out;
 * const uint8_t *in;
 * procimg_attach("procimg", "my-plc", NULL, &c);
 * procimg_find_submodule(c, "echo", 1, 1, &echo);
 * procimg_claim(c, &echo, 1);
 * for (;;) {
 *     if (procimg_wait_startop(c, 100, NULL) != PROCIMG_OK) continue;
 *     procimg_input(c, echo, &in, &n);      // in place, no copy
 *     procimg_output(c, echo, &out, &n);    // in place, no copy
 *     out[0] = in[0] + 1;
 *     procimg_set_opdone(c, NULL);
 * }
 * ```
 */

/**
 * An attached client (opaque): made by `procimg_attach`, freed by `procimg_detach`.
 */
typedef struct procimg_client procimg_client_t;

/**
 * Role of a client that takes part in the STARTOP/OPDONE handshake: the server waits for
 * its `procimg_set_opdone` every cycle (IO-Base's isochronous access).
 */
#define PROCIMG_ROLE_SYNCHRONOUS 0

/**
 * Role of a client that reads the newest image and writes outputs whenever it likes (no
 * handshake; IO-Base's non-isochronous access).
 */
#define PROCIMG_ROLE_ASYNCHRONOUS 1

/**
 * Attach flag: slice access (IO-Base `PNIO_CEP_SLICE_ACCESS`): read and write parts of a
 * submodule, from any address inside it. Without it, accesses by address cover whole
 * submodules from their first address.
 */
#define PROCIMG_ATTACH_SLICE_ACCESS 1

/**
 * Attach flag: deliver `PROCIMG_EVENT_NEWCYCLE` events.
 */
#define PROCIMG_ATTACH_NEWCYCLE 2

/**
 * Attach flag: `procimg_wait_startop` polls for the next image instead of sleeping (for a
 * thread with a CPU of its own).
 */
#define PROCIMG_ATTACH_BUSY_POLL 4

/**
 * Attach flag: refuse to attach (`PROCIMG_ERR_LAYOUT`) unless the server's layout hash is
 * `layout_hash`.
 */
#define PROCIMG_ATTACH_EXPECT_LAYOUT_HASH 8

/**
 * Attach flag: a sleeping `procimg_wait_startop` (and an IO-Base callback thread) sleeps
 * until procimgd signals STARTOP, instead of waking 50 µs before it is due and polling for
 * it (the default, which finds the CPU running when STARTOP comes, for some 30 µs of CPU
 * time a cycle).
 */
#define PROCIMG_ATTACH_SLEEP_ONLY 16

/**
 * The default attach timeout in milliseconds.
 */
#define PROCIMG_DEFAULT_ATTACH_TIMEOUT_MS 3000

/**
 * Event kind: the mode changed to `mode` (IO-Base `PNIO_CBE_MODE_IND`); one event per step,
 * so OFFLINE → OPERATE reports CLEAR, then OPERATE. The same value as `procimg_shm.h`'s
 * event id of the same name, so both headers can be included together.
 */
#define PROCIMG_EVENT_MODE 3

/**
 * Event kind: this client's OPDONE for cycle `cycle` came too late, its outputs of that
 * cycle were not used (IO-Base `PNIO_CP_CBE_OPFAULT_IND`).
 */
#define PROCIMG_EVENT_OPFAULT 1

/**
 * Event kind: a bus cycle's outputs went out (IO-Base `PNIO_CP_CBE_NEWCYCLE_IND`); only
 * with `PROCIMG_ATTACH_NEWCYCLE`. The same value as `procimg_shm.h`'s event id of the same
 * name.
 */
#define PROCIMG_EVENT_NEWCYCLE 2

/**
 * Event kind: the server announced that it is stopping. The client re-attaches by itself
 * when a server for the instance returns.
 */
#define PROCIMG_EVENT_SERVER_SHUTDOWN 4

/**
 * Event kind: the client re-attached to a restarted server of generation `generation`;
 * `procimg_event_fd` has a new descriptor.
 */
#define PROCIMG_EVENT_REATTACHED 5

/**
 * Event kind: after a server restart, the claim on submodule `submodule` could not be taken
 * again (another client holds it now).
 */
#define PROCIMG_EVENT_CLAIM_LOST 6

/**
 * Event kind: the restarted server has another layout (a changed configuration, or a
 * station its program defined anew), hash `layout_hash`, and the client follows it:
 * submodule indexes and addresses are the new layout's, and claims of submodules still
 * there were taken again. Comes right after `PROCIMG_EVENT_REATTACHED`. A client attached
 * with `PROCIMG_ATTACH_EXPECT_LAYOUT_HASH` does not follow: its calls answer
 * `PROCIMG_ERR_LAYOUT` instead.
 */
#define PROCIMG_EVENT_LAYOUT_CHANGED 7

/**
 * The result of every function of `procimg.h`: `PROCIMG_OK` or one of the `PROCIMG_ERR_*`
 * codes. On an error, `procimg_last_error()` tells this thread what went wrong and what to do.
 */
typedef int32_t procimg_error_t;

/**
 * How `procimg_attach` attaches. Fill it with `procimg_attach_options_init` first, then
 * change what you need.
 */
typedef struct {
  /**
   * `sizeof(procimg_attach_options_t)` of the header the program was built with (set by
   * `procimg_attach_options_init`); a smaller value is refused.
   */
  uint32_t struct_size;
  /**
   * `PROCIMG_ROLE_SYNCHRONOUS` or `PROCIMG_ROLE_ASYNCHRONOUS`.
   */
  uint32_t role;
  /**
   * `PROCIMG_ATTACH_*` flags, or-ed.
   */
  uint32_t flags;
  /**
   * How long attaching may take, in milliseconds.
   */
  uint32_t timeout_ms;
  /**
   * The layout hash required with `PROCIMG_ATTACH_EXPECT_LAYOUT_HASH`.
   */
  uint64_t layout_hash;
} procimg_attach_options_t;

/**
 * The four status bytes of a submodule, each `PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`.
 */
typedef struct {
  /**
   * Remote status of the inputs: the device's IOPS.
   */
  uint8_t input_remote;
  /**
   * Local status of the inputs as sent to the device: this side's IOCS.
   */
  uint8_t input_local;
  /**
   * Local status of the outputs as sent to the device: this side's IOPS.
   */
  uint8_t output_local;
  /**
   * Remote status of the outputs: the device's IOCS for the previous cycle's outputs.
   */
  uint8_t output_remote;
} procimg_submodule_ioxs_t;

/**
 * One event. Fields a kind does not use are 0.
 */
typedef struct {
  /**
   * `PROCIMG_EVENT_*`.
   */
  uint32_t kind;
  /**
   * `PROCIMG_EVENT_MODE`: the new mode (`PROCIMG_MODE_OFFLINE`, `_CLEAR`, `_OPERATE`).
   */
  uint32_t mode;
  /**
   * `PROCIMG_EVENT_OPFAULT`: the cycle whose OPDONE came too late.
   */
  uint64_t cycle;
  /**
   * `PROCIMG_EVENT_REATTACHED`: the new server generation.
   */
  uint64_t generation;
  /**
   * `PROCIMG_EVENT_CLAIM_LOST`: the submodule index.
   */
  uint64_t submodule;
  /**
   * `PROCIMG_EVENT_LAYOUT_CHANGED`: the new layout hash.
   */
  uint64_t layout_hash;
} procimg_event_t;

/**
 * Success.
 */
#define PROCIMG_OK 0

/**
 * A required pointer argument was NULL.
 */
#define PROCIMG_ERR_NULL_POINTER 1

/**
 * An argument has a bad value: a string that is not UTF-8, an unknown mode, role or flag,
 * `struct_size` too small, an index out of range, a status byte that is neither
 * `PROCIMG_IOXS_GOOD` nor `PROCIMG_IOXS_BAD`.
 */
#define PROCIMG_ERR_INVALID_ARGUMENT 2

/**
 * No procimgd serves the instance.
 */
#define PROCIMG_ERR_NO_SERVER 3

/**
 * The server (or the operating system) refused: a claim held by another client (the last
 * error names the holder), too many clients, no access to the instance's shared memory, a
 * mode change not confirmed yet.
 */
#define PROCIMG_ERR_REFUSED 4

/**
 * The server's shared-memory layout version or layout hash is not the one expected.
 */
#define PROCIMG_ERR_LAYOUT 5

/**
 * Nothing arrived within the timeout (STARTOP, the server's answer).
 */
#define PROCIMG_ERR_TIMEOUT 6

/**
 * The server went away; the client re-attaches by itself when it returns.
 */
#define PROCIMG_ERR_SERVER_GONE 7

/**
 * The call needs an open STARTOP window (`procimg_wait_startop` first), or the window it
 * acted on is over.
 */
#define PROCIMG_ERR_NOT_IN_CYCLE 8

/**
 * No submodule has this logical address.
 */
#define PROCIMG_ERR_UNKNOWN_ADDRESS 9

/**
 * The length does not fit the submodule at this address.
 */
#define PROCIMG_ERR_LENGTH 10

/**
 * This client does not hold the claim on these outputs.
 */
#define PROCIMG_ERR_NOT_CLAIMED 11

/**
 * No process image has been received yet.
 */
#define PROCIMG_ERR_NO_IMAGE 12

/**
 * The outputs were not delivered: the server's buffer for this client is full.
 */
#define PROCIMG_ERR_NOT_DELIVERED 13

/**
 * The call does not fit the client's role (the handshake on an asynchronous client).
 */
#define PROCIMG_ERR_WRONG_ROLE 14

/**
 * Not a failure: `procimg_next_event` found no event.
 */
#define PROCIMG_ERR_NO_EVENT 15

/**
 * Another thread is inside a call on this handle right now; calls on one handle must not
 * overlap.
 */
#define PROCIMG_ERR_BUSY 16

/**
 * A bug in libprocimg (a caught panic); the last error says where.
 */
#define PROCIMG_ERR_INTERNAL 99

#ifdef __cplusplus
extern "C" {
#endif // __cplusplus

/**
 * A static sentence for `code`, never NULL ("unknown procimg error code" for a value that
 * is no `procimg_error_t`). For what went wrong in a particular call, see
 * `procimg_last_error`.
 */
const char *procimg_strerror(procimg_error_t code);

/**
 * This thread's last failure as text: what went wrong, naming the instance, address or
 * argument involved, and what to do; "" if no call of this thread has failed. Never NULL.
 * The text stays valid until this thread's next call into libprocimg; a successful call
 * does not clear it.
 */
const char *procimg_last_error(void);

/**
 * Fills `opts` with the defaults: `struct_size` = its size, synchronous role, slice access,
 * a timeout of 3000 ms, no expected layout hash. Does nothing when `opts` is NULL.
 *
 * # Safety
 * `opts` is NULL or valid for writing a `procimg_attach_options_t`.
 */
void procimg_attach_options_init(procimg_attach_options_t *opts);

/**
 * Attaches to the procimgd serving `instance` as a client named `name` (shown by
 * `procimg status`; it names the holder when another client's claim is refused). `opts`
 * NULL means the defaults of `procimg_attach_options_init`. On success `*out` is the handle
 * (free it with `procimg_detach`); on failure it is NULL.
 *
 * Fails with `PROCIMG_ERR_NO_SERVER` when no server serves the instance,
 * `PROCIMG_ERR_REFUSED` when it refuses the client (too many clients, no access),
 * `PROCIMG_ERR_LAYOUT` on a layout version or hash mismatch, `PROCIMG_ERR_TIMEOUT` when it
 * does not answer within `timeout_ms`, `PROCIMG_ERR_INVALID_ARGUMENT` on a bad option.
 *
 * # Safety
 * `instance` and `name` are NULL or NUL-terminated strings; `opts` is NULL or points to a
 * `procimg_attach_options_t` of at least its `struct_size` bytes; `out` is NULL or writable.
 */
procimg_error_t procimg_attach(const char *instance,
                               const char *name,
                               const procimg_attach_options_t *opts,
                               procimg_client_t **out);

/**
 * Detaches the client and frees the handle: its claims are released, an open STARTOP
 * window is dropped with its outputs unsent, and every pointer obtained through the handle
 * becomes invalid. `PROCIMG_ERR_BUSY` (and nothing freed) when another thread is inside a
 * call on it.
 *
 * # Safety
 * `client` is NULL or a handle from `procimg_attach` not yet detached; it is not used
 * afterwards.
 */
procimg_error_t procimg_detach(procimg_client_t *client);

/**
 * The submodule table: `*table` points to `*count` entries in image order (an entry's index
 * is the `submodule` argument of the other calls). The table belongs to the handle and stays
 * valid, unchanged, until `procimg_detach`.
 *
 * # Safety
 * `client` is NULL or a live handle; `table` and `count` are NULL or writable.
 */
procimg_error_t procimg_submodules(const procimg_client_t *client,
                                   const procimg_submodule_entry_t **table,
                                   size_t *count);

/**
 * The index of the submodule of device `device` (its station name) at `slot`/`subslot`.
 * `PROCIMG_ERR_INVALID_ARGUMENT` when the layout has no such submodule.
 *
 * # Safety
 * `client` is NULL or a live handle; `device` is NULL or a NUL-terminated string; `index` is
 * NULL or writable.
 */
procimg_error_t procimg_find_submodule(const procimg_client_t *client,
                                       const char *device,
                                       uint16_t slot,
                                       uint16_t subslot,
                                       size_t *index);

/**
 * The station name of device `device` (the `device` field of a submodule entry), as a
 * NUL-terminated string owned by the handle, valid until `procimg_detach`.
 *
 * # Safety
 * `client` is NULL or a live handle; `name` is NULL or writable.
 */
procimg_error_t procimg_device_name(const procimg_client_t *client,
                                    uint16_t device,
                                    const char **name);

/**
 * The layout hash of the server's IO configuration (for `PROCIMG_ATTACH_EXPECT_LAYOUT_HASH`).
 *
 * # Safety
 * `client` is NULL or a live handle; `hash` is NULL or writable.
 */
procimg_error_t procimg_layout_hash(const procimg_client_t *client, uint64_t *hash);

/**
 * Claims the outputs of `count` submodules (indices into the submodule table), all or
 * none. `PROCIMG_ERR_REFUSED` when another client holds one of them: `procimg_last_error()`
 * names the holder (name, pid). `submodules` may be NULL when `count` is 0. Claims die with
 * the client.
 *
 * # Safety
 * `client` is NULL or a live handle; `submodules` is NULL or points to `count` indices.
 */
procimg_error_t procimg_claim(procimg_client_t *client, const size_t *submodules, size_t count);

/**
 * Releases the claims on `count` submodules. `submodules` may be NULL when `count` is 0.
 *
 * # Safety
 * `client` is NULL or a live handle; `submodules` is NULL or points to `count` indices.
 */
procimg_error_t procimg_release(procimg_client_t *client, const size_t *submodules, size_t count);

/**
 * Claims the outputs of every submodule of device `device` (its station name) that has
 * outputs. `PROCIMG_ERR_INVALID_ARGUMENT` when the layout has no such device,
 * `PROCIMG_ERR_REFUSED` (holder named) when another client holds one of them.
 *
 * # Safety
 * `client` is NULL or a live handle; `device` is NULL or a NUL-terminated string.
 */
procimg_error_t procimg_claim_device(procimg_client_t *client, const char *device);

/**
 * Waits up to `timeout_ms` (0: only looks) for the next STARTOP and opens this cycle's
 * window: the inputs of the cycle are published, the outputs may be written until
 * `procimg_set_opdone`. A window still open from before is dropped, its outputs unsent (the
 * server counts an OPFAULT for that cycle). `*info` (when not NULL) gets the cycle's timing
 * as the server stamped it.
 *
 * `PROCIMG_ERR_TIMEOUT` when no STARTOP came, `PROCIMG_ERR_SERVER_GONE` when the server is
 * gone (the client re-attaches by itself while waiting), `PROCIMG_ERR_WRONG_ROLE` for an
 * asynchronous client. Other events that arrive meanwhile wait for `procimg_next_event`.
 *
 * # Safety
 * `client` is NULL or a live handle; `info` is NULL or writable.
 */
procimg_error_t procimg_wait_startop(procimg_client_t *client,
                                     uint32_t timeout_ms,
                                     procimg_cycle_info_t *info);

/**
 * The whole input data (the I area) in place in shared memory, without a copy: `*data`
 * points to `*len` bytes, read-only. Inside a STARTOP window they are this cycle's inputs,
 * valid until the next `procimg_wait_startop` or `procimg_detach` (see the pointer rules at
 * the top of this header for the calls that take a newer image); outside a window they are
 * the newest image's, taken now.
 *
 * # Safety
 * `client` is NULL or a live handle; `data` and `len` are NULL or writable.
 */
procimg_error_t procimg_inputs(procimg_client_t *client, const uint8_t **data, size_t *len);

/**
 * The inputs of submodule `submodule` in place, as `procimg_inputs` (same validity).
 * `*len` is the submodule's input length (0 for a submodule without inputs).
 *
 * # Safety
 * `client` is NULL or a live handle; `data` and `len` are NULL or writable.
 */
procimg_error_t procimg_input(procimg_client_t *client,
                              size_t submodule,
                              const uint8_t **data,
                              size_t *len);

/**
 * The whole output data of this cycle (the Q area of the output sample this client sends
 * with its OPDONE), writable in place: `*data` points to `*len` bytes that start as the
 * outputs last sent. Every submodule this client has claimed is marked written with local
 * status GOOD; bytes of submodules it has not claimed are ignored by the server. Valid until
 * `procimg_set_opdone`, the next `procimg_wait_startop` or `procimg_detach`.
 *
 * `PROCIMG_ERR_NOT_IN_CYCLE` outside a window, `PROCIMG_ERR_WRONG_ROLE` for an asynchronous
 * client, `PROCIMG_ERR_NOT_DELIVERED` when no output sample is free.
 *
 * # Safety
 * `client` is NULL or a live handle; `data` and `len` are NULL or writable.
 */
procimg_error_t procimg_outputs(procimg_client_t *client, uint8_t **data, size_t *len);

/**
 * The outputs of submodule `submodule` for this cycle, writable in place (as
 * `procimg_outputs`, same validity): `*len` is its output length. Marks them written with
 * local status GOOD. `PROCIMG_ERR_NOT_CLAIMED` when this client has not claimed them.
 *
 * # Safety
 * `client` is NULL or a live handle; `data` and `len` are NULL or writable.
 */
procimg_error_t procimg_output(procimg_client_t *client,
                               size_t submodule,
                               uint8_t **data,
                               size_t *len);

/**
 * The status bytes of submodule `submodule`: this cycle's inside a window, the newest
 * image's outside.
 *
 * # Safety
 * `client` is NULL or a live handle; `status` is NULL or writable.
 */
procimg_error_t procimg_submodule_status(procimg_client_t *client,
                                         size_t submodule,
                                         procimg_submodule_ioxs_t *status);

/**
 * Sets the local status (IOPS) sent with submodule `submodule`'s outputs in this cycle
 * (`PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`); marks them written. Needs a window and the
 * claim.
 *
 * # Safety
 * `client` is NULL or a live handle.
 */
procimg_error_t procimg_set_output_status(procimg_client_t *client,
                                          size_t submodule,
                                          uint8_t local);

/**
 * Sends this cycle's outputs and signals OPDONE (IO-Base `PNIO_CP_set_opdone`), closing
 * the window. `*info` (when not NULL) gets the cycle info at OPDONE time: its
 * `since_cycle_start_ns` minus the one from `procimg_wait_startop` is the time this cycle
 * took. Output pointers of the window are invalid afterwards.
 *
 * `PROCIMG_ERR_NOT_IN_CYCLE` without a window or when the window is over (outputs not
 * sent), `PROCIMG_ERR_WRONG_ROLE` for an asynchronous client.
 *
 * # Safety
 * `client` is NULL or a live handle; `info` is NULL or writable.
 */
procimg_error_t procimg_set_opdone(procimg_client_t *client, procimg_cycle_info_t *info);

/**
 * Reads inputs at logical address `address` (IO-Base `PNIO_data_read`): copies
 * `min(len, *data_len)` bytes into `buf`, where `*data_len` is the number of bytes from the
 * address to the end of its submodule (with slice access; the whole submodule without).
 * `local` is the local status (IOCS) to send for these inputs, `PROCIMG_IOXS_GOOD` or
 * `PROCIMG_IOXS_BAD`; `*remote` (when not NULL) gets the device's IOPS.
 *
 * Inside a window it reads this cycle's inputs; outside, the newest image.
 * `PROCIMG_ERR_UNKNOWN_ADDRESS` when no submodule has the address.
 *
 * # Safety
 * `client` is NULL or a live handle; `buf` is NULL (only with `len` 0) or `len` writable
 * bytes; `data_len` is NULL or writable; `remote` is NULL or writable.
 */
procimg_error_t procimg_data_read(procimg_client_t *client,
                                  uint32_t address,
                                  uint8_t *buf,
                                  size_t len,
                                  size_t *data_len,
                                  uint8_t local,
                                  uint8_t *remote);

/**
 * Reads back outputs at logical address `address` as they were last sent (IO-Base
 * `PNIO_output_data_read`), with the `*data_len` rule of `procimg_data_read`. `*local` gets
 * the local status (IOPS) they were sent with, `*remote` the device's IOCS; either may be
 * NULL. Inside a window it reads what this cycle's image reports as sent.
 *
 * # Safety
 * As `procimg_data_read`; `local` is NULL or writable.
 */
procimg_error_t procimg_output_data_read(procimg_client_t *client,
                                         uint32_t address,
                                         uint8_t *buf,
                                         size_t len,
                                         size_t *data_len,
                                         uint8_t *local,
                                         uint8_t *remote);

/**
 * Writes `len` bytes of outputs at logical address `address` (IO-Base `PNIO_data_write`)
 * with local status `local` (IOPS, `PROCIMG_IOXS_GOOD` or `PROCIMG_IOXS_BAD`); `*remote`
 * (when not NULL) gets the device's IOCS, which refers to the previous cycle's outputs.
 *
 * Inside a window the bytes go into this cycle's output sample, sent with
 * `procimg_set_opdone`; outside, they are sent at once in a sample of their own, applied
 * whole in one cycle. `PROCIMG_ERR_LENGTH` when `len` does not fit the submodule (without
 * slice access it must be the whole submodule), `PROCIMG_ERR_NOT_CLAIMED` without the claim.
 *
 * # Safety
 * `client` is NULL or a live handle; `buf` is NULL (only with `len` 0) or `len` readable
 * bytes; `remote` is NULL or writable.
 */
procimg_error_t procimg_data_write(procimg_client_t *client,
                                   uint32_t address,
                                   const uint8_t *buf,
                                   size_t len,
                                   uint8_t local,
                                   uint8_t *remote);

/**
 * Copies the newest input image into the read cache (IO-Base
 * `PNIO_data_read_cache_refresh`), for `procimg_read_cache`. Takes a newer image.
 *
 * # Safety
 * `client` is NULL or a live handle.
 */
procimg_error_t procimg_read_cache_refresh(procimg_client_t *client);

/**
 * Reads inputs from the read cache (IO-Base `PNIO_data_read_cache`), as
 * `procimg_data_read`; `local` goes out with the next `procimg_write_cache_flush`.
 * `PROCIMG_ERR_NO_IMAGE` before the first `procimg_read_cache_refresh`.
 *
 * # Safety
 * As `procimg_data_read`.
 */
procimg_error_t procimg_read_cache(procimg_client_t *client,
                                   uint32_t address,
                                   uint8_t *buf,
                                   size_t len,
                                   size_t *data_len,
                                   uint8_t local,
                                   uint8_t *remote);

/**
 * Writes outputs into the write cache (IO-Base `PNIO_data_write_cache`), as
 * `procimg_data_write`; they go out with the next `procimg_write_cache_flush`. `*remote`
 * comes from the read cache (BAD before the first refresh). It may take a newer image: a
 * submodule's first cached write starts from its outputs as last sent.
 *
 * # Safety
 * As `procimg_data_write`.
 */
procimg_error_t procimg_write_cache(procimg_client_t *client,
                                    uint32_t address,
                                    const uint8_t *buf,
                                    size_t len,
                                    uint8_t local,
                                    uint8_t *remote);

/**
 * Sends everything in the write cache in one sample, applied by the server in one cycle
 * (IO-Base `PNIO_data_write_cache_flush`). Nothing to send is no error.
 *
 * # Safety
 * `client` is NULL or a live handle.
 */
procimg_error_t procimg_write_cache_flush(procimg_client_t *client);

/**
 * Asks the server for mode `mode` (`PROCIMG_MODE_OFFLINE`, `_CLEAR`, `_OPERATE`; IO-Base
 * `PNIO_set_mode`). Returns at once; the change is confirmed by `PROCIMG_EVENT_MODE` events,
 * one per step. `PROCIMG_ERR_REFUSED` while the previous change is not confirmed yet.
 *
 * # Safety
 * `client` is NULL or a live handle.
 */
procimg_error_t procimg_set_mode(procimg_client_t *client, uint32_t mode);

/**
 * The server's mode: in this cycle's image inside a window, in the newest image outside.
 *
 * # Safety
 * `client` is NULL or a live handle; `mode` is NULL or writable.
 */
procimg_error_t procimg_mode(procimg_client_t *client, uint32_t *mode);

/**
 * Takes the next event: `PROCIMG_OK` with `*event` filled, or `PROCIMG_ERR_NO_EVENT` (not a
 * failure; the last error text is left alone) when none is pending. Never waits: poll
 * `procimg_event_fd` to sleep until the server signals. Inside a STARTOP window it hands out
 * only events already collected (asking the server could take a newer image, which would end
 * the window); the rest follow after `procimg_set_opdone`.
 *
 * # Safety
 * `client` is NULL or a live handle; `event` is NULL or writable.
 */
procimg_error_t procimg_next_event(procimg_client_t *client, procimg_event_t *event);

/**
 * A descriptor that becomes readable when the server signals this client (STARTOP, mode,
 * OPFAULT, NEWCYCLE, shutdown): `poll` it, then call `procimg_next_event` or
 * `procimg_wait_startop` with timeout 0. Do not read from or close it. It changes when the
 * client re-attaches (`PROCIMG_EVENT_REATTACHED`); `PROCIMG_ERR_SERVER_GONE` while the server
 * is gone.
 *
 * # Safety
 * `client` is NULL or a live handle; `fd` is NULL or writable.
 */
procimg_error_t procimg_event_fd(procimg_client_t *client, int *fd);

#ifdef __cplusplus
}  // extern "C"
#endif  // __cplusplus

#endif  /* PROCIMG_H */
