/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * pniousrx.h - the IO controller part of procimg's IO-Base compatible API (libprocimg).
 *
 * A program written for the SIMATIC NET IO-Base controller interface (PnioEasy, an
 * isochronous STARTOP/OPDONE program) compiles against this header and runs against a
 * procimgd server: link it with -lprocimg -lpthread -ldl -lm. Names, types, enum values and
 * error codes are those of the IO-Base manual and its 2015 interface. Written for procimg;
 * what follows is how procimg answers the questions the manual leaves open.
 *
 * CP and server. CpIndex n (1..255) names a procimgd instance: the environment variable
 * PROCIMG_CP<n> (PROCIMG_CP1 for CpIndex 1) if set, else PROCIMG_INSTANCE, else "procimg".
 * CpIndex 0 or above 255 gives PNIO_ERR_PRM_CP_ID; no server under that name gives
 * PNIO_ERR_NO_CONFIG. Several controllers may be open at once (one handle each); handles
 * are never reused, so a closed handle gives PNIO_ERR_WRONG_HND.
 *
 * ExtPar. Only PNIO_CEP_MODE_CTRL and PNIO_CEP_SLICE_ACCESS are accepted (any other bit:
 * PNIO_ERR_PRM_EXT_PAR). With PNIO_CEP_MODE_CTRL the program controls the server's mode:
 * PNIO_controller_open asks the server for OFFLINE and returns once it is there (the
 * controller is OFFLINE after open, as the manual says; this takes the devices' connections
 * down). Without it the program only observes the mode the server is in (another program or
 * `procimg mode` sets it): PNIO_set_mode gives PNIO_ERR_SET_MODE_NOT_ALLOWED and
 * PNIO_device_activate PNIO_ERR_DEV_ACT_NOT_ALLOWED, MODE_IND still reports every change,
 * and callbacks may be registered in any mode (the OFFLINE rule exists so that a program
 * registers before it changes its own mode, which such a program never does).
 * PNIO_controller_close leaves the server's mode as it is: set OFFLINE first, as the
 * manual's programs do.
 *
 * Outputs. The controller owns every output submodule of the IO system: open claims them
 * all, and if another program already holds one, open fails with PNIO_ERR_MAX_REACHED (the
 * server's one controller is taken; procimg status names the holder). In OFFLINE the
 * outputs written are lost; after OPERATE is reached write all outputs again.
 *
 * Modes. PNIO_set_mode returns at once; PNIO_CBE_MODE_IND (which must be registered, else
 * PNIO_ERR_SEQUENCE) reports every step: OFFLINE -> OPERATE reports CLEAR, then OPERATE, and
 * OPERATE -> OFFLINE reports CLEAR, then OFFLINE. A second PNIO_set_mode before the mode
 * asked for was reported gives PNIO_ERR_SEQUENCE. Asking for the mode the controller is in
 * reports that mode once.
 *
 * IO data. PNIO_data_read, PNIO_data_write and the cached functions check their parameters
 * in the manual's order (handle, buffer, IODataType, address type, IOlocState, pDataLen,
 * pIOremState, address, length). Without PNIO_CEP_SLICE_ACCESS an access must start at
 * the submodule's first address and a write must be the whole submodule; with it, any
 * part. PNIO_ERR_NO_CONNECTION: the submodule's device is not in data exchange (the
 * controller is OFFLINE, the device failed or is deactivated: *pIOremState is then BAD) or
 * the server is gone. The functions are thread-safe and serialised inside the library.
 *
 * Addresses of records and alarms. A record job or PNIO_device_activate takes any address
 * of the submodule or device. A submodule without IO data (a DAP, interface or port) is
 * named by its diagnostic address, an input address of length 0 (key diagnostic_address of
 * the server's configuration, else assigned after all inputs): record jobs on it take
 * PNIO_IO_IN, and CONFIG_SUBMODULE_LIST lists it with DataLength 0. Alarms name the
 * submodule they come from; station failure and return name the device by its DAP's
 * diagnostic address (for a device configured without a DAP: its lowest input address,
 * else its lowest output address).
 *
 * Device state. PNIO_ctrl_diag_req(PNIO_CTRL_DIAG_DEVICE_STATE) gives the Reason from the
 * kind of failure the server reports: IOD_NOT_FOUND (no answer to DCP Identify),
 * IP_SET_ABORTED (DCP Set failed, or no IP address), RPC_TIMEOUT (no answer to an RPC call,
 * no ApplicationReady), RPC_ERROR (refused or unreadable RPC), PNIO_CONFIGURATION (the
 * device refused Connect, Write or PrmEnd), MISS (cyclic data stopped), IOD_ABORTED (the
 * device aborted the AR), IOC_ABORTED (the controller aborted or released it),
 * MP_DEVICE_DISABLED (deactivated). DEVICE_DIAGNOSTIC gives Mode and, of the device's last
 * failure (0 while it runs): ErrorCause, the CM error cause (the low byte of that Reason + 1:
 * 7 RPC_TIMEOUT, 9 IOD_NOT_FOUND, 11 MISS, 14 IOD_ABORTED, ...; big-endian in memory);
 * ReasonCode, the abort code of an AR ended by an ERR-RTA (ErrorCode2 of CF 81 FD xx, e.g.
 * 0x05 when the server's watchdog expired), else 0; AdditionalInfo[0..3], the failure's PNIO
 * status (ErrorCode, ErrorDecode, ErrorCode1, ErrorCode2) when it has one (a refusal, an
 * abort).
 *
 * Isochronous mode. Registering PNIO_CP_CBE_STARTOP_IND (after PNIO_CP_CBE_OPFAULT_IND,
 * else PNIO_ERR_OPFAULT_NOT_REG; PNIO_CP_CBE_NEWCYCLE_IND only before it, else
 * PNIO_ERR_NEWCYCLE_SEQUENCE_REG) makes the controller take part in the server's cycle handshake:
 * STARTOP_IND comes every cycle, on a thread of the library, from then on (also in OFFLINE).
 * Between STARTOP_IND and PNIO_CP_set_opdone, data_read and data_write act on this cycle's
 * consistent image, and the outputs written go out with PNIO_CP_set_opdone. The window's
 * rules hold for IRT data: the submodules configured with rt_class = 3 (CONFIG_SUBMODULE_LIST
 * says PNIO_DATA_IRT for them). Outside the window data_read and data_write of IRT data still
 * work but return PNIO_WARN_IRT_INCONSISTENT, and the cached functions are passed to them
 * (as the manual does for IRT data). RT data (rt_class = 1) is accessed as by a controller
 * that is not isochronous: PNIO_OK outside the window too, and data_read_cache_refresh and
 * data_write_cache_flush move it (procimg sends both kinds in RT frames of its cycle; the
 * window is what makes IRT data consistent with the cycle). OPFAULT_IND reports a
 * PNIO_CP_set_opdone that came too late (those outputs were not used); a late
 * PNIO_CP_set_opdone still returns PNIO_OK, and one without an open window (twice in a
 * cycle, before the first STARTOP_IND) gives PNIO_ERR_SEQUENCE.
 * PNIO_CYCLE_INFO: CycleCount in 31.25 us units (16 bits, +32 per 1 ms cycle), ClockCount
 * and CountSinceCycleStart in 10 ns units, taken when the event is delivered and when
 * PNIO_CP_set_opdone is called.
 *
 * Callbacks run on threads of the library, never inside an API call on the caller's thread.
 * Inside a callback only the IO data functions (PNIO_data_read, PNIO_output_data_read,
 * PNIO_data_read_cache_refresh, PNIO_data_read_cache, PNIO_data_write,
 * PNIO_data_write_cache, PNIO_data_write_cache_flush), PNIO_CP_set_opdone and
 * PNIO_CP_trigger_watchdog may be called; every other function returns PNIO_ERR_SEQUENCE there (including PNIO_controller_close).
 * Callbacks may still run while PNIO_controller_close runs; none runs after it returned.
 * PNIO_controller_open starts the controller's threads, and they take the scheduling policy,
 * priority and CPU affinity of the thread that calls it: an isochronous program raises that
 * thread to SCHED_FIFO (below procimgd's cycle thread) before the call, and its STARTOP
 * callback runs at that priority.
 *
 * Errors. Besides the code, a failing call leaves a text for the calling thread saying what
 * went wrong and what to do: procimg_last_error() in procimg.h.
 *
 * PN Driver. A PN Driver program starts its own stack first (SERV_CP_init,
 * SERV_CP_startup: servusrx.h); between SERV_CP_init and SERV_CP_startup, and after
 * SERV_CP_shutdown, PNIO_controller_open gives PNIO_ERR_SEQUENCE.
 *
 * Tailoring (PNIO_iosystem_reconfig). The configuration marks devices `optional = true`
 * and ports `programmable = true` in their `[[device.topology]]`; an optional device stays
 * deactivated until a TAILOR names it. The call checks the handle (PNIO_ERR_WRONG_HND), the
 * open (without PNIO_CEP_MODE_CTRL: PNIO_ERR_DEV_ACT_NOT_ALLOWED), Mode (PNIO_ERR_MODE_VALUE,
 * the manual's code, where PN Driver's headers give PNIO_ERR_PRM_TYPE), a reconfiguration
 * under way (PNIO_ERR_NOT_REENTERABLE), a count above 0 with a NULL list (PNIO_ERR_PRM_BUF)
 * and that every address is the program's (PNIO_ERR_PRM_ADD). Then every device is taken
 * down, each port of a pair gets its neighbour (the other port's station and "port-00N")
 * as its PDPortDataCheck, written at connect, and the mandatory devices and the optional
 * ones listed come up. PNIO_CBE_IOSYSTEM_RECONFIG (register it first; else
 * PNIO_ERR_SEQUENCE) says Mode PNIO_DA_TRUE after a TAILOR, PNIO_DA_FALSE after a DEACT,
 * and Status PNIO_OK, or PNIO_ERR_INVALID_STATION (a device listed is not optional) or
 * PNIO_ERR_INVALID_PORT (a port has no programmable peer, or is joined twice) with pAddr
 * the address that named it: then nothing was changed. These are PN Driver's names; the
 * manual's TAILOR_INV_STATION and TAILOR_INV_PORT have no value anywhere.
 *
 * The controller's station. On a real interface procimgd's controller answers DCP as a
 * station of its own (DeviceRole IO controller, its NameOfStation, IP suite, type of station
 * "procimg controller", the alias its LLDP neighbour gives it): engineering tools find it.
 * A DCP Signal to it gives every controller program PNIO_CBE_START_LED_FLASH (Frequency
 * 2 Hz) and, three seconds later, PNIO_CBE_STOP_LED_FLASH; another Signal meanwhile
 * extends the flashing. Its name and IP suite are the configuration's unless [interface]
 * lets programs change them (name_by_program, address_by_program): then
 * PNIO_interface_set_ip_and_nos and a DCP Set from an engineering tool change them (the
 * address on the Linux interface too), and every PNIO_interface_open handle hears of a
 * DCP change as PNIO_CBE_IFC_SET_ADDR_CONF; otherwise a DCP Set is refused and the call
 * confirmed with PNIO_ERR_SET_IP_NOS_NOT_ALLOWED. A reset to factory is always refused.
 *
 * The controller's own interface (PNIO_interface_*, PN Driver's chapter 10) is the
 * interface submodule 0x8000 and its port 0x8001 in slot 0, named by the diagnostic
 * addresses of [interface] (default 16382 and 16381, PNIO_IO_IN). Their records:
 * PDInterfaceDataReal 0x8080, PDPortDataReal 0x802A, PDPortStatistic 0x8072, PDRealData
 * 0xF841, the port's expected PDPortDataCheck 0x802B, and their diagnosis (0x800A ...
 * 0x8013, 0xC00A ... 0xC013, 0xF80C); another index is refused by the interface with
 * PNIORW "invalid index" (ErrCode 0xDE, ErrDecode 0x80, ErrCode1 0xB0), and AddValue1 holds
 * the call's PNIO result as PN Driver's samples test it. Its alarms: the port is checked
 * against the neighbour the configuration gives it (the device whose [[device.topology]]
 * names the controller's station and port-001) and, with check_link, against a link down;
 * a mismatch appears and disappears as PNIO_ALARM_PORT_DATA_CHANGED with its extended
 * channel diagnosis, one at a time.
 *
 * PROFIenergy. PNIO_pe_cmd_req writes the PE request to record 0x80A0 (PE_SAP_DR_INDEX) of
 * the submodule at pAddr and reads the answer from it, again while the device answers
 * "resource busy/unavailable", for at most PNIO_PE_SERVICE_REQ_LIFETIME_DEFAULT seconds;
 * the PE callback gets pe_hdr.state 1 and the member struct_id names for an answer, state 2
 * with RespNegative (struct_id PE_CNF_STRUCT_ID_ERROR) for the device's refusal, state 2
 * with struct_id 0 and Err for a command not carried out (IO-Base's "no connection" C0 80
 * A3 00 when the lifetime passed). PNIO_pe_cmd_req without a registered PE callback is
 * PNIO_ERR_SEQUENCE; an unknown CmdId or modifier PNIO_ERR_PRM_INVALIDARG; 16 commands and
 * record jobs open PNIO_ERR_NO_RESOURCE. procimg's own device role answers as a station
 * without energy-saving modes unless its program takes PE (pniousrd.h).
 *
 * Not here: PNIO_data_cache_exchange: procimg does not offer it yet. PNIO_CBE_CP_STOP_REQ
 * comes when the procimgd is to restart (a configuration download, a reset: servusrx.h):
 * close the controller, outside the callback; the restart waits up to 10 s for it. The CP
 * application watchdog (PNIO_CP_set_appl_watchdog, PNIO_CP_trigger_watchdog,
 * PNIO_CBF_APPL_WATCHDOG) is pniobase.h's, shared with the device side; what its expiry
 * does is said there.
 */
#ifndef PNIOUSRX_H
#define PNIOUSRX_H

#include "pniobase.h"
#include "pnioerrx.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Enums --------------------------------------------------------------------------- */

/* The controller's mode. */
typedef enum {
    PNIO_MODE_OFFLINE = 0, /* stop: no IO data, records or alarms */
    PNIO_MODE_CLEAR = 1,   /* IO data exchanged, outputs sent as invalid */
    PNIO_MODE_OPERATE = 2  /* normal operation */
} PNIO_MODE_TYPE;

/* Deactivate or activate a device. */
typedef enum {
    PNIO_DA_FALSE = 0, /* deactivate */
    PNIO_DA_TRUE = 1   /* activate */
} PNIO_DEV_ACT_TYPE;

/* The controller's callback events. ALARM_IND, REC_READ_CONF and REC_WRITE_CONF are
 * registered through PNIO_controller_open only, the others through PNIO_register_cbf. */
typedef enum {
    PNIO_CBE_MODE_IND = 1,          /* own mode changed */
    PNIO_CBE_ALARM_IND = 2,         /* an alarm arrived */
    PNIO_CBE_REC_READ_CONF = 3,     /* a record read finished */
    PNIO_CBE_REC_WRITE_CONF = 4,    /* a record write finished */
    PNIO_CBE_DEV_ACT_CONF = 5,      /* a device (de)activation finished */
    PNIO_CBE_CP_STOP_REQ = 6,       /* the server is to restart: close */
    PNIO_CBE_START_LED_FLASH = 7,   /* start flashing: DCP Signal to the controller's station */
    PNIO_CBE_STOP_LED_FLASH = 8,    /* stop flashing, 3 s later */
    PNIO_CBE_CTRL_DIAG_CONF = 9,    /* a diagnosis request finished */
    PNIO_CBE_IFC_SET_ADDR_CONF = 10, /* PN Driver only */
    PNIO_CBE_REMA_READ_CONF = 11,   /* PN Driver only */
    PNIO_CBE_IOSYSTEM_RECONFIG = 12,
    PNIO_CBE_IFC_REC_READ_CONF = 13, /* PN Driver only */
    PNIO_CBE_IFC_ALARM_IND = 14     /* PN Driver only */
} PNIO_CBE_TYPE;

/* The manual also spells the LED events with _IND. */
#define PNIO_CBE_START_LED_FLASH_IND PNIO_CBE_START_LED_FLASH
#define PNIO_CBE_STOP_LED_FLASH_IND PNIO_CBE_STOP_LED_FLASH

/* Modes of PNIO_iosystem_reconfig (which procimg does not offer). */
typedef enum {
    PNIO_IOS_RECONFIG_MODE_DEACT = 1,
    PNIO_IOS_RECONFIG_MODE_TAILOR = 2
} PNIO_IOS_RECONFIG_MODE;

/* The services of PNIO_ctrl_diag_req. */
typedef enum {
    PNIO_CTRL_DIAG_RESERVED = 0,
    PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST = 1,    /* PNIO_CTRL_DIAG_CONFIG_SUBMODULE[] */
    PNIO_CTRL_DIAG_DEVICE_STATE = 2,             /* PNIO_CTRL_DIAG_DEVICE */
    PNIO_CTRL_DIAG_CONFIG_IOROUTER_PRESENT = 3,  /* answer in DiagDataBufferLen */
    PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE_LIST = 4, /* PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE[] */
    PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO = 5,    /* PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA */
    PNIO_CTRL_DIAG_GET_COMM_COUNTER_DATA = 6,    /* PNIO_CTRL_COMM_COUNTER_DATA */
    PNIO_CTRL_DIAG_RESET_COMM_COUNTERS = 7,      /* the same, then the counters restart */
    PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC = 8         /* PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA */
} PNIO_CTRL_DIAG_ENUM;

/* ---- Device state (PNIO_CTRL_DIAG_DEVICE) ------------------------------------------- */

/* DiagState: a bit field. */
#define PNIO_CTRL_DEV_DIAG_OFFLINE 0x00000001        /* the device is offline */
#define PNIO_CTRL_DEV_DIAG_ADDR_INFO_OK 0x00000010   /* its address is resolved */
#define PNIO_CTRL_DEV_DIAG_AR_CONNECTING 0x00000100  /* its AR is being set up */
#define PNIO_CTRL_DEV_DIAG_AR_IN_DATA 0x00000200     /* its AR is in data exchange */
#define PNIO_CTRL_DEV_DIAG_AR_OFFLINE 0x00000400     /* its AR is offline: see Reason */
#define PNIO_CTRL_DEV_DIAG_AR_RTC3_FOLLOWS 0x00001000 /* its AR waits for RTC3 data */

/* Reason: why the device is not in data exchange. */
#define PNIO_CTRL_REASON_NONE 0x0000
/* Name and address resolution: */
#define PNIO_CTRL_REASON_NARE_ERR_MULTIPLE_IP_USE 0x0101
#define PNIO_CTRL_REASON_NARE_ERR_IP_IN_USE 0x0102
#define PNIO_CTRL_REASON_NARE_ERR_DCP_MULTIPLE_STATIONS 0x0103
#define PNIO_CTRL_REASON_NARE_ERR_DCP_SET_FAILED 0x0104
#define PNIO_CTRL_REASON_NARE_ERR_DCP_SET_TIMEOUT 0x0105
#define PNIO_CTRL_REASON_NARE_ERR_DCP_STATION_NOT_FOUND 0x0106
#define PNIO_CTRL_REASON_NARE_ERR_OPCODE 0x0107
#define PNIO_CTRL_REASON_NARE_ERR_CHANNEL_USE 0x0108
#define PNIO_CTRL_REASON_NARE_ERR_DNS_FAILED 0x0109
#define PNIO_CTRL_REASON_NARE_ERR_LL 0x010A
#define PNIO_CTRL_REASON_NARE_ERR_NO_OWN_IP 0x010B
#define PNIO_CTRL_REASON_NARE_ERR_DCP_IDENT_TLV_ERROR 0x010C
#define PNIO_CTRL_REASON_NARE_ERR_IP_RESOLVE_NO_ANSWER 0x010D
/* Connectionless RPC: */
#define PNIO_CTRL_REASON_CLRPC_ERR_FAULTED 0x0201
#define PNIO_CTRL_REASON_CLRPC_ERR_REJECTED 0x0202
#define PNIO_CTRL_REASON_CLRPC_ERR_IN_ARGS 0x0203
#define PNIO_CTRL_REASON_CLRPC_ERR_OUT_ARGS 0x0204
#define PNIO_CTRL_REASON_CLRPC_ERR_DECODE 0x0205
#define PNIO_CTRL_REASON_CLRPC_ERR_PNIO_OUT_ARGS 0x0206
#define PNIO_CTRL_REASON_CLRPC_ERR_TIMEOUT 0x0207
/* Address information classes: */
#define PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_LINK 0x0301
#define PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_MISS 0x0401
#define PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_COMPANION 0x0501
#define PNIO_CTRL_REASON_CM_ADDR_INFO_CLASS_OTHER 0x0601
/* Connection: */
#define PNIO_CTRL_REASON_ERR_MULTIPLE_IP_USE 0x0700
#define PNIO_CTRL_REASON_ERR_MULTIPLE_STATIONS 0x0701
#define PNIO_CTRL_REASON_REASON_LINK_DOWN 0x0702
#define PNIO_CTRL_REASON_MAU_MISMATCH 0x0703
#define PNIO_CTRL_REASON_RPC_ERROR 0x0704
#define PNIO_CTRL_REASON_PNIO_CONFIGURATION 0x0705
#define PNIO_CTRL_REASON_RPC_TIMEOUT 0x0706
#define PNIO_CTRL_REASON_IP_SET_ABORTED 0x0707
#define PNIO_CTRL_REASON_IOD_NOT_FOUND 0x0708
#define PNIO_CTRL_REASON_OUT_OF_RESOURCES 0x0709
#define PNIO_CTRL_REASON_MISS 0x070A
#define PNIO_CTRL_REASON_NOS_SET_ABORTED 0x070B
#define PNIO_CTRL_REASON_IOC_ABORTED 0x070C
#define PNIO_CTRL_REASON_IOD_ABORTED 0x070D
#define PNIO_CTRL_REASON_VENDORID_ABORTED 0x070E
#define PNIO_CTRL_REASON_MP_IN_PROGRESS 0x070F
#define PNIO_CTRL_REASON_MP_NOS_MISSING 0x0710
#define PNIO_CTRL_REASON_MP_IPv4_MISSING 0x0711
#define PNIO_CTRL_REASON_MP_NOS_INVALID 0x0712
#define PNIO_CTRL_REASON_MP_IPv4_INVALID 0x0713
#define PNIO_CTRL_REASON_MP_TAILORING_MISSING 0x0714
#define PNIO_CTRL_REASON_MP_PDEV_ERROR 0x0715
#define PNIO_CTRL_REASON_MP_DEVICE_DISABLED 0x0716

/* ---- Alarms -------------------------------------------------------------------------- */

/* An alarm as PNIO_CBE_ALARM_IND delivers it. */
typedef struct {
    PNIO_ALARM_TYPE AlarmType;      /* PNIO_ALARM_* */
    PNIO_APRIO_TYPE AlarmPriority;  /* PNIO_APRIO_* */
    PNIO_UINT16 DeviceNum;          /* station number */
    PNIO_UINT16 SlotNum;
    PNIO_UINT16 SubslotNum;
    PNIO_UINT16 CpuAlarmPriority;
    PNIO_UINT32 PnioCompatModtype;
    PNIO_ALARM_TINFO AlarmTinfo;    /* configuration details */
    PNIO_UINT8 DiagDs[4];           /* diagnosis bytes as in OB82 */
    PNIO_UINT8 PrAlarmInfo[4];      /* process alarm bytes */
    PNIO_ALARM_INFO AlarmAinfo;     /* the alarm notification and its user data */
} ATTR_PACKED PNIO_CTRL_ALARM_DATA;

/* ---- Diagnosis ----------------------------------------------------------------------- */

/* A diagnosis request. It belongs to the library from PNIO_ctrl_diag_req until its
 * PNIO_CBE_CTRL_DIAG_CONF has been delivered. */
typedef struct {
    PNIO_CTRL_DIAG_ENUM DiagService;
    union {
        PNIO_UINT32 Reserved1[8];
        PNIO_ADDR Addr; /* DEVICE_STATE, DEVICE_DIAGNOSTIC: an address of the device */
    } u;
    PNIO_REF ReqRef; /* yours, echoed in the confirmation's pDiagData */
    PNIO_UINT32 Reserved2;
} ATTR_PACKED PNIO_CTRL_DIAG;

/* CONFIG_SUBMODULE_LIST: DiagDataBufferLen / sizeof(PNIO_CTRL_DIAG_CONFIG_SUBMODULE)
 * elements. */
typedef struct {
    PNIO_ADDR Address;           /* logical address */
    PNIO_UINT32 DataLength;      /* bytes */
    PNIO_DATA_TYPE DataType;     /* RT or IRT */
    PNIO_COM_TYPE ComType;       /* unicast or direct data exchange */
    PNIO_UINT32 Api;
    PNIO_UINT32 ReductionFactor; /* sent every ReductionFactor cycles */
    PNIO_UINT32 Phase;           /* 0 .. ReductionFactor-1 */
    PNIO_UINT32 CycleTime;       /* send clock, 31.25 us units */
    PNIO_UINT32 Reserved1[2];
    PNIO_UINT32 StatNo;          /* station number */
    PNIO_UINT32 Slot;
    PNIO_UINT32 Subslot;
    PNIO_UINT32 Reserved2[2];
} ATTR_PACKED PNIO_CTRL_DIAG_CONFIG_SUBMODULE;

/* DEVICE_STATE. */
typedef struct {
    PNIO_DEV_ACT_TYPE Mode;  /* activated or not */
    PNIO_UINT32 DiagState;   /* PNIO_CTRL_DEV_DIAG_* bits */
    PNIO_UINT32 Reason;      /* PNIO_CTRL_REASON_* */
    PNIO_UINT32 Reserved1[12];
} ATTR_PACKED PNIO_CTRL_DIAG_DEVICE;

/* CONFIG_OUTPUT_SLICE_LIST: the output bits this program may write. */
typedef struct {
    PNIO_ADDR Address;
    PNIO_UINT16 BitOffset;
    PNIO_UINT16 BitLength;
} ATTR_PACKED PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE;

/* CONFIG_NAME_ADDR_INFO: the controller's own name and address (procimgd's station name,
 * its type "procimg controller", the interface's address and mask; the addresses in network
 * byte order, as struct in_addr holds them; default_router 0 when none is known). */
typedef struct {
    PNIO_UINT8 name[256];          /* station name, NUL-terminated */
    PNIO_UINT8 TypeOfStation[256]; /* NUL-terminated */
    PNIO_UINT32 ip_addr;
    PNIO_UINT32 ip_mask;
    PNIO_UINT32 default_router;
} ATTR_PACKED PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA;

/* DEVICE_DIAGNOSTIC: why a device's AR ended. */
typedef struct {
    PNIO_DEV_ACT_TYPE Mode;
    PNIO_UINT16 ErrorCause; /* big-endian */
    PNIO_UINT8 ReasonCode;
    PNIO_UINT8 AdditionalInfo[10];
} ATTR_PACKED PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA;

/* GET_COMM_COUNTER_DATA, RESET_COMM_COUNTERS: Ethernet counters of one port. procimg counts
 * the controller's interface as its one port (NumberOfPorts 1; 0 on the simulated network),
 * from the kernel's counters since procimgd started or a RESET; RESET answers the counters
 * as they were, then starts them again from 0. */
typedef struct {
    PNIO_UINT32 SndNoError;    /* frames sent */
    PNIO_UINT32 SndCollision;  /* sends failed by collision */
    PNIO_UINT32 SndOtherError; /* sends failed otherwise */
    PNIO_UINT32 RcvNoError;    /* frames received */
    PNIO_UINT32 RcvResError;   /* frames received with errors */
    PNIO_UINT32 RcvRejected;   /* frames rejected */
} ATTR_PACKED PNIO_CTRL_COMM_PORT_COUNTER_DATA;

typedef struct {
    PNIO_CTRL_COMM_PORT_COUNTER_DATA Port[4];
    PNIO_UINT16 NumberOfPorts;
} ATTR_PACKED PNIO_CTRL_COMM_COUNTER_DATA;

/* ---- Callback events ----------------------------------------------------------------- */

typedef struct {
    PNIO_MODE_TYPE Mode; /* the new mode */
} ATTR_PACKED PNIO_CBE_PRM_MODE_IND;

typedef struct {
    PNIO_ADDR *pAddr;          /* the address of the job */
    PNIO_UINT32 RecordIndex;
    PNIO_REF ReqRef;           /* as given to PNIO_rec_read_req */
    PNIO_ERR_STAT Err;         /* the job's status */
    PNIO_UINT32 Length;        /* bytes in pBuffer */
    const PNIO_UINT8 *pBuffer; /* the record: valid during the callback only */
} ATTR_PACKED PNIO_CBE_PRM_REC_READ_CONF;

typedef struct {
    PNIO_ADDR *pAddr;
    PNIO_UINT32 RecordIndex;
    PNIO_REF ReqRef;   /* as given to PNIO_rec_write_req */
    PNIO_ERR_STAT Err; /* the job's status */
} ATTR_PACKED PNIO_CBE_PRM_REC_WRITE_CONF;

typedef struct {
    PNIO_ADDR *pAddr; /* a device's address (station failure/return) or a module's */
    PNIO_REF IndRef;  /* internal, reserved */
    const PNIO_CTRL_ALARM_DATA *pAlarmData; /* valid during the callback only */
} ATTR_PACKED PNIO_CBE_PRM_ALARM_IND;

typedef struct {
    PNIO_ADDR *pAddr;       /* the address of the job */
    PNIO_DEV_ACT_TYPE Mode; /* the device's connection state now */
    PNIO_UINT32 Result;     /* PNIO_OK, or why it failed */
} ATTR_PACKED PNIO_CBE_PRM_DEV_ACT_CONF;

typedef struct {
    PNIO_UINT32 Frequency; /* Hz */
} ATTR_PACKED PNIO_CBE_PRM_LED_FLASH;

typedef struct {
    PNIO_CTRL_DIAG *pDiagData;   /* the request, yours again from now on */
    PNIO_UINT32 DiagDataBufferLen;
    PNIO_UINT8 *pDiagDataBuffer; /* the answer: valid during the callback only */
    PNIO_UINT32 ErrorCode;       /* PNIO_OK or the service's error */
} ATTR_PACKED PNIO_CBE_PRM_CTRL_DIAG_CONF;

typedef struct {
    PNIO_ADDR *pAddr;       /* the device or port that made it fail; all zero if none */
    PNIO_DEV_ACT_TYPE Mode; /* PNIO_DA_TRUE after TAILOR, PNIO_DA_FALSE after DEACT */
    PNIO_UINT32 Status;     /* PNIO_OK, PNIO_ERR_INVALID_STATION, PNIO_ERR_INVALID_PORT */
} ATTR_PACKED PNIO_CBE_PRM_IOSYS_CONF;

/* ---- PROFIenergy ------------------------------------------------------------------------ */

/* PE's record: the subslot's PROFIenergy service access point. */
#define PE_SAP_DR_INDEX 0x80A0
#define PE_MSRMT_IDS_MAX 254
/* How long a PE command is polled for its answer, seconds. */
#define PNIO_PE_SERVICE_REQ_LIFETIME_DEFAULT 10

typedef enum {
    PNIO_PE_CMD_RESERVED = 0,
    PNIO_PE_CMD_START_PAUSE = 1,
    PNIO_PE_CMD_END_PAUSE = 2,
    PNIO_PE_CMD_Q_MODES = 3,
    PNIO_PE_CMD_PEM_STATUS = 4,
    PNIO_PE_CMD_PE_IDENTIFY = 5,
    PNIO_PE_CMD_Q_MSRMT = 16
} PNIO_PE_CMD_ENUM;

typedef enum {
    PE_CMD_MODIF_NOT_USED = 0,         /* every command but the two below */
    PE_CMD_MODIF_Q_MODE_LIST_ALL = 1,  /* with PNIO_PE_CMD_Q_MODES */
    PE_CMD_MODIF_Q_MODE_GET_MODE = 2,
    PE_CMD_MODIF_Q_MSRMT_LIST_ALL = 1, /* with PNIO_PE_CMD_Q_MSRMT */
    PE_CMD_MODIF_Q_MSRMT_GET_VAL = 2
} PNIO_PE_CMD_MODIFIER_ENUM;

/* pe_hdr.struct_id: with CmdId, which member of pe_prm holds the answer. */
#define PE_CNF_STRUCT_ID_RESERVED 0
#define PE_CNF_STRUCT_ID_UNIQUE 1
#define PE_CNF_STRUCT_ID_QMODE_LIST_ALL 1
#define PE_CNF_STRUCT_ID_QMODE_GET_MODE 2
#define PE_CNF_STRUCT_ID_QMSRMT_LIST_ALL 1
#define PE_CNF_STRUCT_ID_QMSRMT_GET_VAL 2
#define PE_CNF_STRUCT_ID_ERROR 0xFF

typedef struct {
    PNIO_UINT32 time_ms; /* the pause expected */
} ATTR_PACKED PNIO_PE_PRM_START_PAUSE_REQ;

typedef struct {
    PNIO_UINT8 peModeId;
    PNIO_UINT8 reserved;
} ATTR_PACKED PNIO_PE_PRM_Q_MODE_GET_MODE_REQ;

typedef struct {
    PNIO_UINT8 num;
    PNIO_UINT8 reserved;
    PNIO_UINT16 Measurement_ID[PE_MSRMT_IDS_MAX];
} ATTR_PACKED PNIO_PE_PRM_Q_MSRMT_GET_VAL_REQ;

/* A PE command: CmdId and CmdModifier, and the parameters of those that have any. */
typedef struct {
    PNIO_PE_CMD_ENUM CmdId;
    PNIO_PE_CMD_MODIFIER_ENUM CmdModifier;
    union {
        PNIO_PE_PRM_START_PAUSE_REQ StartPause;
        PNIO_PE_PRM_Q_MODE_GET_MODE_REQ ModeGet;
        PNIO_PE_PRM_Q_MSRMT_GET_VAL_REQ MeasurementValue;
    } rq;
} ATTR_PACKED PNIO_PE_REQ_PRM;

typedef struct {
    PNIO_UINT8 err_code; /* the device's PE Error_Code */
    PNIO_UINT8 reserved;
} ATTR_PACKED PNIO_PE_PRM_GENERIC_CONF_NEG;

typedef struct {
    PNIO_UINT32 pe_mode_id; /* the mode reached */
} ATTR_PACKED PNIO_PE_PRM_START_PAUSE_CONF;

typedef struct {
    PNIO_UINT32 time_ms; /* until ready to operate */
} ATTR_PACKED PNIO_PE_PRM_END_PAUSE_CONF;

typedef struct {
    PNIO_UINT8 numServices;
    PNIO_UINT8 serviceId[254];
} ATTR_PACKED PNIO_PE_PRM_PE_IDENTIFY_CONF;

typedef struct {
    PNIO_UINT8 PE_Mode_ID_Source;
    PNIO_UINT8 PE_Mode_ID_Destination;
    PNIO_UINT32 Time_to_operate;               /* ms */
    PNIO_UINT32 Remaining_time_to_destination; /* ms */
    float Mode_Power_Consumption;               /* kW */
    float Energy_Consumption_to_Destination;    /* kWh */
    float Energy_Consumption_to_operate;        /* kWh */
} ATTR_PACKED PNIO_PE_PRM_PEM_STATUS_CONF;

typedef struct {
    PNIO_UINT8 numModeIds;
    PNIO_UINT8 peModeId[254];
} ATTR_PACKED PNIO_PE_PRM_Q_MODE_LIST_ALL_CONF;

typedef struct {
    PNIO_UINT8 peModeId;
    PNIO_UINT8 PE_Mode_Attributes; /* bit 0: dynamic figures */
    PNIO_UINT32 Time_min_Pause;
    PNIO_UINT32 Time_to_Pause;
    PNIO_UINT32 Time_to_operate;
    PNIO_UINT32 Time_min_length_of_stay;
    PNIO_UINT32 Time_max_length_of_stay;
    float Mode_Power_Consumption;
    float Energy_Consumption_to_pause;
    float Energy_Consumption_to_operate;
} ATTR_PACKED PNIO_PE_PRM_Q_MODE_GET_MODE_CONF;

typedef struct {
    PNIO_UINT16 Measurement_ID;
    PNIO_UINT8 Accuracy_Domain;
    PNIO_UINT8 Accuracy_Class;
    float Range;
} ATTR_PACKED PNIO_PE_PRM_Q_MSRMT_LIST_ELEM;

typedef struct {
    PNIO_UINT8 numMeasurementIds;
    PNIO_UINT8 reserved;
    PNIO_PE_PRM_Q_MSRMT_LIST_ELEM elem[PE_MSRMT_IDS_MAX];
} ATTR_PACKED PNIO_PE_PRM_Q_MSRMT_GET_LIST_CONF;

typedef struct {
    PNIO_UINT16 Measurement_ID;
    PNIO_UINT16 Status_of_Measurement_Value; /* 1 valid, 2 not available, 3 temporarily */
    float Transmission_Data_Type;             /* the value */
    PNIO_UINT32 End_of_demand;
    PNIO_UINT32 reserved;
} ATTR_PACKED PNIO_PE_PRM_Q_MSRMT_VAL_ELEM;

typedef struct {
    PNIO_UINT8 numMeasurementValues;
    PNIO_UINT8 reserved;
    PNIO_PE_PRM_Q_MSRMT_VAL_ELEM value[PE_MSRMT_IDS_MAX];
} ATTR_PACKED PNIO_PE_PRM_Q_MSRMT_GET_VAL_CONF;

typedef struct {
    PNIO_PE_CMD_ENUM CmdId; /* the command */
    PNIO_UINT32 Handle;     /* the controller's */
    PNIO_ADDR Addr;         /* the address the command went to */
    PNIO_REF Ref;           /* as given to PNIO_pe_cmd_req */
    PNIO_ERR_STAT Err;      /* the record jobs' status */
    PNIO_UINT16 state;      /* 1: answered; 2: refused by the device or not carried out */
    PNIO_UINT16 struct_id;  /* PE_CNF_STRUCT_ID_*: which member of pe_prm */
    PNIO_UINT32 length;     /* bytes of that member */
} ATTR_PACKED PE_CBE_HDR;

typedef struct {
    PE_CBE_HDR pe_hdr;
    union {
        PNIO_PE_PRM_GENERIC_CONF_NEG RespNegative;
        PNIO_PE_PRM_START_PAUSE_CONF StartPause;
        PNIO_PE_PRM_END_PAUSE_CONF EndPause;
        PNIO_PE_PRM_PE_IDENTIFY_CONF PeIdentify;
        PNIO_PE_PRM_PEM_STATUS_CONF PemStatus;
        PNIO_PE_PRM_Q_MODE_LIST_ALL_CONF ModeList;
        PNIO_PE_PRM_Q_MODE_GET_MODE_CONF ModeGet;
        PNIO_PE_PRM_Q_MSRMT_GET_LIST_CONF MeasurementList;
        PNIO_PE_PRM_Q_MSRMT_GET_VAL_CONF MeasurementValue;
    } pe_prm;
} ATTR_PACKED PNIO_PE_CBE_PRM;

/* A PE confirmation callback: its parameters are valid during the call only. */
typedef void (*PNIO_PE_CBF)(PNIO_PE_CBE_PRM *pPeCbfPrm);

/* ---- The controller's own interface (PN Driver's PNIO_interface_*) ------------------- */

/* PN Driver's boolean (its LSA_BOOL, one byte). */
typedef PNIO_UINT8 PNIO_BOOL;
#define PNIO_FALSE 0
#define PNIO_TRUE 1

/* What PNIO_interface_set_ip_and_nos changes: either or both (0x0003). */
typedef enum {
    PNIO_SET_IP_MODE = 0x0001,  /* the IP suite */
    PNIO_SET_NOS_MODE = 0x0002  /* the NameOfStation */
} PNIO_SET_IP_NOS_MODE_TYPE;

/* An IP suite, bytes in dotted order ({192, 168, 0, 1}). */
typedef struct {
    PNIO_UINT8 IpAddress[4];
    PNIO_UINT8 NetMask[4];
    PNIO_UINT8 Gateway[4]; /* {0, 0, 0, 0}: none */
    PNIO_BOOL Remanent;    /* kept across a restart (PNIO_CBE_REMA_READ_CONF hands it out) */
} ATTR_PACKED PNIO_IPv4;

/* A NameOfStation: Length bytes of Nos (a NUL after them is not needed). */
typedef struct {
    PNIO_UINT8 Nos[256];
    PNIO_UINT16 Length; /* 1 .. 240 */
    PNIO_BOOL Remanent; /* kept across a restart */
} ATTR_PACKED PNIO_NOS;

/* PNIO_CBE_IFC_SET_ADDR_CONF: a PNIO_interface_set_ip_and_nos ended, or an engineering tool
 * set the name or address by DCP (then Mode says what it set). The station as it is now. */
typedef struct {
    PNIO_SET_IP_NOS_MODE_TYPE Mode; /* what was to change */
    void *pStationName;             /* StationNameLen bytes: valid during the callback only */
    PNIO_UINT16 StationNameLen;
    PNIO_UINT8 LocalIPAddress[4];
    PNIO_UINT8 LocalSubnetMask[4];
    PNIO_UINT8 DefaultRouterAddr[4];
    PNIO_UINT32 Options;            /* reserved: 0 */
    PNIO_UINT32 Err;                /* PNIO_OK, PNIO_ERR_SET_IP_NOS_NOT_ALLOWED, PRM_IP, ... */
} ATTR_PACKED PNIO_CBE_PRM_SET_ADDR_CONF;

/* PNIO_CBE_REMA_READ_CONF: the interface's retentive data changed (a Remanent name or
 * address set by the program, or a permanent one by DCP): store the text and hand it to
 * SERV_CP_startup as pRemaData next time. */
typedef struct {
    PNIO_UINT8 *RemaXMLBuffer;       /* valid during the callback only */
    PNIO_UINT32 RemaXMLBufferLength; /* bytes, without a terminating NUL */
    PNIO_UINT32 Err;                 /* PNIO_OK */
} ATTR_PACKED PNIO_CBE_PRM_REMA_READ_IND;

/* What a controller callback receives; the member of the anonymous union that CbeType
 * selects holds the event's parameters. Valid during the callback only. */
typedef struct {
    PNIO_CBE_TYPE CbeType;
    PNIO_UINT32 Handle;
    union {
        PNIO_CBE_PRM_MODE_IND ModeInd;
        PNIO_CBE_PRM_REC_READ_CONF RecReadConf;
        PNIO_CBE_PRM_REC_WRITE_CONF RecWriteConf;
        PNIO_CBE_PRM_ALARM_IND AlarmInd;
        PNIO_CBE_PRM_DEV_ACT_CONF DevActConf;
        PNIO_CBE_PRM_LED_FLASH LedFlash;
        PNIO_CBE_PRM_CTRL_DIAG_CONF CtrlDiagConf;
        PNIO_CBE_PRM_IOSYS_CONF IoSystemReconf;
        PNIO_CBE_PRM_SET_ADDR_CONF SetAddrConf;
        PNIO_CBE_PRM_REMA_READ_IND RemaReadConf;
    };
} ATTR_PACKED PNIO_CBE_PRM;

/* A controller callback. */
typedef void (*PNIO_CBF)(PNIO_CBE_PRM *pCbfPrm);

/* ---- Functions ----------------------------------------------------------------------- */

/* Opens a controller on CP CpIndex (see above). The record callbacks must not be NULL,
 * the alarm callback may be (alarms are then acknowledged by the library). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_controller_open(
    PNIO_UINT32 CpIndex,         /* in */
    PNIO_UINT32 ExtPar,          /* in: PNIO_CEP_MODE_CTRL, PNIO_CEP_SLICE_ACCESS */
    PNIO_CBF cbf_rec_read_conf,  /* in */
    PNIO_CBF cbf_rec_write_conf, /* in */
    PNIO_CBF cbf_alarm_ind,      /* in, may be NULL */
    PNIO_UINT32 *Handle);        /* out */

/* Closes the controller: no callback runs once it returned. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_controller_close(
    PNIO_UINT32 Handle); /* in */

/* Registers a callback (in OFFLINE, each type once). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_register_cbf(
    PNIO_UINT32 Handle,    /* in */
    PNIO_CBE_TYPE CbeType, /* in */
    PNIO_CBF Cbf);         /* in, not NULL */

/* Asks for a mode; PNIO_CBE_MODE_IND reports each step. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_set_mode(
    PNIO_UINT32 Handle,   /* in */
    PNIO_MODE_TYPE Mode); /* in */

/* Activates or deactivates the device that has address pAddr; PNIO_CBE_DEV_ACT_CONF
 * reports the result. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_device_activate(
    PNIO_UINT32 Handle,            /* in */
    PNIO_ADDR *pAddr,              /* in */
    PNIO_DEV_ACT_TYPE DeviceMode); /* in */

/* Reads inputs. *pDataLen: the bytes from the address to the end of the submodule (as
 * many as fit were copied). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_data_read(
    PNIO_UINT32 Handle,        /* in */
    PNIO_ADDR *pAddr,          /* in */
    PNIO_UINT32 BufLen,        /* in */
    PNIO_UINT32 *pDataLen,     /* out */
    PNIO_UINT8 *pBuffer,       /* out */
    PNIO_IOXS IOlocState,      /* in: IOCS sent to the device */
    PNIO_IOXS *pIOremState);   /* out: the device's IOPS */

/* Reads outputs back as they were last sent. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_output_data_read(
    PNIO_UINT32 Handle,        /* in */
    PNIO_ADDR *pAddr,          /* in */
    PNIO_UINT32 BufLen,        /* in */
    PNIO_UINT32 *pDataLen,     /* out */
    PNIO_UINT8 *pBuffer,       /* out */
    PNIO_IOXS *pIOlocState,    /* out: the IOPS they were sent with */
    PNIO_IOXS *pIOremState);   /* out: the device's IOCS */

/* Copies all RT inputs and the remote status of all RT outputs into the read cache. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_data_read_cache_refresh(
    PNIO_UINT32 Handle); /* in */

/* Reads inputs from the read cache; IOlocState goes out with the next flush. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_data_read_cache(
    PNIO_UINT32 Handle,        /* in */
    PNIO_ADDR *pAddr,          /* in */
    PNIO_UINT32 BufLen,        /* in */
    PNIO_UINT32 *pDataLen,     /* out */
    PNIO_UINT8 *pBuffer,       /* out */
    PNIO_IOXS IOlocState,      /* in */
    PNIO_IOXS *pIOremState);   /* out */

/* Writes outputs. *pIOremState refers to the outputs of the previous cycle. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_data_write(
    PNIO_UINT32 Handle,        /* in */
    PNIO_ADDR *pAddr,          /* in */
    PNIO_UINT32 BufLen,        /* in */
    PNIO_UINT8 *pBuffer,       /* in */
    PNIO_IOXS IOlocState,      /* in: IOPS */
    PNIO_IOXS *pIOremState);   /* out: the device's IOCS */

/* Writes outputs into the write cache. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_data_write_cache(
    PNIO_UINT32 Handle,        /* in */
    PNIO_ADDR *pAddr,          /* in */
    PNIO_UINT32 BufLen,        /* in */
    PNIO_UINT8 *pBuffer,       /* in */
    PNIO_IOXS IOlocState,      /* in */
    PNIO_IOXS *pIOremState);   /* out: from the read cache */

/* Sends the write cache's outputs and the local input states, applied in one cycle. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_data_write_cache_flush(
    PNIO_UINT32 Handle); /* in */

/* Reads a record; PNIO_CBE_REC_READ_CONF delivers it. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_rec_read_req(
    PNIO_UINT32 Handle,      /* in */
    PNIO_ADDR *pAddr,        /* in */
    PNIO_UINT32 RecordIndex, /* in */
    PNIO_REF ReqRef,         /* in */
    PNIO_UINT32 Length);     /* in: at most PNIO_MAX_REC_LEN */

/* Writes a record; PNIO_CBE_REC_WRITE_CONF reports the result. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_rec_write_req(
    PNIO_UINT32 Handle,      /* in */
    PNIO_ADDR *pAddr,        /* in */
    PNIO_UINT32 RecordIndex, /* in */
    PNIO_REF ReqRef,         /* in */
    PNIO_UINT32 Length,      /* in */
    PNIO_UINT8 *pBuffer);    /* in */

/* Asks for a diagnosis; PNIO_CBE_CTRL_DIAG_CONF (registered first) delivers it. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_ctrl_diag_req(
    PNIO_UINT32 Handle,        /* in */
    PNIO_CTRL_DIAG *pDiagReq); /* in */

/* Deactivates every device (DEACT) or tailors the IO system (TAILOR); the end comes as
 * PNIO_CBE_IOSYSTEM_RECONFIG. DeviceList: an address of each optional device present;
 * PortInterconnectionList: 2 x PortInterconnectionCnt addresses, each pair two ports
 * joined. Both lists are copied during the call. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_iosystem_reconfig(
    PNIO_UINT32 Handle,                        /* in */
    PNIO_IOS_RECONFIG_MODE Mode,               /* in */
    PNIO_UINT32 DeviceCnt,                     /* in */
    PNIO_ADDR *DeviceList,                     /* in */
    PNIO_UINT32 PortInterconnectionCnt,        /* in, pairs */
    PNIO_ADDR *PortInterconnectionList);       /* in */

/* Registers the PE confirmation callback, once, before the first PNIO_pe_cmd_req. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_register_pe_cbf(
    PNIO_UINT32 Handle,           /* in */
    PNIO_PE_CBF cbf_pe_cmd_conf); /* in */

/* Sends a PE command to the submodule at pAddr (the device's head module: the diagnostic
 * address of its slot 0 subslot 1); *pPeReqPrm is copied. The answer comes to the PE
 * callback. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_pe_cmd_req(
    PNIO_UINT32 Handle,           /* in */
    PNIO_ADDR *pAddr,             /* in */
    PNIO_REF ReqRef,              /* in */
    PNIO_PE_REQ_PRM *pPeReqPrm);  /* in */

/* Opens the controller's own interface on CP CpIndex (one open per interface). Its record
 * reads are confirmed by PNIO_CBE_IFC_REC_READ_CONF (RecReadConf), its alarms come as
 * PNIO_CBE_IFC_ALARM_IND (AlarmInd); either callback may be NULL. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_interface_open(
    PNIO_UINT32 CpIndex,        /* in */
    PNIO_CBF cbf_rec_read_conf, /* in, may be NULL */
    PNIO_CBF cbf_alarm_ind,     /* in, may be NULL */
    PNIO_UINT32 *Handle);       /* out */

/* Registers PNIO_CBE_IFC_SET_ADDR_CONF or PNIO_CBE_REMA_READ_CONF, once each. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_interface_register_cbf(
    PNIO_UINT32 Handle,    /* in */
    PNIO_CBE_TYPE CbeType, /* in */
    PNIO_CBF Cbf);         /* in */

/* Closes the interface: no callback runs after it returns. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_interface_close(PNIO_UINT32 Handle);

/* Gives the controller's station a new IP suite and/or NameOfStation, where the
 * configuration lets programs change them ([interface] address_by_program,
 * name_by_program); the outcome comes as PNIO_CBE_IFC_SET_ADDR_CONF. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_interface_set_ip_and_nos(
    PNIO_UINT32 Handle,             /* in */
    PNIO_SET_IP_NOS_MODE_TYPE Mode, /* in */
    PNIO_IPv4 IpV4,                 /* in */
    PNIO_NOS NoS);                  /* in */

/* Reads a record of the interface (pAddr: its diagnostic address or its port's, PNIO_IO_IN);
 * the record comes as PNIO_CBE_IFC_REC_READ_CONF. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_interface_rec_read_req(
    PNIO_UINT32 Handle,      /* in */
    PNIO_ADDR *pAddr,        /* in */
    PNIO_UINT32 RecordIndex, /* in */
    PNIO_REF ReqRef,         /* in */
    PNIO_UINT32 Length);     /* in: 1 .. 4096 */

#ifdef __cplusplus
}
#endif

#endif /* PNIOUSRX_H */
