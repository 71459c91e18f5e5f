/* SPDX-License-Identifier: MIT OR Apache-2.0 */

#ifndef PROCIMG_SHM_H
#define PROCIMG_SHM_H

/* Generated from shm-layout/src by cbindgen: do not edit. Regenerate with
 * PROCIMG_BLESS=1 cargo test -p procimg-shm-layout --test c_header */

#include <stdint.h>
#include <stddef.h>

/**
 * The inputs of a new cycle are published: process them (IO-Base STARTOP).
 */
#define PROCIMG_EVENT_STARTOP 1

/**
 * The outputs of the cycle went out and a new bus cycle begins (IO-Base NEWCYCLE).
 */
#define PROCIMG_EVENT_NEWCYCLE 2

/**
 * The server's mode changed (IO-Base MODE_IND); the new mode is in the next image header.
 */
#define PROCIMG_EVENT_MODE 3

/**
 * The server is shutting down; clients should expect a restart.
 */
#define PROCIMG_EVENT_SHUTDOWN 4

/**
 * OPFAULT for the client in slot `s` is `EVENT_OPFAULT_BASE + s`.
 */
#define PROCIMG_EVENT_OPFAULT_BASE 16



/**
 * Largest IO data of one submodule in one direction: a PROFINET frame carries at most 1440
 * bytes of IO data and status, so one submodule can have at most 1439 bytes plus its IOPS.
 */
#define PROCIMG_MAX_SUBMODULE_DATA_LEN 1439

/**
 * "PROCIMG1" as the bytes of a little-endian `u64`: the first field of every header.
 */
#define PROCIMG_IMAGE_MAGIC 3550891808262148688

/**
 * Version of this layout. Raised on every incompatible change of a shared type.
 */
#define PROCIMG_LAYOUT_VERSION 2

/**
 * Most clients attached to one server instance at the same time.
 */
#define PROCIMG_MAX_CLIENTS 64

/**
 * Mode changes an image header remembers.
 */
#define PROCIMG_MODE_HISTORY 4

/**
 * A logical address field that holds no address (the submodule has no data in that space).
 */
#define PROCIMG_NO_ADDRESS 4294967295

/**
 * Nanoseconds of one `CycleInfo::cycle_count` unit (the PROFINET base clock, 31.25 µs).
 */
#define PROCIMG_CYCLE_COUNT_UNIT_NS 31250

/**
 * Bytes of a station name field, NUL-padded (PROFINET NameOfStation is at most 240).
 */
#define PROCIMG_STATION_NAME_LEN 240

/**
 * The server is an IO controller: the image's inputs come from its devices, its outputs
 * go to them (`LayoutHeader::role`).
 */
#define ROLE_CONTROLLER 0

/**
 * The server is an IO device: the server-written part of the image (the submodule table's
 * `input_*` fields) carries the output data the PLC wrote (Q), the client-written part
 * (`output_*`) the device's input data that the PLC reads (I). Directions are named from
 * the PLC's view, as in IO-Base's device interface.
 */
#define ROLE_DEVICE 1

/**
 * Mode OFFLINE: no IO data is exchanged with the devices.
 */
#define PROCIMG_MODE_OFFLINE 0

/**
 * Mode CLEAR: the devices are connected, outputs go out marked invalid.
 */
#define PROCIMG_MODE_CLEAR 1

/**
 * Mode OPERATE: outputs go out valid.
 */
#define PROCIMG_MODE_OPERATE 2

/**
 * IOPS/IOCS value GOOD (DataState bit set, detected by the subslot).
 */
#define PROCIMG_IOXS_GOOD 128

/**
 * IOPS/IOCS value BAD, detected by the subslot.
 */
#define PROCIMG_IOXS_BAD 0

/**
 * IOPS/IOCS value BAD, detected by the IO controller (device failed, client late, mode CLEAR).
 */
#define PROCIMG_IOXS_BAD_BY_CONTROLLER 96

/**
 * IOPS/IOCS value BAD, detected by the IO device: what a server in the device role sends
 * for data no client provides (no owner, client late, mode CLEAR).
 */
#define IOXS_BAD_BY_DEVICE 64

/**
 * `ClientSubmoduleStatus::flags`: the client wrote this submodule's output data.
 */
#define PROCIMG_CLIENT_WROTE_OUTPUTS 1

/**
 * `ClientSubmoduleStatus::flags`: `output_iops` is set.
 */
#define PROCIMG_CLIENT_SET_OUTPUT_IOPS 2

/**
 * `ClientSubmoduleStatus::flags`: `input_iocs` is set.
 */
#define PROCIMG_CLIENT_SET_INPUT_IOCS 4

/**
 * `OutputHeader::flags`: the sample is this client's OPDONE for `OutputHeader::cycle_number`.
 */
#define PROCIMG_OUTPUT_SYNCHRONOUS 1

/**
 * `SubmoduleEntry::rt_class` of RT class 1 (unsynchronised) data.
 */
#define PROCIMG_RT_CLASS_1 1

/**
 * `SubmoduleEntry::rt_class` of RT class 3 (IRT) data.
 */
#define PROCIMG_RT_CLASS_3 3

/**
 * The cycle's timing, as IO-Base's `PNIO_CYCLE_INFO` but in nanoseconds.
 */
typedef struct {
  /**
   * Cycle index k since the server started (cycle k starts at epoch + k·T).
   */
  uint64_t cycle_number;
  /**
   * `CLOCK_MONOTONIC` time, in ns, at which cycle k was due to start.
   */
  uint64_t cycle_start_ns;
  /**
   * Free-running clock (`CLOCK_MONOTONIC`, ns) when this info was stamped.
   */
  uint64_t clock_ns;
  /**
   * `clock_ns - cycle_start_ns`.
   */
  uint64_t since_cycle_start_ns;
  /**
   * Cycle counter in 31.25 µs units, 16 significant bits: +32 per 1 ms cycle.
   */
  uint32_t cycle_count;
  /**
   * Reserved, zero.
   */
  uint32_t reserved;
} procimg_cycle_info_t;

/**
 * The iceoryx2 user header of every input-image sample.
 */
typedef struct {
  /**
   * [`IMAGE_MAGIC`].
   */
  uint64_t magic;
  /**
   * [`LAYOUT_VERSION`].
   */
  uint32_t layout_version;
  /**
   * `size_of::<ImageHeader>()`.
   */
  uint32_t header_size;
  /**
   * [`crate::layout_hash`] of the layout this image follows.
   */
  uint64_t layout_hash;
  /**
   * Identifies one run of the server; changes when the server restarts.
   */
  uint64_t generation;
  /**
   * This cycle's timing.
   */
  procimg_cycle_info_t cycle;
  /**
   * Current mode ([`MODE_OFFLINE`], [`MODE_CLEAR`], [`MODE_OPERATE`]).
   */
  uint32_t mode;
  /**
   * Number of submodules in the layout.
   */
  uint32_t submodule_count;
  /**
   * Bytes of the sample's payload.
   */
  uint32_t payload_size;
  /**
   * Mode changes since the server started; the mode after change n is
   * `mode_history[n % MODE_HISTORY]`, so a client that missed MODE events can replay
   * every step it did not see.
   */
  uint32_t mode_changes;
  /**
   * Cycle time in ns.
   */
  uint64_t cycle_ns;
  /**
   * OPDONE deadline, in ns after the cycle start.
   */
  uint64_t opdone_deadline_ns;
  /**
   * For each client slot, the last cycle in which that client got OPFAULT (0: never).
   */
  uint64_t opfault_cycle[PROCIMG_MAX_CLIENTS];
  /**
   * The modes after the last [`MODE_HISTORY`] changes (see `mode_changes`).
   */
  uint32_t mode_history[PROCIMG_MODE_HISTORY];
} procimg_image_header_t;

/**
 * One IO device of the IO system.
 */
typedef struct {
  /**
   * NameOfStation, NUL-padded.
   */
  uint8_t station_name[PROCIMG_STATION_NAME_LEN];
  /**
   * PROFINET vendor ID.
   */
  uint16_t vendor_id;
  /**
   * PROFINET device ID.
   */
  uint16_t device_id;
  /**
   * Device instance.
   */
  uint16_t instance;
  /**
   * Reduction ratio of this device's IO CRs (cycles per frame).
   */
  uint16_t reduction_ratio;
  /**
   * IPv4 address, network byte order.
   */
  uint8_t ip_address[4];
  /**
   * Index of the device's first entry in the submodule table.
   */
  uint32_t first_submodule;
  /**
   * Number of submodule table entries of this device.
   */
  uint32_t submodule_count;
  /**
   * Watchdog factor (DataHoldFactor) of the consumer CR.
   */
  uint16_t watchdog_factor;
  /**
   * Reserved, zero.
   */
  uint16_t reserved;
} procimg_device_entry_t;

/**
 * One submodule of the process image.
 */
typedef struct {
  /**
   * Index of the device in the device table.
   */
  uint16_t device;
  /**
   * Slot number.
   */
  uint16_t slot;
  /**
   * Subslot number.
   */
  uint16_t subslot;
  /**
   * RT class of its data ([`RT_CLASS_1`], [`RT_CLASS_3`]).
   */
  uint8_t rt_class;
  /**
   * Reserved, zero.
   */
  uint8_t reserved0;
  /**
   * Application process identifier.
   */
  uint32_t api;
  /**
   * Module ident number.
   */
  uint32_t module_ident;
  /**
   * Submodule ident number.
   */
  uint32_t submodule_ident;
  /**
   * First logical address in the input (I) space, or [`NO_ADDRESS`]. A submodule
   * without any IO data has its diagnostic address here (input and output length 0).
   */
  uint32_t input_address;
  /**
   * First logical address in the output (Q) space, or [`NO_ADDRESS`].
   */
  uint32_t output_address;
  /**
   * Bytes of input data.
   */
  uint16_t input_length;
  /**
   * Bytes of output data.
   */
  uint16_t output_length;
  /**
   * Offset of the input data in the input-image payload.
   */
  uint32_t input_offset;
  /**
   * Offset of the output data in an output-sample payload.
   */
  uint32_t output_offset;
  /**
   * Offset of the output data's mirror in the input-image payload. The mirror is not
   * packed: in the controller role each device's outputs lie in its output frame, which
   * the mirror holds whole (header and status bytes between the outputs), so that the
   * frame is sent from the image. Read each submodule at its own offset.
   */
  uint32_t output_mirror_offset;
  /**
   * Offset in the input-image payload of this submodule's [`SubmoduleStatus`].
   */
  uint32_t status_offset;
  /**
   * Offset in an output-sample payload of this submodule's [`ClientSubmoduleStatus`].
   */
  uint32_t client_status_offset;
  /**
   * Reserved, zero.
   */
  uint32_t reserved1;
  /**
   * Reserved, zero.
   */
  uint32_t reserved2;
  /**
   * Reserved, zero.
   */
  uint32_t reserved3;
} procimg_submodule_entry_t;
/**
 * An entry with every field zero except the addresses, which hold [`NO_ADDRESS`].
 */
#define procimg_submodule_entry_t_EMPTY (procimg_submodule_entry_t){ .device = 0, .slot = 0, .subslot = 0, .rt_class = PROCIMG_RT_CLASS_1, .reserved0 = 0, .api = 0, .module_ident = 0, .submodule_ident = 0, .input_address = PROCIMG_NO_ADDRESS, .output_address = PROCIMG_NO_ADDRESS, .input_length = 0, .output_length = 0, .input_offset = 0, .output_offset = 0, .output_mirror_offset = 0, .status_offset = 0, .client_status_offset = 0, .reserved1 = 0, .reserved2 = 0, .reserved3 = 0 }

/**
 * The status bytes of one submodule in the input image, as exchanged in the cycle.
 */
typedef struct {
  /**
   * Remote status of the inputs: the device's IOPS.
   */
  uint8_t input_iops;
  /**
   * Local status of the inputs as sent to the device: our IOCS.
   */
  uint8_t input_iocs;
  /**
   * Local status of the outputs as sent to the device: our IOPS.
   */
  uint8_t output_iops;
  /**
   * Remote status of the outputs: the device's IOCS for the previous cycle's outputs.
   */
  uint8_t output_iocs;
} procimg_submodule_status_t;

/**
 * What a client sets for one submodule in an output sample.
 */
typedef struct {
  /**
   * Local status for the outputs (IOPS), valid with [`CLIENT_SET_OUTPUT_IOPS`].
   */
  uint8_t output_iops;
  /**
   * Local status for the inputs (IOCS), valid with [`CLIENT_SET_INPUT_IOCS`].
   */
  uint8_t input_iocs;
  /**
   * `CLIENT_*` flags.
   */
  uint8_t flags;
  /**
   * Reserved, zero.
   */
  uint8_t reserved;
} procimg_client_submodule_status_t;

/**
 * The iceoryx2 user header of the layout sample.
 */
typedef struct {
  /**
   * [`IMAGE_MAGIC`].
   */
  uint64_t magic;
  /**
   * [`LAYOUT_VERSION`].
   */
  uint32_t layout_version;
  /**
   * `size_of::<LayoutHeader>()`.
   */
  uint32_t header_size;
  /**
   * [`crate::layout_hash`] of this layout.
   */
  uint64_t layout_hash;
  /**
   * Identifies one run of the server.
   */
  uint64_t generation;
  /**
   * Cycle time in ns.
   */
  uint64_t cycle_ns;
  /**
   * OPDONE deadline, in ns after the cycle start.
   */
  uint64_t opdone_deadline_ns;
  /**
   * Entries in the device table.
   */
  uint32_t device_count;
  /**
   * Entries in the submodule table.
   */
  uint32_t submodule_count;
  /**
   * Bytes of input data.
   */
  uint32_t input_size;
  /**
   * Bytes of output data.
   */
  uint32_t output_size;
  /**
   * Bytes of an input-image payload.
   */
  uint32_t input_payload_size;
  /**
   * Bytes of an output-sample payload.
   */
  uint32_t output_payload_size;
  /**
   * Offset of the device table in the layout payload.
   */
  uint32_t device_table_offset;
  /**
   * Offset of the submodule table in the layout payload.
   */
  uint32_t submodule_table_offset;
  /**
   * Offset of the status array in the input-image payload.
   */
  uint32_t status_offset;
  /**
   * Offset of the output mirror in the input-image payload: where it starts. Its
   * submodules are not packed (see `SubmoduleEntry::output_mirror_offset`).
   */
  uint32_t output_mirror_offset;
  /**
   * Offset of the client status array in an output-sample payload.
   */
  uint32_t client_status_offset;
  /**
   * The PROFINET role of the server: [`ROLE_CONTROLLER`] or [`ROLE_DEVICE`].
   */
  uint32_t role;
} procimg_layout_header_t;

/**
 * The iceoryx2 user header of an output sample sent by a client.
 */
typedef struct {
  /**
   * [`IMAGE_MAGIC`].
   */
  uint64_t magic;
  /**
   * Layout hash the client wrote against.
   */
  uint64_t layout_hash;
  /**
   * The cycle these outputs belong to (synchronous), or the newest cycle seen (asynchronous).
   */
  uint64_t cycle_number;
  /**
   * Token the server gave the client at registration; samples with a stale token are dropped.
   */
  uint64_t client_token;
  /**
   * The client's slot.
   */
  uint32_t client_slot;
  /**
   * `OUTPUT_*` flags.
   */
  uint32_t flags;
  /**
   * The client's `CLOCK_MONOTONIC` in ns when it sent the sample: the server measures the
   * OPDONE one-way latency from it.
   */
  uint64_t sent_ns;
} procimg_output_header_t;

#endif  /* PROCIMG_SHM_H */
