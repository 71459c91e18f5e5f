/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * pniousrd.h - the IO device part of procimg's IO-Base compatible API (libprocimg).
 *
 * A program written for the SIMATIC NET IO-Base device interface (the PC as an IO device of
 * somebody else's PLC, as the manual's DevEasy) compiles against this header. Names, types,
 * enum values and layouts are those of the IO-Base manual and its 2015 interface; written for
 * procimg. libprocimg implements these functions over procimgd's device role (`role =
 * "device"` in procimgd's configuration): procimgd is the station on the network and runs
 * its ARs with the PLC, its cyclic data, records and alarms; the program plugs, answers the
 * callbacks and moves the data.
 *
 * Status: libprocimg defines the management and configuration functions, the AR's, the IO
 * data functions, the records, diagnosis and alarm functions, and calls every callback of
 * PNIO_CBF_FUNCTIONS. The isochronous and watchdog functions are pniobase.h's (see below).
 *
 * IO data. PNIO_initiate_data_write(_ext) and _read(_ext) call PNIO_CBF_DATA_WRITE and
 * PNIO_CBF_DATA_READ on the caller's thread, one call per submodule the program plugged that
 * has I data (write) or Q data (read), and return when all returned; they may be called
 * inside callbacks. The buffer is the library's copy of the image: for a write it starts as
 * the I data last sent, and all submodules' I data goes out with the IOPS returned in one
 * cycle; for a read it holds the newest Q data, and the IOCS returned reaches the PLC in the
 * next cycle. A return value other than PNIO_S_GOOD counts as PNIO_S_BAD. From
 * PNIO_device_start to PNIO_device_stop the library owns the program's I data on procimgd
 * (until the first write the PLC gets it with IOPS BAD). The plain calls visit RT data; _ext
 * selects by pAddr (NULL, a slot with subslot 0, or one submodule, in every API; one the
 * program has not plugged: PNIO_ERR_PRM_ADD) and AccessType (PNIO_ACCESS_ALL_WITH_LOCK and
 * PNIO_ACCESS_IRT_WITH_LOCK: PNIO_ERR_PRM_ACCESS_TYPE). Before start: PNIO_ERR_SEQUENCE;
 * without an AR whose PNIO_CBF_PRM_END_IND was given, or with nothing selected:
 * PNIO_WARN_NO_SUBMODULES. As the manual's order has it, the program writes after
 * PRM_END_IND the I data the PLC gets with the ApplicationReady (its IOPS too), then calls
 * PNIO_set_appl_state_ready, which lets the ApplicationReady go once procimgd sends that
 * data (a few cycles at most).
 *
 * ARs. From open to close the device checks the station's ARs and holds its
 * ApplicationReady. All callbacks come from one library thread, in the manual's order: for
 * a PLC's Connect PNIO_CBF_AR_CHECK_IND (ArNumber 1, 2, ... per open, the station's
 * SessionKey, and the Connect's: the PLC's IP address as HostIp, in network byte order as
 * struct in_addr's s_addr, ArType, ArUUID, ArProperties, CMInitiatorObjectUUID as
 * CmiObjUUID, the PLC's station name), PNIO_CBF_CHECK_IND per expected submodule where other ident numbers are plugged
 * (a PROPER or SUBSTITUTED answer with other ident numbers plugs those before the Connect
 * is answered), then the Connect is accepted (PNIO_device_ar_abort refuses it afterwards);
 * PNIO_CBF_AR_INFO_IND (IOCRs and modules from the Connect, valid during the call); PNIO_CBF_PRM_END_IND (subslot 0) at the PLC's PrmEnd;
 * PNIO_set_appl_state_ready then sends the ApplicationReady (procimgd sends it itself after
 * 10 s), whose ModuleDiffBlock gives the submodules of its list (NULL: none) the ARInfo
 * "application ready pending" until PNIO_ret_of_sub_alarm_send announces each;
 * PNIO_CBF_AR_INDATA_IND; PNIO_CBF_APDU_STATUS_IND (RUN or STOP, STATION_OK or
 * STATION_PROBLEM, PRIMARY or BACKUP, as the DataStatus of the PLC's frames says) when it
 * changes, a change before data exchange right after AR_INDATA_IND; at the
 * AR's end PNIO_CBF_AR_OFFLINE_IND after AR_INDATA_IND, else PNIO_CBF_AR_ABORT_IND, whose
 * ReasonCode is the RTA abort code (1..34 are the same numbers), PNIO_AR_REASON_REL for the
 * PLC's release, PNIO_AR_REASON_ABORT for the station's own end with another code.
 * A submodule plugged in data exchange is parameterized by the PLC again: PRM_END_IND then
 * names it (API, slot, subslot), and PNIO_set_appl_state_ready (once per such PRM_END_IND)
 * lets its PlugApplicationReady go, after which its data and alarms are the AR's again.
 * PNIO_device_stop gives the end callback before PNIO_CBF_DEVICE_STOPPED;
 * PNIO_device_ar_abort ends that AR only (an ERR-RTA with AbortRequest; the station stays on
 * the wire and takes the PLC's next Connect; the end callback has PNIO_AR_REASON_ABORT). In
 * the per-AR calls an
 * ArNumber never given answers PNIO_ERR_SEQUENCE, an ended AR's or a wrong SessionKey
 * PNIO_ERR_SESSION.
 *
 * Records. From PNIO_device_start to PNIO_device_stop the PLC's reads and writes of the
 * user records (0x0000..0x7FFF) of every submodule the program plugged come to
 * PNIO_CBF_REC_READ and PNIO_CBF_REC_WRITE on the library thread; those of I&M0..I&M4
 * (0xAFF0..0xAFF4) too for a submodule plugged with PNIO_sub_plug_ext_IM and IM0_bits other
 * than NOTHING: the program answers them with the whole record, PNIO_BLOCK_HEADER included
 * (the PNIO_IMn_TYPE structs), stores I&M1..4 itself and refuses writes to I&M0. The other
 * records (identification, diagnosis, ModuleDiff, I&M0FilterData, and I&M of submodules
 * plugged without I&M bits) are procimgd's. ArNumber and SessionKey are the AR's (0 for a
 * read outside any AR); SequenceNum counts the jobs from 1. A read's *pBufLen is the most
 * the PLC takes, and what the callback leaves there is the length sent. A PNIO_ERR_STAT
 * other than all zeros refuses the job with its ErrCode1 and ErrCode2 (procimgd sends
 * ErrorCode 0xDE for a read, 0xDF for a write, ErrorDecode PNIORW; ErrCode1 0 means "read
 * error" or "write error"). The callback has 2 s; after that the PLC got "resource busy".
 *
 * Diagnosis. PNIO_diag_channel_add, _ext_channel_add and _generic_add put the entry into
 * procimgd's diagnosis of the submodule at once and without an alarm (the PLC reads it in the
 * diagnosis records and the submodule's state); PNIO_diag_alarm_send announces it. The
 * program's submodule only (else PNIO_ERR_PRM_ADD); DiagTag 0 is refused with
 * PNIO_ERR_PRM_INVALIDARG on add and removes all entries of the function's kind on remove; an
 * unknown DiagTag is no error. procimgd keys entries by channel, direction and error type
 * (manufacturer ones by UserStructIdent): entries of two tags with the same key are one,
 * which goes with the last of its tags. ChannelProp's maintenance bits make the entry
 * "maintenance required" or "demanded" instead of a fault. They may be called from open to
 * stop, and inside callbacks.
 *
 * Alarms. PNIO_process_alarm_send, PNIO_diag_alarm_send and PNIO_ret_of_sub_alarm_send need
 * the AR the program called PNIO_set_appl_state_ready for (before: PNIO_ERR_SEQUENCE; a wrong
 * SessionKey: PNIO_ERR_SESSION), at most 172 bytes of data (PNIO_ERR_VALUE_LEN), a data
 * pointer when DataLen is not 0 (PNIO_ERR_PRM_BUF) and a UserStructIdent that fits the alarm
 * (0x0000..0x7FFF for a process alarm; never 0x8001: PNIO_ERR_PRM_INVALIDARG). The call
 * returns PNIO_OK once procimgd sent the alarm; PNIO_CBF_REQ_DONE follows on the library
 * thread with the UserHndl: PNIO_OK and a zero PNIO_ERR_STAT when the PLC acknowledged it
 * positively, PNIO_ERR_ALARM_DATA_FORMAT with the AlarmAck's PNIOStatus when it refused it,
 * PNIO_ERR_ABORT when the AR ended first. A process alarm of a submodule the program did not
 * plug or the AR does not hold answers PNIO_ERR_UNKNOWN_ADDR; a diagnosis or return alarm
 * of one returns PNIO_OK, as the manual says, and REQ_DONE brings PNIO_ERR_UNKNOWN_ADDR. A
 * diagnosis alarm's data is the item after its UserStructIdent (0x8000 channel, 0x8002
 * extended channel diagnosis, big-endian); it is DiagnosisDisappears when nothing is left on
 * the submodule, else Diagnosis, with the AlarmSpecifier of procimgd's store. They may be
 * called inside callbacks.
 *
 * Identification and stop request. A DCP Signal from an engineering tool calls
 * PNIO_CBF_START_LED_FLASH (2 Hz) and, three seconds later, PNIO_CBF_STOP_LED_FLASH. A DCP
 * reset to factory, which takes the station's name and address (its setup over the network),
 * calls PNIO_CBF_CP_STOP_REQ: close the device outside the callback, and open it again once
 * the station has an address (until then open answers PNIO_ERR_CONFIG_IN_UPDATE). So does
 * a restart of the procimgd (a configuration download, a reset: servusrx.h), which waits up
 * to 10 s for the device to close.
 *
 * Open, start, stop. CpIndex names a procimgd instance as for the controller (PROCIMG_CP<n>,
 * else PROCIMG_INSTANCE, else "procimg"); it must be in the device role (otherwise
 * PNIO_ERR_PRM_CP_ID) with the VendorId and DeviceId given (otherwise
 * PNIO_ERR_INVALID_CONFIG), and have an IP address (otherwise PNIO_ERR_CONFIG_IN_UPDATE: open
 * again later). PNIO_device_open takes the server to OFFLINE, so that no PLC connects before
 * PNIO_device_start, which takes it to OPERATE; PNIO_device_stop takes it to OFFLINE again
 * (the PLC's AR ends) and PNIO_CBF_DEVICE_STOPPED confirms on a library thread.
 * PNIO_device_close leaves the server as it is. procimgd's station serves one AR at a time,
 * whatever MaxAr says; the annotation is checked but the station shows its configuration's.
 *
 * A station the program defines. When procimgd's configuration names the station's GSDML
 * file and no submodules (`[station] gsdml = "FILE"`), the program's plugs outside slot 0
 * are the station: each PNIO_sub_plug is checked against the file at once (a module or
 * submodule ident the file lacks, or a slot or subslot it does not allow: PNIO_ERR_PRM_ADD,
 * the text naming the ident and the file) and confirmed without touching procimgd, whose
 * station waits off the wire with its DAP. PNIO_device_start defines the station with the
 * program's tree (IO lengths and parameter records from the file; every submodule's records
 * the program's, its I&M records too when plugged with IM0_bits): procimgd runs the station
 * anew, and the PLC may connect at once. A start after a stop defines it again only when
 * the tree changed. PNIO_device_close (or the program's end) ends the AR with an abort and
 * the station waits off the wire for the next program. The VendorID and DeviceID given to
 * PNIO_device_open are the file's.
 *
 * Plugging. What the program plugs must lie at positions procimgd's configuration of the
 * station has (`[[station.submodule]]`, with those IO lengths); its ident numbers are what
 * the PLC sees (a plug with other ident numbers is a wrong or substitute submodule for the
 * PLC). A plug elsewhere, or in an API not added, or outside 1..MaxSubslots, is refused with
 * PNIO_ERR_PRM_ADD. PNIO_mod_plug records the slot's ModuleIdentNumber; each submodule plug
 * is carried out on procimgd on a library thread and confirmed by PNIO_CBF_PULL_PLUG_CONF
 * (if given): at a position where procimgd has nothing, the program's submodule is plugged;
 * where procimgd has a submodule with the same ident numbers, that one is taken as the
 * program's (no pull, no alarm); where it has one with other ident numbers, that one is
 * pulled and the program's plugged. (What procimgd has is its configuration's, or what this
 * library plugged or pulled since open; another client's plugs meanwhile are not seen.)
 * PNIO_device_start first pulls every position outside slot 0 that the program did not
 * plug, so that the PLC sees the program's tree; slot 0 (the DAP, its interface and ports)
 * stays as procimgd has it unless the program plugs there. PNIO_sub_pull and PNIO_mod_pull
 * pull the program's submodules on procimgd. After start, plug and pull need
 * PNIO_CBF_PULL_PLUG_CONF (otherwise PNIO_ERR_SEQUENCE) and reach the PLC as Pull, Plug or
 * Plug Wrong alarms; between the PLC's Connect and data exchange procimgd refuses them and
 * the confirmation carries PNIO_ERR_SEQUENCE. AlarmType and IM0_bits are checked, but
 * procimgd picks the alarm by what the PLC expects and keeps I&M0FilterData itself; IM0_bits
 * other than NOTHING give the program the submodule's I&M records (see Records).
 *
 * Sequence. open -> api_add -> mod_plug, sub_plug -> start -> stop (DEVICE_STOPPED) ->
 * mod_pull -> api_remove -> close; calls out of it answer PNIO_ERR_SEQUENCE: a submodule
 * before its module, a second plug at a position, a pull of what the program did not plug,
 * api_add/api_remove or close while started or stopping, close with plugs or pulls not yet
 * confirmed by PNIO_CBF_PULL_PLUG_CONF, a second open of the same instance, and inside a
 * callback every call but the IO data, diagnosis, alarm and PNIO_set_dev_state functions
 * (and PNIO_CP_set_opdone). An API added twice answers
 * PNIO_ERR_ALREADY_DONE.
 *
 * Layout. As in pniobase.h: ATTR_PACKED is alignment 4, not byte packing, and enums are
 * int-sized. PNIO_BLOCK_HEADER alone is a plain struct (6 bytes), so that the I&M records
 * have their wire layout up to the struct's tail padding.
 *
 * Where the manual and IO-Base's header name a thing differently, both names work:
 * PNIO_CFB_FUNCTIONS and PNIO_CBF_FUNCTIONS, the members pnio_cbf_cp_stop_req and
 * cbf_cp_stop_req, pnio_cbf_device_stopped and cbf_device_stopped (the manual's are the
 * members, IO-Base's header's are macros naming them), PNIO_AR_TYPE's pReserved
 * and pNextAr, PNIO_MODULE_TYPE's API and Api, PNIO_SUB_PROP_TYPE_* and
 * CM_SUB_PROP_USER_TYPE_*. Where they differ in a type, the header's type is used, since a
 * program compiled against it expects that one: PNIO_CBF_PULL_PLUG_CONF returns void and
 * takes a PNIO_DEV_ACTION, PNIO_CBF_PRM_END_IND takes 16-bit slot and subslot numbers, and
 * PNIO_IOCR_TYPE's Direction and IOCRProperties are its enums (32 bits, as the manual's
 * PNIO_UINT32). IO-Base declares PNIO_device_open_ext and PNIO_api_add_ext only when the
 * program defines PNIO_DEVICE_IF_EXT_01; here they are always declared.
 *
 * Isochronous mode. PNIO_CP_register_cbf and PNIO_CP_set_opdone are pniobase.h's; a
 * device passes its device handle as CpHandle (controller and device handles never share a
 * number). Registering is allowed before PNIO_device_start only (else PNIO_ERR_SEQUENCE),
 * with the controller's rules: OPFAULT before STARTOP (else PNIO_ERR_OPFAULT_NOT_REG),
 * NEWCYCLE before STARTOP (else PNIO_ERR_NEWCYCLE_SEQUENCE_REG), each type once (else
 * PNIO_ERR_ALLREADY_DONE), Cbf not NULL (else PNIO_ERR_PRM_CALLBACK). With STARTOP the
 * device takes part in procimgd's cycle handshake, as an isochronous controller does:
 * from the registration on (before start and without an AR too) STARTOP_IND comes every
 * cycle on a thread of the library; inside it PNIO_initiate_data_read and _write act on
 * this cycle (the I data written goes out with PNIO_CP_set_opdone, in one piece), then
 * PNIO_CP_set_opdone ends the cycle. A PNIO_CP_set_opdone after procimgd's deadline still
 * answers PNIO_OK; OPFAULT_IND reports it and that cycle's I data is not used. One without
 * an open cycle gives PNIO_ERR_SEQUENCE, one without STARTOP registered
 * PNIO_ERR_STARTOP_NOT_REGISTERED. Outside the window the data functions work as without
 * STARTOP (no PNIO_WARN_IRT_INCONSISTENT). While a plug or pull is carried out on procimgd
 * the device misses that cycle (an OPFAULT). PNIO_CYCLE_INFO is as for the controller
 * (pniousrx.h).
 *
 * The CP application watchdog (PNIO_CP_set_appl_watchdog, PNIO_CP_trigger_watchdog,
 * PNIO_CBF_APPL_WATCHDOG) is pniobase.h's, for controllers and devices alike; what its
 * expiry does is said there. Error codes are pnioerrx.h's.
 *
 * PROFIenergy. A device opened with PNIO_CEP_PE_MODE_ENABLE answers the PROFIenergy record
 * (0x80A0) of the submodules it plugged itself: the PLC's PE request comes as a REC_WRITE
 * of index 0x80A0 (a PE request block), the read that fetches the answer as a REC_READ of
 * it, which the program answers with the PE response block (or refuses with ErrCode1 0xB5
 * "state conflict" when nothing was asked, 0xC3 "resource unavailable" while the answer is
 * not ready: the controller reads again). Without it the station answers PE itself, as an
 * entity without energy-saving modes (Start_Pause refused with PE error 0x06, one mode,
 * 0xFF ready to operate).
 *
 * The CP service functions of chapter 8 (SERV_CP_get_fw_info, _set_type_of_station,
 * _download, _reset, the info interface) and PN Driver's start-up are servusrx.h's.
 */
#ifndef PNIOUSRD_H
#define PNIOUSRD_H

#include <stddef.h>

#include "pniobase.h"
#include "pnioerrx.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Limits and encodings ------------------------------------------------------------ */

/* Characters of PNIO_ANNOTATION's text fields (without the terminating NUL). */
#define MAX_DEVICE_TYPE_LENGTH 25
#define MAX_ORDER_ID_LENGTH 20

/* MaxAr of PNIO_device_open with ExtPar PNIO_CEP_DEV_MAXAR_BY_TYPE: the ARs of RT class
 * 1/2, of RT class 3 and of device access, 4 bits each. */
#define PNIO_DEVICE_SET_MAXAR_BY_TYPE(MaxArClass1_2, MaxArClass3, MaxArDeviceAccess) \
    ((((MaxArDeviceAccess) & 0xF) << 8) | (((MaxArClass3) & 0xF) << 4) |                \
     ((MaxArClass1_2) & 0xF))

/* DevState of PNIO_set_dev_state. */
#define PNIO_DEVSTAT_OK 1              /* no problem */
#define PNIO_DEVSTAT_STATION_PROBLEM 2 /* the station has a problem */

/* ---- Enums --------------------------------------------------------------------------- */

/* Which IO data PNIO_initiate_data_read_ext and PNIO_initiate_data_write_ext visit, and
 * how consistent it is. */
typedef enum {
    PNIO_ACCESS_ALL_WITH_LOCK = 0,    /* not supported */
    PNIO_ACCESS_ALL_WITHOUT_LOCK = 1, /* RT and IRT; IRT consistent only isochronously */
    PNIO_ACCESS_RT_WITH_LOCK = 2,     /* RT only, consistent */
    PNIO_ACCESS_RT_WITHOUT_LOCK = 3,  /* RT only, not guaranteed consistent */
    PNIO_ACCESS_IRT_WITH_LOCK = 4,    /* not supported */
    PNIO_ACCESS_IRT_WITHOUT_LOCK = 5  /* IRT only, consistent only isochronously */
} PNIO_ACCESS_ENUM;

/* What a PNIO_CBF_PULL_PLUG_CONF confirms. */
typedef enum {
    PNIO_MOD_PULL = 1, /* PNIO_mod_pull */
    PNIO_MOD_PLUG = 2, /* PNIO_mod_plug */
    PNIO_SUB_PULL = 3, /* PNIO_sub_pull */
    PNIO_SUB_PLUG = 4  /* PNIO_sub_plug, PNIO_sub_plug_ext, PNIO_sub_plug_ext_IM */
} PNIO_DEV_ACTION;

/* A submodule's entry in I&M0FilterData (record 0xF840), given to PNIO_sub_plug_ext_IM. */
typedef enum {
    PNIO_PLUG_IM0_BITS_NOTHING = 0x00,               /* no I&M data */
    PNIO_PLUG_IM0_BITS_SUBMODULE = 0x01,             /* I&M data of its own (the 2nd and
                                                        later I&M submodule of a slot) */
    PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MODULE = 0x03,  /* also speaks for its module */
    PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV = 0x07  /* also for the device: the DAP's
                                                        submodule only */
} PNIO_PLUG_IM0_BITS;

/* ArType of PNIO_CBF_AR_CHECK_IND. */
typedef enum {
    PNIO_AR_TYPE_SINGLE = 0x01,     /* an IO AR */
    PNIO_AR_TYPE_SUPERVISOR = 0x06, /* a supervisor AR (device access) */
    PNIO_AR_TYPE_SINGLE_RTC3 = 0x10 /* an IO AR with RT class 3 (IRT) */
} PNIO_AR_TYPE_ENUM;

/* Why an AR ended (PNIO_CBF_AR_ABORT_IND, PNIO_CBF_AR_OFFLINE_IND). */
typedef enum {
    PNIO_AR_REASON_NONE = 0,
    PNIO_AR_REASON_RESERVED1 = 1,  /* internal */
    PNIO_AR_REASON_RESERVED2 = 2,  /* internal */
    PNIO_AR_REASON_MEM = 3,        /* out of memory */
    PNIO_AR_REASON_FRAME = 4,      /* adding a provider or consumer failed */
    PNIO_AR_REASON_MISS = 5,       /* the consumer missed the PLC's frames */
    PNIO_AR_REASON_TIMER = 6,      /* CMI timeout */
    PNIO_AR_REASON_ALARM = 7,      /* opening the alarm channel failed */
    PNIO_AR_REASON_ALSND = 8,      /* sending an alarm failed */
    PNIO_AR_REASON_ALACK = 9,      /* sending an alarm acknowledgement failed */
    PNIO_AR_REASON_ALLEN = 10,     /* alarm data too long */
    PNIO_AR_REASON_ASRT = 11,      /* alarm indication error */
    PNIO_AR_REASON_RPC = 12,       /* an RPC client call failed */
    PNIO_AR_REASON_ABORT = 13,     /* AR abort requested */
    PNIO_AR_REASON_RERUN = 14,     /* a new AR replaced this one */
    PNIO_AR_REASON_REL = 15,       /* the PLC released the AR */
    PNIO_AR_REASON_PAS = 16,       /* the device was passivated */
    PNIO_AR_REASON_RMV = 17,       /* the device or AR was removed */
    PNIO_AR_REASON_PROT = 18,      /* protocol violation */
    PNIO_AR_REASON_NARE = 19,      /* name and address resolution error */
    PNIO_AR_REASON_BIND = 20,      /* RPC bind error */
    PNIO_AR_REASON_CONNECT = 21,   /* RPC connect error */
    PNIO_AR_REASON_READ = 22,      /* RPC read error */
    PNIO_AR_REASON_WRITE = 23,     /* RPC write error */
    PNIO_AR_REASON_CONTROL = 24,   /* RPC control error */
    PNIO_AR_REASON_PULLPLUG = 25,  /* pull or plug between the AR check and PrmEnd */
    PNIO_AR_REASON_AP_RMV = 26,    /* deprecated: AP removed */
    PNIO_AR_REASON_LNK_DWN = 27,   /* link down */
    PNIO_AR_REASON_MMAC = 28,      /* a multicast MAC could not be registered */
    PNIO_AR_REASON_SYNC = 29,      /* not synchronised (no companion AR) */
    PNIO_AR_REASON_TOPO = 30,      /* wrong topology (no companion AR) */
    PNIO_AR_REASON_DCP_NAME = 31,  /* DCP changed the station name */
    PNIO_AR_REASON_DCP_RESET = 32, /* DCP reset to factory settings */
    PNIO_AR_REASON_PRM = 33,       /* deprecated: companion AR blocked by a port or
                                      interface submodule of the first AR */
    PNIO_AR_REASON_IRDATA = 34,    /* no IR data record yet */
    PNIO_AR_REASON_MAX = 255
} PNIO_AR_REASON;

/* The PLC's state, as PNIO_CBF_APDU_STATUS_IND reports it: bits. */
typedef enum {
    PNIO_EVENT_APDU_STATUS_STOP = 0x01,            /* the PLC is in STOP */
    PNIO_EVENT_APDU_STATUS_RUN = 0x02,             /* the PLC is in RUN */
    PNIO_EVENT_APDU_STATUS_STATION_OK = 0x04,      /* no station problem */
    PNIO_EVENT_APDU_STATUS_STATION_PROBLEM = 0x08, /* station problem */
    PNIO_EVENT_APDU_STATUS_PRIMARY = 0x10,         /* primary (redundancy) */
    PNIO_EVENT_APDU_STATUS_BACKUP = 0x20           /* backup (redundancy) */
} PNIO_APDU_STATUS_IND;

/* An IOCR's direction, named from the PLC's side (PNIO_IOCR_TYPE::Direction). */
typedef enum {
    PNIO_IOCR_TYPE_RESERVED_0 = 0,
    PNIO_IOCR_TYPE_INPUT = 1,              /* input frame: the device sends */
    PNIO_IOCR_TYPE_OUTPUT = 2,             /* output frame: the device receives */
    PNIO_IOCR_TYPE_MULTICAST_PROVIDER = 3, /* multicast provider (an input frame) */
    PNIO_IOCR_TYPE_MULTICAST_CONSUMER = 4  /* multicast consumer (an output frame) */
} PNIO_IOCR_TYPE_ENUM;

/* An IOCR's properties (PNIO_IOCR_TYPE::IOCRProperties): mask first. An unknown RT class
 * is a reason to abort the AR (PNIO_device_ar_abort). */
typedef enum {
    PNIO_IOCR_PROP_RT_CLASS_MASK = 0x0F,
    PNIO_IOCR_PROP_RT_CLASS_1 = 0x01,     /* RT */
    PNIO_IOCR_PROP_RT_CLASS_2 = 0x02,     /* RT */
    PNIO_IOCR_PROP_RT_CLASS_3 = 0x03,     /* IRT */
    PNIO_IOCR_PROP_RT_CLASS_1_UDP = 0x04  /* RT over UDP */
} PNIO_IOCR_PROP_ENUM;

/* *pModState of PNIO_CBF_CHECK_IND. */
typedef enum {
    PNIO_MOD_STATE_NO_MODULE = 0,
    PNIO_MOD_STATE_WRONG_MODULE = 1,
    PNIO_MOD_STATE_PROPER_MODULE = 2,
    PNIO_MOD_STATE_SUBSTITUTED_MODULE = 3
} PNIO_MODULE_STATE;

/* The ident bits of a submodule state (bits 11-14). */
typedef enum {
    PNIO_SUB_STATE_IDENT_MASK = 0x7800,
    PNIO_SUB_STATE_IDENT_NO_SUBMODULE = 0x1800,
    PNIO_SUB_STATE_IDENT_WRONG = 0x1000,
    PNIO_SUB_STATE_IDENT_SUBSTITUTE = 0x0800,
    PNIO_SUB_STATE_IDENT_OK = 0x0000
} PNIO_SUBMODULE_STATE;

/* Bit 15 of a submodule state: the state has format 1. */
#define PNIO_SUB_STATE_FORMAT_1 0x8000

/* *pSubState of PNIO_CBF_CHECK_IND: PNIO_SUB_STATE_FORMAT_1 | an ident. Missing modules
 * and submodules are reported without the callback, which so needs no NO_SUBMODULE. */
typedef enum {
    PNIO_SUB_CHECK_NO_SUBMODULE = 0x9800,
    PNIO_SUB_CHECK_WRONG_SUBMODULE = 0x9000,
    PNIO_SUB_CHECK_SUBSTITUTED_SUBMODULE = 0x8800,
    PNIO_SUB_CHECK_PROPER_SUBMODULE = 0x8000
} PNIO_SUB_CHECK_STATE;

/* PNIO_SUBMOD_TYPE::SubMProperties: mask first, the other bits are reserved. */
enum PNIO_SUB_PROPERTIES_ENUM_USER {
    CM_SUB_PROP_USER_TYPE_MASK = 0x03,
    CM_SUB_PROP_USER_TYPE_NO_DATA = 0x00,
    CM_SUB_PROP_USER_TYPE_INPUT = 0x01,
    CM_SUB_PROP_USER_TYPE_OUTPUT = 0x02,
    CM_SUB_PROP_USER_TYPE_INPUT_OUTPUT = 0x03,
    CM_SUB_PROP_USER_SHARED_INP_MASK = 0x04,     /* shared input */
    CM_SUB_PROP_USER_REDUCE_INP_LEN_MASK = 0x08, /* input data length reduced to 0 */
    CM_SUB_PROP_USER_REDUCE_OUT_LEN_MASK = 0x10, /* output data length reduced to 0 */
    CM_SUB_PROP_USER_DISCARD_IOXS_MASK = 0x20    /* IOxS length treated as 0 */
};

/* The manual's names of the submodule type. */
#define PNIO_SUB_PROP_TYPE_MASK CM_SUB_PROP_USER_TYPE_MASK
#define PNIO_SUB_PROP_TYPE_NO_DATA CM_SUB_PROP_USER_TYPE_NO_DATA
#define PNIO_SUB_PROP_TYPE_INPUT CM_SUB_PROP_USER_TYPE_INPUT
#define PNIO_SUB_PROP_TYPE_OUTPUT CM_SUB_PROP_USER_TYPE_OUTPUT
#define PNIO_SUB_PROP_TYPE_INPUT_OUTPUT CM_SUB_PROP_USER_TYPE_INPUT_OUTPUT

/* ---- Alarms -------------------------------------------------------------------------- */

/* AlarmType of PNIO_sub_plug_ext and PNIO_sub_plug_ext_IM. */
#define PNIO_ALARM_TYPE_PLUG 0x0004       /* the submodule the PLC expects */
#define PNIO_ALARM_TYPE_PLUG_WRONG 0x000A /* another one, not compatible */

/* AlarmState of PNIO_diag_alarm_send. */
#define PNIO_STATE_ALARM_APPEARS 1
#define PNIO_STATE_ALARM_DISAPPEARS 2

/* UserStructIdent of an alarm: 0x0000-0x7FFF are the vendor's. */
#define PNIO_USR_STRUC_ID_CHANNEL_DIAG 0x8000       /* channel diagnosis */
#define PNIO_USR_STRUC_ID_MULTI_MANUFAC_DIAG 0x8001 /* several diagnoses: not allowed */
#define PNIO_USR_STRUC_ID_EXTCHANNEL_DIAG 0x8002    /* extended channel diagnosis */

/* ---- Diagnosis ----------------------------------------------------------------------- */

/* Type of PNIO_build_channel_properties: the channel's size. */
#define PNIO_DIAG_CHANPROP_TYPE_SUBMOD 0x00 /* the whole submodule */
#define PNIO_DIAG_CHANPROP_TYPE_1BIT 0x01
#define PNIO_DIAG_CHANPROP_TYPE_2BIT 0x02
#define PNIO_DIAG_CHANPROP_TYPE_4BIT 0x03
#define PNIO_DIAG_CHANPROP_TYPE_BYTE 0x04
#define PNIO_DIAG_CHANPROP_TYPE_WORD 0x05
#define PNIO_DIAG_CHANPROP_TYPE_DWORD 0x06
#define PNIO_DIAG_CHANPROP_TYPE_LWORD 0x07

/* Spec of PNIO_build_channel_properties. */
#define PNIO_DIAG_CHAN_SPEC_ERROR_APPEARS 0x0001      /* appears */
#define PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_FREE 0x0002  /* disappears, no other error */
#define PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_REMAIN 0x0003 /* disappears, others remain
                                                          (alarms only) */

/* Dir of PNIO_build_channel_properties. */
#define PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE 0x0000 /* vendor specific */
#define PNIO_DIAG_CHAN_DIRECTION_INPUT 0x0001
#define PNIO_DIAG_CHAN_DIRECTION_OUTPUT 0x0002
#define PNIO_DIAG_CHAN_DIRECTION_BIDIRECT 0x0003

/* Maintenance bits of ChannelProperties (bits 9 and 10). */
#define PNIO_CHAN_PROP_MAINT_REQUIRED_BIT 0x0200
#define PNIO_CHAN_PROP_MAINT_DEMANDED_BIT 0x0400

/* ChannelErrType of PNIO_diag_channel_add and PNIO_diag_ext_channel_add. */
#define PNIO_DIAG_CHAN_ERROR_SHORT_CIRCUIT 0x0001
#define PNIO_DIAG_CHAN_ERROR_UNDERVOLTAGE 0x0002
#define PNIO_DIAG_CHAN_ERROR_OVERVOLTAGE 0x0003
#define PNIO_DIAG_CHAN_ERROR_OVERLOAD 0x0004
#define PNIO_DIAG_CHAN_ERROR_OVERTEMPERATURE 0x0005
#define PNIO_DIAG_CHAN_ERROR_LINE_BREAK 0x0006
#define PNIO_DIAG_CHAN_ERROR_UPPER_LIMIT_VALUE_EXCEEDED 0x0007
#define PNIO_DIAG_CHAN_ERROR_LOWER_LIMIT_VALUE_EXCEEDED 0x0008
#define PNIO_DIAG_CHAN_ERROR 0x0009 /* error */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_PARAM 0x0010     /* parameterisation */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_SUPPLY 0x0011    /* power supply */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_FUSE 0x0012      /* fuse */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_MANUF 0x0013     /* vendor specific */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_GROUND 0x0014    /* ground fault */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_REF_POINT 0x0015 /* reference point lost */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_PROCESS 0x0016   /* process event lost */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_THRES 0x0017     /* threshold warning */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_OUTPUT 0x0018    /* output disabled */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_SAFETY 0x0019    /* safety event */
#define PNIO_DIAG_CHAN_ERROR_MANUFACTURER_SPECIFIC_EXTERNAL 0x001A  /* external fault */
#define PNIO_DIAG_CHAN_ERROR_DATA_TRANSMISSION 0x8000 /* data transmission impossible */
#define PNIO_DIAG_CHAN_ERROR_REMOTE_MISMATCH 0x8001
#define PNIO_DIAG_CHAN_ERROR_MEDIA_REDUND 0x8002      /* media redundancy mismatch */
#define PNIO_DIAG_CHAN_ERROR_SYNC_MISMATCH 0x8003
#define PNIO_DIAG_CHAN_ERROR_ISOCH_MISMATCH 0x8004    /* isochronous mode mismatch */
#define PNIO_DIAG_CHAN_ERROR_MULTICAST_CR 0x8005      /* multicast CR mismatch */
#define PNIO_DIAG_CHAN_ERROR_MULTICAST_PROV 0x8006    /* multicast provider status mismatch */

/* ---- Structs ------------------------------------------------------------------------- */

/* A device address: always geographical (AddrType PNIO_ADDR_GEO), u.Geo.Slot and
 * u.Geo.Subslot. IODataType says which data of the submodule is meant where it matters. */
typedef struct {
    PNIO_ADDR_TYPE AddrType; /* PNIO_ADDR_GEO */
    PNIO_IO_TYPE IODataType; /* PNIO_IO_IN or PNIO_IO_OUT */
    union {
        PNIO_UINT32 RESERVED;
        struct {
            PNIO_UINT32 RESERVED1[2];
            PNIO_UINT32 Slot;
            PNIO_UINT32 Subslot;
            PNIO_UINT32 RESERVED2[1];
        } Geo;
    } u;
} ATTR_PACKED PNIO_DEV_ADDR;

/* What the PLC's engineering shows of the device (from its GSDML file). */
typedef struct {
    PNIO_UINT8 deviceType[MAX_DEVICE_TYPE_LENGTH + 1]; /* ProductFamily, NUL-terminated */
    PNIO_UINT8 orderId[MAX_ORDER_ID_LENGTH + 1];       /* OrderNumber, NUL-terminated */
    PNIO_UINT16 hwRevision;                            /* HardwareRelease */
    PNIO_UINT8 swRevisionPrefix;                       /* 'V' of SoftwareRelease "V1.2.3" */
    PNIO_UINT16 swRevision1;                           /* 1 */
    PNIO_UINT16 swRevision2;                           /* 2 */
    PNIO_UINT16 swRevision3;                           /* 3 */
} ATTR_PACKED PNIO_ANNOTATION;

/* A UUID (ARUUID, CMInitiatorObjectUUID), passed by value. */
typedef struct {
    PNIO_UINT32 TimeLow;
    PNIO_UINT16 TimeMid;
    PNIO_UINT16 TimeHiAndVersion;
    PNIO_UINT8 ClockSeqHiAndReserved;
    PNIO_UINT8 ClockSeqLow;
    PNIO_UINT8 Node[6];
} ATTR_PACKED PNIO_UUID_TYPE;

/* A submodule in an IOCR: one whose data object (its data, then its IOPS) the frames carry. */
typedef struct {
    PNIO_UINT32 SlotNum;
    PNIO_UINT32 SubslotNum;
    PNIO_UINT32 reserved; /* procimg: the data object's first byte in the frames' C_SDU */
} ATTR_PACKED PNIO_IOCS_TYPE;

/* An IO communication relation: one input or output frame of an AR. */
typedef struct {
    PNIO_UINT32 CycleTime;              /* in ms: SendClock x 31.25 us x ReductioFactor,
                                           rounded down */
    PNIO_IOCR_TYPE_ENUM Direction;      /* PNIO_IOCR_TYPE_* */
    PNIO_IOCR_PROP_ENUM IOCRProperties; /* PNIO_IOCR_PROP_*: mask with RT_CLASS_MASK */
    PNIO_UINT32 SendClock;              /* in 31.25 us units */
    PNIO_UINT32 ReductioFactor;         /* sent every ReductioFactor send clocks */
    PNIO_UINT32 Phase;
    PNIO_UINT32 NumOfIoCs;              /* elements of pIoCsList */
    PNIO_IOCS_TYPE *pIoCsList;          /* the submodules in this frame */
    PNIO_UINT32 reserved[3];            /* procimg: [0] the FrameID of the frames, [1] their
                                           C_SDU length in bytes, [2] 0 */
} ATTR_PACKED PNIO_IOCR_TYPE;

/* A submodule of an AR. Lengths are in bytes; In* is the data the device sends. */
typedef struct {
    PNIO_UINT32 SlotNum;
    PNIO_UINT32 SubSlotNum;
    PNIO_UINT32 SubMProperties; /* mask with PNIO_SUB_PROP_TYPE_MASK */
    PNIO_UINT32 SubMIdent;      /* SubmoduleIdentNumber */
    PNIO_UINT32 InDatLen;
    PNIO_UINT32 InIopsLen;      /* the device's IOPS of its inputs */
    PNIO_UINT32 InIocsLen;      /* the PLC's IOCS of them */
    PNIO_UINT32 OutDatLen;
    PNIO_UINT32 OutIopsLen;     /* the PLC's IOPS of its outputs */
    PNIO_UINT32 OutIocsLen;     /* the device's IOCS of them */
    PNIO_UINT32 reserved[8];
} ATTR_PACKED PNIO_SUBMOD_TYPE;

/* A module of an AR and its submodules. The manual names the first field API, IO-Base's
 * header Api: both names work. */
typedef struct {
    union {
        PNIO_UINT32 Api;
        PNIO_UINT32 API;
    };
    PNIO_UINT32 SlotNum;
    PNIO_UINT32 NumOfSubmod;       /* elements of pSubList */
    PNIO_UINT32 ModProperties;     /* reserved, 0 */
    PNIO_UINT32 ModIdent;          /* ModuleIdentNumber */
    PNIO_SUBMOD_TYPE *pSubList;
} ATTR_PACKED PNIO_MODULE_TYPE;

/* An AR. In PNIO_CBF_AR_CHECK_IND only ArNumber and SessionKey are filled (NumOfMod 0,
 * pModList NULL); in PNIO_CBF_AR_INFO_IND also its IOCRs and modules. Read only. */
typedef struct {
    union {
        void *pNextAr;   /* don't care */
        void *pReserved; /* the same, as the manual names it */
    };
    PNIO_UINT16 ArNumber;       /* keep it with SessionKey for the calls about this AR */
    PNIO_UINT16 SessionKey;     /* grows with every AR */
    PNIO_UINT32 NumOfIocr;      /* elements of pIoCrList */
    PNIO_IOCR_TYPE *pIoCrList;
    PNIO_UINT32 NumOfMod;       /* elements of pModList */
    PNIO_MODULE_TYPE *pModList;
} ATTR_PACKED PNIO_AR_TYPE;

/* A link of a doubly linked list (PNIO_set_appl_state_ready). A head whose Flink is NULL
 * or the head itself is an empty list. */
typedef struct pnio_list_entry_tag {
    struct pnio_list_entry_tag *Flink; /* next */
    struct pnio_list_entry_tag *Blink; /* previous */
} ATTR_PACKED PNIO_LIST_ENTRY_TYPE;

/* The submodules that are not ready, by API, slot and subslot, each once. */
typedef struct {
    PNIO_LIST_ENTRY_TYPE ap_list; /* of PNIO_APPL_READY_AP_TYPE */
} ATTR_PACKED PNIO_APPL_READY_LIST_TYPE;

typedef struct {
    PNIO_LIST_ENTRY_TYPE link;        /* first: the list entry is the element */
    PNIO_UINT32 api;
    PNIO_LIST_ENTRY_TYPE module_list; /* of PNIO_APPL_READY_MODULE_TYPE */
} ATTR_PACKED PNIO_APPL_READY_AP_TYPE;

typedef struct {
    PNIO_LIST_ENTRY_TYPE link;
    PNIO_UINT16 slot_nr;
    PNIO_LIST_ENTRY_TYPE submodule_list; /* of PNIO_APPL_READY_SUBMODULE_TYPE */
} ATTR_PACKED PNIO_APPL_READY_MODULE_TYPE;

typedef struct {
    PNIO_LIST_ENTRY_TYPE link;
    PNIO_UINT16 subslot_nr;
} ATTR_PACKED PNIO_APPL_READY_SUBMODULE_TYPE;

/* Building such a list: the head and entries are PNIO_LIST_ENTRY_TYPE pointers (an
 * element's link). Circular: an empty head points to itself. */
#define PNIO_LIST_INITIALIZE(ListHead_)                                                   \
    do {                                                                                  \
        (ListHead_)->Flink = (ListHead_)->Blink = (ListHead_);                            \
    } while (0)
#define PNIO_LIST_IS_EMPTY(ListHead_)                                                     \
    ((ListHead_)->Flink == NULL || (ListHead_)->Flink == (ListHead_))
#define PNIO_LIST_INSERT_HEAD(ListHead_, Entry_)                                          \
    do {                                                                                  \
        (Entry_)->Flink = (ListHead_)->Flink;                                             \
        (Entry_)->Blink = (ListHead_);                                                    \
        (ListHead_)->Flink->Blink = (Entry_);                                             \
        (ListHead_)->Flink = (Entry_);                                                    \
    } while (0)
#define PNIO_LIST_INSERT_TAIL(ListHead_, Entry_)                                          \
    do {                                                                                  \
        (Entry_)->Flink = (ListHead_);                                                    \
        (Entry_)->Blink = (ListHead_)->Blink;                                             \
        (ListHead_)->Blink->Flink = (Entry_);                                             \
        (ListHead_)->Blink = (Entry_);                                                    \
    } while (0)
#define PNIO_LIST_REMOVE_ENTRY(Entry_)                                                    \
    do {                                                                                  \
        PNIO_LIST_ENTRY_TYPE *pnio_list_entry_ = (Entry_);                                \
        pnio_list_entry_->Blink->Flink = pnio_list_entry_->Flink;                         \
        pnio_list_entry_->Flink->Blink = pnio_list_entry_->Blink;                         \
    } while (0)
/* The first element as Type_ (a pointer type), or NULL. */
#define PNIO_LIST_FIRST(ListHead_, Type_)                                                 \
    ((Type_)(PNIO_LIST_IS_EMPTY(ListHead_) ? NULL : (void *)(ListHead_)->Flink))
/* The element after Entry_ as Type_, or NULL at the end. */
#define PNIO_LIST_NEXT(ListHead_, Entry_, Type_)                                          \
    ((Type_)((Entry_)->Flink == (ListHead_) ? NULL : (void *)(Entry_)->Flink))

/* The header of an I&M record (big-endian on the wire; BlockVersion 1.0). A plain struct:
 * 6 bytes. */
typedef struct {
    PNIO_UINT16 BlockType;   /* 0x0020 + n for I&Mn */
    PNIO_UINT16 BlockLength; /* bytes after BlockType and BlockLength */
    PNIO_UINT8 BlockVersionHigh;
    PNIO_UINT8 BlockVersionLow;
} PNIO_BLOCK_HEADER;

/* I&M0 (record 0xAFF0, read only). 16-bit fields are big-endian. */
typedef struct {
    PNIO_BLOCK_HEADER BlockHeader;
    PNIO_UINT8 VendorIDHigh;
    PNIO_UINT8 VendorIDLow;
    PNIO_UINT8 OrderID[20];               /* blank-padded */
    PNIO_UINT8 IM_Serial_Number[16];      /* blank-padded */
    PNIO_UINT16 IM_Hardware_Revision;
    PNIO_UINT8 IM_Software_Revision[4];   /* prefix, functional, bug fix, internal */
    PNIO_UINT16 IM_Revision_Counter;      /* after 0xFFFF comes 1 */
    PNIO_UINT16 IM_Profile_ID;            /* 0xF600: generic device */
    PNIO_UINT16 IM_Profile_Specific_Type;
    PNIO_UINT8 IM_Version_Major;          /* 1 */
    PNIO_UINT8 IM_Version_Minor;          /* 1 */
    PNIO_UINT16 IM_Supported;             /* bit n: I&Mn supported (n = 1..4) */
} ATTR_PACKED PNIO_IM0_TYPE;

/* I&M1 (record 0xAFF1). */
typedef struct {
    PNIO_BLOCK_HEADER BlockHeader;
    PNIO_UINT8 IM_Tag_Function[32];
    PNIO_UINT8 IM_Tag_Location[22];
} ATTR_PACKED PNIO_IM1_TYPE;

/* I&M2 (record 0xAFF2). */
typedef struct {
    PNIO_BLOCK_HEADER BlockHeader;
    PNIO_UINT8 IM_Date[16]; /* "YYYY-MM-DD hh:mm" */
} ATTR_PACKED PNIO_IM2_TYPE;

/* I&M3 (record 0xAFF3). */
typedef struct {
    PNIO_BLOCK_HEADER BlockHeader;
    PNIO_UINT8 IM_Descriptor[54];
} ATTR_PACKED PNIO_IM3_TYPE;

/* I&M4 (record 0xAFF4). */
typedef struct {
    PNIO_BLOCK_HEADER BlockHeader;
    PNIO_UINT8 IM_Signature[54];
} ATTR_PACKED PNIO_IM4_TYPE;

/* ---- Callbacks ----------------------------------------------------------------------- */

/* Callbacks run on threads of the library. Inside one only PNIO_initiate_data_read(_ext),
 * PNIO_initiate_data_write(_ext), PNIO_CP_set_opdone and PNIO_CP_trigger_watchdog may be
 * called. Pointers passed to a callback are valid during the call only. */

/* Inputs: copy at most BufLen bytes into pBuffer; IOremState is the PLC's IOCS of the
 * inputs sent before. Returns the device's IOPS. */
typedef PNIO_IOXS (*PNIO_CBF_DATA_WRITE)(
    PNIO_UINT32 DevHndl,
    PNIO_DEV_ADDR *pAddr,
    PNIO_UINT32 BufLen,
    PNIO_UINT8 *pBuffer,   /* out */
    PNIO_IOXS IOremState); /* in */

/* Outputs: take BufLen bytes from pBuffer; IOremState is the PLC's IOPS. Returns the
 * device's IOCS. */
typedef PNIO_IOXS (*PNIO_CBF_DATA_READ)(
    PNIO_UINT32 DevHndl,
    PNIO_DEV_ADDR *pAddr,
    PNIO_UINT32 BufLen,
    PNIO_UINT8 *pBuffer,   /* in */
    PNIO_IOXS IOremState); /* in */

/* A record read: write at most *pBufLen bytes, set *pBufLen to the bytes written and
 * *pPnioState (all 0: success). */
typedef void (*PNIO_CBF_REC_READ)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT32 Api,
    PNIO_UINT16 ArNumber,
    PNIO_UINT16 SessionKey,
    PNIO_UINT32 SequenceNum,
    PNIO_DEV_ADDR *pAddr,
    PNIO_UINT32 RecordIndex,
    PNIO_UINT32 *pBufLen,        /* in: room, out: bytes written */
    PNIO_UINT8 *pBuffer,         /* out */
    PNIO_ERR_STAT *pPnioState);  /* out */

/* A record write of *pBufLen bytes. */
typedef void (*PNIO_CBF_REC_WRITE)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT32 Api,
    PNIO_UINT16 ArNumber,
    PNIO_UINT16 SessionKey,
    PNIO_UINT32 SequenceNum,
    PNIO_DEV_ADDR *pAddr,
    PNIO_UINT32 RecordIndex,
    PNIO_UINT32 *pBufLen,        /* in: bytes */
    PNIO_UINT8 *pBuffer,         /* in */
    PNIO_ERR_STAT *pPnioState);  /* out */

/* The PLC acknowledged an alarm (UserHndl as given to the send function). */
typedef void (*PNIO_CBF_REQ_DONE)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT32 UserHndl,
    PNIO_UINT32 Status,          /* PNIO_OK or an error code */
    PNIO_ERR_STAT *pPnioState);  /* the acknowledgement's PNIO status */

/* The PLC expects something else at pAddr than is plugged there: report what is. */
typedef void (*PNIO_CBF_CHECK_IND)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT32 Api,
    PNIO_UINT16 ArNumber,
    PNIO_UINT16 SessionKey,
    PNIO_DEV_ADDR *pAddr,
    PNIO_UINT32 *pModIdent,  /* out */
    PNIO_UINT16 *pModState,  /* out: PNIO_MOD_STATE_* */
    PNIO_UINT32 *pSubIdent,  /* out */
    PNIO_UINT16 *pSubState); /* out: PNIO_SUB_CHECK_* */

/* A PLC connects: keep pAr->ArNumber and pAr->SessionKey. */
typedef void (*PNIO_CBF_AR_CHECK_IND)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT32 HostIp,          /* the PLC's IP address */
    PNIO_UINT16 ArType,          /* PNIO_AR_TYPE_* */
    PNIO_UUID_TYPE ArUUID,
    PNIO_UINT32 ArProperties,
    PNIO_UUID_TYPE CmiObjUUID,   /* the initiator's object UUID */
    PNIO_UINT16 CmiStationNameLength,
    PNIO_UINT8 *pCmiStationName, /* the initiator's station name, not NUL-terminated */
    PNIO_AR_TYPE *pAr);

/* The AR's IOCRs, modules and submodules. */
typedef void (*PNIO_CBF_AR_INFO_IND)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT16 ArNumber,
    PNIO_UINT16 SessionKey,
    PNIO_AR_TYPE *pAR);

/* Cyclic data exchange began (maybe before PNIO_set_appl_state_ready returned). */
typedef void (*PNIO_CBF_AR_INDATA_IND)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT16 ArNumber,
    PNIO_UINT16 SessionKey);

/* The AR ended before data exchange. */
typedef void (*PNIO_CBF_AR_ABORT_IND)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT16 ArNumber,
    PNIO_UINT16 SessionKey,
    PNIO_AR_REASON ReasonCode);

/* The AR ended after data exchange had begun. */
typedef void (*PNIO_CBF_AR_OFFLINE_IND)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT16 ArNumber,
    PNIO_UINT16 SessionKey,
    PNIO_AR_REASON ReasonCode);

/* The PLC's state changed. */
typedef void (*PNIO_CBF_APDU_STATUS_IND)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT16 ArNumber,
    PNIO_UINT16 SessionKey,
    PNIO_APDU_STATUS_IND ApduStatus);

/* The PLC ended parameterising: of all submodules (SubslotNum 0) or, after a plug, of the
 * one at Api, SlotNum, SubslotNum. */
typedef void (*PNIO_CBF_PRM_END_IND)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT16 ArNumber,
    PNIO_UINT16 SessionKey,
    PNIO_UINT32 Api,
    PNIO_UINT16 SlotNum,
    PNIO_UINT16 SubslotNum);

/* A remote download or reconfiguration asks the program to close the device. */
typedef void (*PNIO_CBF_CP_STOP_REQ)(PNIO_UINT32 DevHndl);

/* PNIO_device_stop finished. */
typedef void (*PNIO_CBF_DEVICE_STOPPED)(PNIO_UINT32 DevHndl, PNIO_UINT32 ErrorCode);

/* Identification: flash at Frequency Hz until STOP_LED_FLASH. */
typedef void (*PNIO_CBF_START_LED_FLASH)(PNIO_UINT32 DevHndl, PNIO_UINT32 Frequency);
typedef void (*PNIO_CBF_STOP_LED_FLASH)(PNIO_UINT32 DevHndl);

/* A plug or pull finished (ErrorCode PNIO_OK or why not). */
typedef void (*PNIO_CBF_PULL_PLUG_CONF)(
    PNIO_UINT32 DevHndl,
    PNIO_UINT32 Api,
    PNIO_DEV_ACTION Action,
    PNIO_DEV_ADDR *pAddr,
    PNIO_UINT32 ErrorCode);

/* The callbacks given to PNIO_device_open. All but the last three are mandatory. */
typedef struct {
    PNIO_UINT32 size; /* sizeof(PNIO_CBF_FUNCTIONS): says which version of the table */
    PNIO_CBF_DATA_WRITE cbf_data_write;
    PNIO_CBF_DATA_READ cbf_data_read;
    PNIO_CBF_REC_READ cbf_rec_read;
    PNIO_CBF_REC_WRITE cbf_rec_write;
    PNIO_CBF_REQ_DONE cbf_alarm_done;
    PNIO_CBF_CHECK_IND cbf_check_ind;
    PNIO_CBF_AR_CHECK_IND cbf_ar_check_ind;
    PNIO_CBF_AR_INFO_IND cbf_ar_info_ind;
    PNIO_CBF_AR_INDATA_IND cbf_ar_indata_ind;
    PNIO_CBF_AR_ABORT_IND cbf_ar_abort_ind;
    PNIO_CBF_AR_OFFLINE_IND cbf_ar_offline_ind;
    PNIO_CBF_APDU_STATUS_IND cbf_apdu_status_ind;
    PNIO_CBF_PRM_END_IND cbf_prm_end_ind;
    PNIO_CBF_CP_STOP_REQ pnio_cbf_cp_stop_req;       /* IO-Base's header: cbf_cp_stop_req */
    PNIO_CBF_DEVICE_STOPPED pnio_cbf_device_stopped; /* IO-Base's header: cbf_device_stopped */
    PNIO_CBF_START_LED_FLASH cbf_start_led_flash; /* optional */
    PNIO_CBF_STOP_LED_FLASH cbf_stop_led_flash;   /* optional */
    PNIO_CBF_PULL_PLUG_CONF cbf_pull_plug_conf;   /* optional; needed to plug and pull
                                                     after PNIO_device_start */
} ATTR_PACKED PNIO_CBF_FUNCTIONS;

/* The manual's name of the struct, and IO-Base's header's names of two members: a plain
 * struct of the manual's members in its order, so that positional and designated
 * initializers alike compile with every warning on. */
#define PNIO_CFB_FUNCTIONS PNIO_CBF_FUNCTIONS
#define cbf_cp_stop_req pnio_cbf_cp_stop_req
#define cbf_device_stopped pnio_cbf_device_stopped

/* ---- Functions: the device ----------------------------------------------------------- */

/* Opens the device and registers its callbacks. ExtPar must have PNIO_CEP_MODE_CTRL;
 * InstanceId is 1; MaxAr 1 (RT), 2 (RT and IRT) or 3 (and a supervisor), or
 * PNIO_DEVICE_SET_MAXAR_BY_TYPE with PNIO_CEP_DEV_MAXAR_BY_TYPE. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_device_open(
    PNIO_UINT32 CpIndex,              /* in */
    PNIO_UINT32 ExtPar,               /* in: PNIO_CEP_* */
    PNIO_UINT16 VendorId,             /* in: the GSDML's VendorID */
    PNIO_UINT16 DeviceId,             /* in: the GSDML's DeviceID */
    PNIO_UINT16 InstanceId,           /* in */
    PNIO_UINT32 MaxAr,                /* in */
    PNIO_ANNOTATION *pDevAnnotation,  /* in */
    PNIO_CBF_FUNCTIONS *pCbf,         /* in */
    PNIO_UINT32 *pDevHndl);           /* out */

/* PNIO_device_open with the highest slot and subslot numbers the device uses. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_device_open_ext(
    PNIO_UINT32 CpIndex,              /* in */
    PNIO_UINT32 ExtPar,               /* in */
    PNIO_UINT16 VendorId,             /* in */
    PNIO_UINT16 DeviceId,             /* in */
    PNIO_UINT16 InstanceId,           /* in */
    PNIO_UINT32 MaxAr,                /* in */
    PNIO_ANNOTATION *pDevAnnotation,  /* in */
    PNIO_CBF_FUNCTIONS *pCbf,         /* in */
    PNIO_UINT16 highSlotNum,          /* in */
    PNIO_UINT16 highSubslotNum,       /* in */
    PNIO_UINT32 *pDevHndl);           /* out */

/* Closes the device: after PNIO_device_stop was confirmed and every job was; no callback
 * runs once it returned. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_device_close(PNIO_UINT32 DevHndl);

/* Makes the device reachable for PLCs. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_device_start(PNIO_UINT32 DevHndl);

/* Makes it unreachable and ends its ARs; PNIO_CBF_DEVICE_STOPPED confirms. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_device_stop(PNIO_UINT32 DevHndl);

/* Sets the device's state: PNIO_DEVSTAT_OK or PNIO_DEVSTAT_STATION_PROBLEM. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_set_dev_state(
    PNIO_UINT32 DevHndl,   /* in */
    PNIO_UINT32 DevState); /* in */

/* ---- Functions: APIs, modules, submodules -------------------------------------------- */

/* Adds an API (0 for the DAP) with the highest slot and subslot numbers used in it. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_api_add(
    PNIO_UINT32 DevHndl,      /* in */
    PNIO_UINT32 Api,          /* in */
    PNIO_UINT16 MaxSlots,     /* in */
    PNIO_UINT16 MaxSubslots); /* in */

/* PNIO_api_add for a device opened with PNIO_device_open_ext. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_api_add_ext(
    PNIO_UINT32 DevHndl, /* in */
    PNIO_UINT32 Api);    /* in */

PNIO_UINT32 PNIO_CODE_ATTR PNIO_api_remove(
    PNIO_UINT32 DevHndl, /* in */
    PNIO_UINT32 Api);    /* in */

/* Plugs a module (before its submodules); PNIO_CBF_PULL_PLUG_CONF confirms. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_mod_plug(
    PNIO_UINT32 DevHndl,   /* in */
    PNIO_UINT32 Api,       /* in */
    PNIO_DEV_ADDR *pAddr,  /* in: the slot */
    PNIO_UINT32 ModIdent); /* in: ModuleIdentNumber */

/* Pulls a module and its submodules (a pull alarm each); PNIO_CBF_PULL_PLUG_CONF
 * confirms. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_mod_pull(
    PNIO_UINT32 DevHndl,  /* in */
    PNIO_UINT32 Api,      /* in */
    PNIO_DEV_ADDR *pAddr); /* in */

/* Plugs a submodule (deprecated: PNIO_sub_plug_ext_IM). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_sub_plug(
    PNIO_UINT32 DevHndl,   /* in */
    PNIO_UINT32 Api,       /* in */
    PNIO_DEV_ADDR *pAddr,  /* in */
    PNIO_UINT32 SubIdent); /* in: SubmoduleIdentNumber */

/* Plugs a submodule with the alarm type (deprecated: PNIO_sub_plug_ext_IM). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_sub_plug_ext(
    PNIO_UINT32 DevHndl,    /* in */
    PNIO_UINT32 Api,        /* in */
    PNIO_DEV_ADDR *pAddr,   /* in */
    PNIO_UINT32 SubIdent,   /* in */
    PNIO_UINT32 AlarmType); /* in: PNIO_ALARM_TYPE_PLUG or _PLUG_WRONG */

/* Plugs a submodule, with its I&M role. In data exchange the PLC gets a plug alarm and
 * parameterises it again (records, PNIO_CBF_PRM_END_IND, PNIO_set_appl_state_ready);
 * PNIO_CBF_PULL_PLUG_CONF confirms. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_sub_plug_ext_IM(
    PNIO_UINT32 DevHndl,           /* in */
    PNIO_UINT32 Api,               /* in */
    PNIO_DEV_ADDR *pAddr,          /* in: subslot 1..MaxSubslots */
    PNIO_UINT32 SubIdent,          /* in */
    PNIO_UINT32 AlarmType,         /* in: PNIO_ALARM_TYPE_PLUG or _PLUG_WRONG */
    PNIO_PLUG_IM0_BITS IM0_bits);  /* in */

/* Pulls a submodule (a pull alarm); PNIO_CBF_PULL_PLUG_CONF confirms. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_sub_pull(
    PNIO_UINT32 DevHndl,  /* in */
    PNIO_UINT32 Api,      /* in */
    PNIO_DEV_ADDR *pAddr); /* in */

/* ---- Functions: IO data -------------------------------------------------------------- */

/* Calls PNIO_CBF_DATA_WRITE for every submodule with inputs in an IO AR; returns when all
 * returned. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_initiate_data_write(PNIO_UINT32 DevHndl);

/* The same for the submodules pAddr selects (NULL: all, subslot 0: the slot's) and the
 * data AccessType selects. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_initiate_data_write_ext(
    PNIO_UINT32 DevHndl,          /* in */
    PNIO_DEV_ADDR *pAddr,         /* in, may be NULL */
    PNIO_ACCESS_ENUM AccessType); /* in */

/* Calls PNIO_CBF_DATA_READ for every submodule with outputs in an IO AR; returns when all
 * returned. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_initiate_data_read(PNIO_UINT32 DevHndl);

/* The same, selected as PNIO_initiate_data_write_ext selects. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_initiate_data_read_ext(
    PNIO_UINT32 DevHndl,          /* in */
    PNIO_DEV_ADDR *pAddr,         /* in, may be NULL */
    PNIO_ACCESS_ENUM AccessType); /* in */

/* ---- Functions: the AR --------------------------------------------------------------- */

/* Application ready for the AR, with the submodules that are not (an empty list, or NULL
 * links, when all are). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_set_appl_state_ready(
    PNIO_UINT32 DevHndl,               /* in */
    PNIO_UINT16 ArNumber,              /* in */
    PNIO_UINT16 SessionKey,            /* in */
    PNIO_APPL_READY_LIST_TYPE *pList); /* in */

/* Aborts the AR: PNIO_CBF_AR_OFFLINE_IND or PNIO_CBF_AR_ABORT_IND follows. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_device_ar_abort(
    PNIO_UINT32 DevHndl,     /* in */
    PNIO_UINT16 ArNumber,    /* in */
    PNIO_UINT16 SessionKey); /* in */

/* ---- Functions: diagnosis ------------------------------------------------------------ */

/* ChannelProperties: Type | Spec << 11 | Dir << 13. */
PNIO_UINT16 PNIO_CODE_ATTR PNIO_build_channel_properties(
    PNIO_UINT32 DevHndl, /* in */
    PNIO_UINT16 Type,    /* in: PNIO_DIAG_CHANPROP_TYPE_* */
    PNIO_UINT16 Spec,    /* in: PNIO_DIAG_CHAN_SPEC_* */
    PNIO_UINT16 Dir);    /* in: PNIO_DIAG_CHAN_DIRECTION_* */

/* Stores a channel diagnosis on a submodule under DiagTag (not 0). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_diag_channel_add(
    PNIO_UINT32 DevHndl,        /* in */
    PNIO_UINT32 Api,            /* in */
    PNIO_DEV_ADDR *pAddr,       /* in */
    PNIO_UINT16 ChannelNum,     /* in: 0..0x7FFF, 0x8000 the submodule */
    PNIO_UINT16 ChannelProp,    /* in */
    PNIO_UINT32 ChannelErrType, /* in: PNIO_DIAG_CHAN_ERROR_* */
    PNIO_UINT16 DiagTag);       /* in */

/* Removes the channel diagnosis DiagTag, or all of the submodule's (DiagTag 0). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_diag_channel_remove(
    PNIO_UINT32 DevHndl,  /* in */
    PNIO_UINT32 Api,      /* in */
    PNIO_DEV_ADDR *pAddr, /* in */
    PNIO_UINT16 DiagTag); /* in */

/* Stores an extended channel diagnosis under DiagTag (not 0). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_diag_ext_channel_add(
    PNIO_UINT32 DevHndl,            /* in */
    PNIO_UINT32 Api,                /* in */
    PNIO_DEV_ADDR *pAddr,           /* in */
    PNIO_UINT16 ChannelNum,         /* in */
    PNIO_UINT16 ChannelProp,        /* in */
    PNIO_UINT16 ChannelErrType,     /* in */
    PNIO_UINT16 ExtChannelErrType,  /* in */
    PNIO_UINT32 ExtChannelAddValue, /* in */
    PNIO_UINT16 DiagTag);           /* in */

/* Removes the extended channel diagnosis DiagTag, or all of them (DiagTag 0). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_diag_ext_channel_remove(
    PNIO_UINT32 DevHndl,  /* in */
    PNIO_UINT32 Api,      /* in */
    PNIO_DEV_ADDR *pAddr, /* in */
    PNIO_UINT16 DiagTag); /* in */

/* Stores a vendor diagnosis under DiagTag (not 0): at most 1404 bytes, big-endian. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_diag_generic_add(
    PNIO_UINT32 DevHndl,         /* in */
    PNIO_UINT32 Api,             /* in */
    PNIO_DEV_ADDR *pAddr,        /* in */
    PNIO_UINT16 ChannelNum,      /* in: 0..0x7FFF */
    PNIO_UINT16 ChannelProp,     /* in */
    PNIO_UINT16 DiagTag,         /* in */
    PNIO_UINT16 UserStructIdent, /* in: 0..0x7FFF */
    PNIO_UINT8 *pInfoData,       /* in */
    PNIO_UINT32 InfoDataLen);    /* in */

/* Removes the vendor diagnosis DiagTag, or all of them (DiagTag 0). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_diag_generic_remove(
    PNIO_UINT32 DevHndl,  /* in */
    PNIO_UINT32 Api,      /* in */
    PNIO_DEV_ADDR *pAddr, /* in */
    PNIO_UINT16 DiagTag); /* in */

/* ---- Functions: alarms --------------------------------------------------------------- */
/* Only after PNIO_set_appl_state_ready; PNIO_CBF_REQ_DONE reports the PLC's
 * acknowledgement with UserHndl. Alarm data is big-endian, at most 172 bytes. */

/* Sends a process alarm. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_process_alarm_send(
    PNIO_UINT32 DevHndl,         /* in */
    PNIO_UINT32 Api,             /* in */
    PNIO_UINT16 ArNumber,        /* in */
    PNIO_UINT16 SessionKey,      /* in */
    PNIO_DEV_ADDR *pAddr,        /* in */
    PNIO_UINT8 *pData,           /* in */
    PNIO_UINT32 DataLen,         /* in */
    PNIO_UINT16 UserStructIdent, /* in */
    PNIO_UINT32 UserHndl);       /* in */

/* Sends a diagnosis alarm for a diagnosis stored (appears) or removed (disappears)
 * before. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_diag_alarm_send(
    PNIO_UINT32 DevHndl,         /* in */
    PNIO_UINT32 Api,             /* in */
    PNIO_UINT16 ArNumber,        /* in */
    PNIO_UINT16 SessionKey,      /* in */
    PNIO_UINT32 AlarmState,      /* in: PNIO_STATE_ALARM_* */
    PNIO_DEV_ADDR *pAddr,        /* in */
    PNIO_UINT8 *pData,           /* in */
    PNIO_UINT32 DataLen,         /* in */
    PNIO_UINT16 UserStructIdent, /* in: PNIO_USR_STRUC_ID_* or 0..0x7FFF */
    PNIO_UINT32 UserHndl);       /* in */

/* Sends a return-of-submodule alarm: the submodule works again (its IOxS GOOD). */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_ret_of_sub_alarm_send(
    PNIO_UINT32 DevHndl,    /* in */
    PNIO_UINT32 Api,        /* in */
    PNIO_UINT16 ArNumber,   /* in */
    PNIO_UINT16 SessionKey, /* in */
    PNIO_DEV_ADDR *pAddr,   /* in */
    PNIO_UINT32 UserHndl);  /* in */

#ifdef __cplusplus
}
#endif

#endif /* PNIOUSRD_H */
