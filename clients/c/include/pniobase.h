/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * pniobase.h - the basic types of procimg's IO-Base compatible API, shared by the controller
 * part (pniousrx.h) and a device part.
 *
 * Written for procimg from the SIMATIC NET IO-Base programming manual's names and types and
 * the numeric values of the 2015 interface, so that an IO-Base program compiles against it
 * unchanged. Structs are "ATTR_PACKED", which IO-Base defines as alignment 4, not byte
 * packing: the natural C layout, with every struct aligned to at least 4 bytes.
 *
 * PN Driver's start-up (SERV_CP_init ... SERV_CP_undo_init) is servusrx.h's, the controller's
 * own interface (PNIO_interface_*) pniousrx.h's. Not here: the PROFIenergy types: procimg
 * does not offer them yet.
 */
#ifndef PNIOBASE_H
#define PNIOBASE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Compiler attributes ------------------------------------------------------------- */

/* Alignment 4 (IO-Base's ATTR_PACKED is not byte packing). */
#ifndef ATTR_PACKED
#if defined(__GNUC__) || defined(__clang__)
#define ATTR_PACKED __attribute__((aligned(4)))
#else
#define ATTR_PACKED
#endif
#endif

/* Calling convention of the API functions: the platform's default on Linux. */
#ifndef PNIO_CODE_ATTR
#define PNIO_CODE_ATTR
#endif

/* ---- Basic types --------------------------------------------------------------------- */

typedef uint8_t PNIO_UINT8;   /* 8 bits unsigned */
typedef uint16_t PNIO_UINT16; /* 16 bits unsigned */
typedef uint32_t PNIO_UINT32; /* 32 bits unsigned (the manual's 32-bit "unsigned long") */
typedef uint32_t PNIO_REF;    /* a user reference, echoed in a confirmation */

/* ---- Limits -------------------------------------------------------------------------- */

#define PNIO_API_VERSION 230         /* the interface version these headers describe */
#define PNIO_MAX_ALARM_DATA_LEN 1472 /* user data bytes of one alarm */
#define PNIO_MAX_IO_LEN 254          /* data bytes of one submodule */
#define PNIO_MAX_REC_LEN 4096        /* bytes of one record read */

/* ---- ExtPar flags of PNIO_controller_open ------------------------------------------- */

#define PNIO_CEP_MODE_CTRL 0x00000002             /* the program may change the mode */
#define PNIO_CEP_DEV_MAXAR_BY_TYPE 0x00000004     /* device side */
#define PNIO_CEP_SLICE_ACCESS 0x00000008          /* access parts of submodules */
#define PNIO_CEP_DEV_MAXAR_BY_TYPE_ADV 0x00000010 /* device side */
#define PNIO_CEP_PE_MODE_ENABLE 0x00000020        /* device side: PROFIenergy */
#define PNIO_CEP_SET_MRP_ROLE_OFF 0x00000040      /* MRP role off */

/* ---- Enums --------------------------------------------------------------------------- */

/* How a PNIO_ADDR addresses. The controller uses logical addresses only. */
typedef enum {
    PNIO_ADDR_LOG = 0, /* logical address */
    PNIO_ADDR_GEO = 1  /* geographical address */
} PNIO_ADDR_TYPE;

/* The address space: inputs (I) or outputs (Q). */
typedef enum {
    PNIO_IO_IN = 0, /* inputs */
    PNIO_IO_OUT = 1 /* outputs */
} PNIO_IO_TYPE;

/* A data status (IOPS or IOCS). */
typedef enum {
    PNIO_S_GOOD = 0, /* valid */
    PNIO_S_BAD = 1   /* invalid */
} PNIO_IOXS;

/* RT or IRT data (CONFIG_SUBMODULE_LIST). */
typedef enum {
    PNIO_DATA_RT = 0, /* real time */
    PNIO_DATA_IRT = 1 /* isochronous real time */
} PNIO_DATA_TYPE;

/* How a submodule's data travels (CONFIG_SUBMODULE_LIST). */
typedef enum {
    PNIO_COM_UNICAST = 0,       /* device <-> controller */
    PNIO_COM_DIRECT_DATA_EX = 1 /* direct data exchange */
} PNIO_COM_TYPE;

/* The isochronous events (PNIO_CP_register_cbf). */
typedef enum {
    PNIO_CP_CBE_UNKNOWN = 0,     /* no event */
    PNIO_CP_CBE_STARTOP_IND = 1, /* this cycle's inputs are there: start processing */
    PNIO_CP_CBE_OPFAULT_IND = 2, /* PNIO_CP_set_opdone came too late */
    PNIO_CP_CBE_NEWCYCLE_IND = 3 /* a new bus cycle began */
} PNIO_CP_CBE_TYPE;

/* Alarm types (PNIO_CTRL_ALARM_DATA::AlarmType). */
typedef enum {
    PNIO_ALARM_DIAGNOSTIC = 0x01,
    PNIO_ALARM_PROCESS = 0x02,
    PNIO_ALARM_PULL = 0x03,
    PNIO_ALARM_PLUG = 0x04,
    PNIO_ALARM_STATUS = 0x05,
    PNIO_ALARM_UPDATE = 0x06,
    PNIO_ALARM_REDUNDANCY = 0x07,
    PNIO_ALARM_CONTROLLED_BY_SUPERVISOR = 0x08,
    PNIO_ALARM_RELEASED_BY_SUPERVISOR = 0x09,
    PNIO_ALARM_PLUG_WRONG = 0x0A,
    PNIO_ALARM_RETURN_OF_SUBMODULE = 0x0B,
    PNIO_ALARM_DIAGNOSTIC_DISAPPEARS = 0x0C,
    PNIO_ALARM_MCR_MISMATCH = 0x0D,
    PNIO_ALARM_PORT_DATA_CHANGED = 0x0E,
    PNIO_ALARM_SYNC_DATA_CHANGED = 0x0F,
    PNIO_ALARM_ISOCHRONE_MODE_PROBLEM = 0x10,
    PNIO_ALARM_NETWORK_COMPONENT_PROBLEM = 0x11,
    PNIO_ALARM_UPLOAD_AND_STORAGE = 0x1E,
    PNIO_ALARM_PULL_MODULE = 0x1F,
    /* Made by the controller, not sent by a device: */
    PNIO_ALARM_DEV_FAILURE = 0x00010000, /* the device's connection (AR) ended */
    PNIO_ALARM_DEV_RETURN = 0x00010001   /* the device is in data exchange again */
} PNIO_ALARM_TYPE;

/* Alarm priority. */
typedef enum {
    PNIO_APRIO_LOW = 0,
    PNIO_APRIO_HIGH = 1
} PNIO_APRIO_TYPE;

/* ---- Structs ------------------------------------------------------------------------- */

/* An address: for the controller AddrType is PNIO_ADDR_LOG, IODataType the space and
 * u.Addr the logical address. */
typedef struct {
    PNIO_ADDR_TYPE AddrType;
    PNIO_IO_TYPE IODataType;
    union {
        PNIO_UINT32 Addr;        /* logical address */
        PNIO_UINT32 Reserved[5]; /* reserved */
    } u;
} ATTR_PACKED PNIO_ADDR;

/* A PROFINET IO status (IEC 61158-6 PNIOStatus) of a record job, and two more values.
 * (0xC0, 0x80, 0xA3, 0): no connection to the device; (0xDE/0xDF, 0x80, 0xC3, 0): the
 * device is busy, repeat the job. After a successful read AddValue1 = 1 says the record has
 * more data than was read. */
typedef struct {
    PNIO_UINT8 ErrCode;
    PNIO_UINT8 ErrDecode;
    PNIO_UINT8 ErrCode1;
    PNIO_UINT8 ErrCode2;
    PNIO_UINT16 AddValue1;
    PNIO_UINT16 AddValue2;
} ATTR_PACKED PNIO_ERR_STAT;

/* Timing of the current cycle. */
typedef struct {
    PNIO_UINT32 CycleCount;           /* + cycle time per cycle, 31.25 us units, 16 bits:
                                         +32 per 1 ms cycle; another step = lost cycles */
    PNIO_UINT32 ClockCount;           /* free-running clock, 10 ns units, 32 bits */
    PNIO_UINT32 CountSinceCycleStart; /* time since the cycle started, 10 ns units */
} ATTR_PACKED PNIO_CYCLE_INFO;

/* Configuration details of an alarm's source. */
typedef struct {
    PNIO_UINT16 CompatDevGeoaddr; /* bits 0-10 device number, 11-14 IO subsystem, 15 = 1 */
    PNIO_UINT8 ProfileType;       /* 0x08: bits 0-3 PNIO, 4-7 DP */
    PNIO_UINT8 AinfoType;         /* bits 0-3: 0 = transparent */
    PNIO_UINT8 ControllerFlags;   /* bit 0: external DP interface */
    PNIO_UINT8 DeviceFlag;        /* bit 0: APDU status failure */
    PNIO_UINT16 PnioVendorIdent;  /* vendor ID */
    PNIO_UINT16 PnioDevIdent;     /* device ID */
    PNIO_UINT16 PnioDevInstance;  /* device instance */
} ATTR_PACKED PNIO_ALARM_TINFO;

/* The alarm notification (IEC 61158-6 AlarmNotification) with its user data. procimg fills
 * the user data as the device sent it; the union has the plain byte view only. */
typedef struct {
    PNIO_UINT16 BlockType;        /* 0x0001 high, 0x0002 low priority */
    PNIO_UINT16 BlockVersion;
    PNIO_UINT32 Api;
    PNIO_UINT16 AlarmSpecifier;   /* sequence number and diagnosis flags */
    PNIO_UINT32 ModIdent;         /* module ident number */
    PNIO_UINT32 SubIdent;         /* submodule ident number */
    PNIO_UINT16 UserStrucIdent;   /* user structure identifier */
    PNIO_UINT16 UserAlarmDataLen; /* bytes of UAData.UserAlarmData */
    union {
        PNIO_UINT8 UserAlarmData[PNIO_MAX_ALARM_DATA_LEN];
    } UAData;
} ATTR_PACKED PNIO_ALARM_INFO;

/* The parameters of the three isochronous events (the same fields for all three). The
 * manual names the first field CpHandle, IO-Base's header AppHandle: both names work. */
typedef struct {
    union {
        PNIO_UINT32 AppHandle; /* the handle of PNIO_controller_open */
        PNIO_UINT32 CpHandle;  /* the same, as the manual names it */
    };
    PNIO_CYCLE_INFO CycleInfo; /* this cycle's timing */
} ATTR_PACKED PNIO_CP_CBE_PRM_STARTOP_IND;

typedef PNIO_CP_CBE_PRM_STARTOP_IND PNIO_CP_CBE_PRM_OPFAULT_IND;
typedef PNIO_CP_CBE_PRM_STARTOP_IND PNIO_CP_CBE_PRM_NEWCYCLE_IND;

/* What an isochronous callback receives. */
typedef struct {
    PNIO_CP_CBE_TYPE CbeType; /* the event */
    PNIO_UINT32 CpIndex;      /* the CpIndex given to PNIO_controller_open */
    union {
        PNIO_CP_CBE_PRM_STARTOP_IND StartOp;
        PNIO_CP_CBE_PRM_OPFAULT_IND OpFault;
        PNIO_CP_CBE_PRM_NEWCYCLE_IND NewCycle;
    } u;
} ATTR_PACKED PNIO_CP_CBE_PRM;

/* An isochronous callback. The parameters are valid during the call only. */
typedef void (*PNIO_CP_CBF)(PNIO_CP_CBE_PRM *pCbfPrm);

/* ---- Isochronous functions (controller and device) ---------------------------------- */

/* Registers an isochronous callback: a controller in OFFLINE, a device before
 * PNIO_device_start; each type once (else PNIO_ERR_ALLREADY_DONE), OPFAULT before STARTOP
 * (else PNIO_ERR_OPFAULT_NOT_REG), NEWCYCLE before STARTOP (else
 * PNIO_ERR_NEWCYCLE_SEQUENCE_REG). Registering STARTOP makes the controller or device take
 * part in the cycle handshake. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_CP_register_cbf(
    PNIO_UINT32 CpHandle,     /* in: the handle of PNIO_controller_open or PNIO_device_open */
    PNIO_CP_CBE_TYPE CbeType, /* in */
    PNIO_CP_CBF Cbf);         /* in: not NULL */

/* Ends this cycle's processing (OPDONE): the outputs written since STARTOP go out.
 * CycleInfo, when not NULL, receives the timing at this moment. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_CP_set_opdone(
    PNIO_UINT32 CpHandle,        /* in */
    PNIO_CYCLE_INFO *CycleInfo); /* out, may be NULL */

/* ---- The CP application watchdog (controller and device) ---------------------------- */

/* Called once when the watchdog of CPIndex expires (on a thread of the library). */
typedef void (*PNIO_CBF_APPL_WATCHDOG)(PNIO_UINT32 CPIndex);

/* Registers the application watchdog of CPIndex (one per CPIndex in a process: a second
 * gives PNIO_ERR_ALLREADY_DONE); wdTimeOutInMs 0 with pnio_appl_wd_cbf NULL deregisters it
 * (0 with a callback: PNIO_ERR_PRM_TIMEOUT; a timeout with NULL: PNIO_ERR_PRM_CALLBACK).
 * Monitoring starts at the first PNIO_CP_trigger_watchdog. The watchdog is libprocimg's,
 * per process; procimgd does not know it. When no trigger comes within the timeout:
 * every controller and device of this process open on the procimgd instance CPIndex names
 * is stopped (the outputs, a device's I data, it holds go out once more with IOPS BAD, so
 * the devices or the PLC see IOPS BAD; an isochronous one's later cycles end with them BAD
 * and its STARTOP_IND is no longer called), then the callback is called once; from then on
 * every call with such a handle answers PNIO_ERR_NO_FW_COMMUNICATION except
 * PNIO_controller_close and PNIO_device_close (which also stops a started device). Open
 * again to resume; deregister and register to arm the watchdog again. Unlike a real CP,
 * the programs of other processes on the same procimgd instance are not affected. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_CP_set_appl_watchdog(
    PNIO_UINT32 CPIndex,                        /* in: 1..255 */
    PNIO_UINT32 wdTimeOutInMs,                  /* in: 0 to deregister */
    PNIO_CBF_APPL_WATCHDOG pnio_appl_wd_cbf);   /* in: NULL to deregister */

/* Retriggers the watchdog of CPIndex: PNIO_ERR_SEQUENCE when none is registered,
 * PNIO_ERR_NO_FW_COMMUNICATION after it expired. May be called inside callbacks. */
PNIO_UINT32 PNIO_CODE_ATTR PNIO_CP_trigger_watchdog(PNIO_UINT32 CPIndex); /* in: 1..255 */

#ifdef __cplusplus
}
#endif

#endif /* PNIOBASE_H */
