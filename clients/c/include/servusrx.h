/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * servusrx.h - PN Driver's start-up functions in procimg's IO-Base compatible API
 * (libprocimg).
 *
 * A PN Driver program (Siemens' IO controller on a standard Ethernet adapter) starts and
 * ends its stack itself:
 *
 *     SERV_CP_init(&debug or NULL)              first
 *     SERV_CP_get_network_adapters(list, &n)    optional: the adapters to choose from
 *     SERV_CP_startup(&list[i], 1, config, len, rema, rlen, &sysdescr)
 *     PNIO_controller_open(1, ...) ... PNIO_controller_close(handle)
 *     SERV_CP_shutdown()
 *     SERV_CP_undo_init()                       last
 *
 * Such a program compiles unchanged against this header and runs against procimg. Names,
 * types and values are the manual's (chapter 9 of the IO-Base manual, PN Driver V1.0);
 * where the manual prints none (the trace enums, PNIO_SYSTEM_DESCR) they are those of PN
 * Driver's public headers. What follows is how procimg answers the questions the manual
 * leaves open.
 *
 * The stack is a procimgd. SERV_CP_startup starts one for the program (the program named
 * by the environment variable PROCIMGD, else procimgd on PATH), for the instance CpIndex 1
 * names (PROCIMG_CP1, else PROCIMG_INSTANCE, else "procimg": see pniousrx.h), and returns
 * once it serves; SERV_CP_shutdown stops it (outputs to their safe state first). It also
 * stops when the program ends, however it ends: it watches a pipe the program holds.
 * If a procimgd already serves that instance, SERV_CP_startup gives
 * PNIO_ERR_CREATE_INSTANCE: one stack per instance.
 *
 * The configuration. pConfigData is PN Driver's configuration, the XML that TIA Portal
 * exports for it (…PNDriverConfiguration.xml), or procimg's own, the TOML text procimgd
 * reads from a file (`procimgd --print-demo-config` prints a commented example), of
 * ConfigDataLen bytes or up to a NUL byte. procimgd imports the XML as the README's "TIA
 * Portal's PN Driver configuration" says (`procimg config import FILE` shows the result):
 * IRT, isochronous mode, multicast IOCRs and shared devices are refused. Its controller starts
 * OFFLINE, as PN Driver's. What procimgd refuses gives PNIO_ERR_CORRUPTED_DATA; the reason
 * (line and what to do) is in procimg_last_error() (procimg.h). Relative gsdml paths start
 * at the program's current directory.
 *
 * The adapter. SERV_CP_get_network_adapters lists the machine's Ethernet interfaces
 * (those of the network namespace the program runs in; not the loopback), in interface
 * index order, at most PROCIMG_MAX_NETWORK_ADAPTERS of them: CpList must hold that many.
 * Each entry has CpSelection = PNIO_CP_SELECT_WITH_MAC_ADDRESS, the interface's MAC in
 * CpMacAddr, the PCI location of a PCI card in CpPciLocation (zero for a virtual interface),
 * and the interface name ("enp3s0") as the NUL-terminated Description. SERV_CP_startup takes
 * the adapter its entry names, by MAC address, or by PCI location with
 * PNIO_CP_SELECT_WITH_PCI_LOCATION; no such adapter gives PNIO_ERR_CREATE_INSTANCE. The
 * adapter replaces the configuration's `network` interface (which need not exist on this
 * machine: the configuration is written once for all of them); a configuration that simulates
 * its network (`network = "sim"`, as the demo does) keeps its simulation, so a program can
 * be tried without hardware (the adapter is then not used, but must exist).
 *
 * Retentive data. pRemaData is the text PNIO_CBE_REMA_READ_CONF handed out (the station's
 * NameOfStation and IP suite that a program or DCP set to be kept), or NULL / RemaDataLen 0
 * for none. The started controller takes the name and address from it where its
 * configuration lets programs set them ([interface] name_by_program, address_by_program);
 * text that is not procimg's retentive data (another PN Driver's) is PNIO_ERR_INVALID_REMA,
 * and so is a name or address the station cannot take (the stack is then stopped again).
 * pSysDescr may be NULL; procimg reads nothing from it.
 *
 * The trace. procimgd's log is the stack's trace, component PNIO_TRACE_COMP_PND. With a
 * DebugSetting whose CbfPntrcBufferFull is set, SERV_CP_startup sets procimgd's log level
 * from TraceLevels[PNIO_TRACE_COMP_PND] (ERROR: errors, WARN: warnings, NOTE_HIGH and NOTE:
 * progress, NOTE_LOW and CHAT: details), and its lines, text ending in '\n', are gathered
 * in a buffer of PROCIMG_TRACE_BUFFER_SIZE bytes, handed to the callback (on a library
 * thread) when the next line does not fit, and once more at SERV_CP_shutdown.
 * SERV_CP_set_trace_level(PNIO_TRACE_COMP_PND, ...) changes which lines are kept, within the
 * level procimgd was started with; the other components' levels are kept and used by
 * nothing (procimgd's log is one). Its CbfSetTraceLevelDone, if not NULL, is called on a
 * library thread once the level holds. Without the callback (DebugSetting NULL, or
 * CbfPntrcBufferFull NULL) procimgd's log goes to the program's standard error.
 *
 * Order. SERV_CP_init first and once (else PNIO_ERR_SEQUENCE), SERV_CP_startup once after
 * it, SERV_CP_set_trace_level after startup, SERV_CP_shutdown after startup and after every
 * controller is closed, SERV_CP_undo_init after shutdown (or without startup); then
 * SERV_CP_init may start again. In a program that called SERV_CP_init, PNIO_controller_open
 * before SERV_CP_startup gives PNIO_ERR_SEQUENCE. A program that never calls SERV_CP_init
 * opens controllers on procimgd instances that run already, as a CP 1616 program does.
 *
 * The CP service functions (chapter 8 of the manual) that procimg has: SERV_CP_get_fw_info
 * tells the firmware of the CP that CpIndex names (see pniousrx.h): procimgd's version
 * (fw_version 0.1.0 -> v1 0, v2 1, v3 0), the instance name as cp_ser_nr (a procimgd has no
 * board serial number), the order number ("procimgd" for a controller, the station's I&M0
 * OrderID in the device role), the hardware revision (0 for a controller, the station's
 * I&M0 one), the interface's MAC in mac, its IPv4 address, mask and default router (network
 * byte order, as struct in_addr holds them), the station name and the type of station. No
 * procimgd serving that instance gives PNIO_ERR_NO_FW_COMMUNICATION. It may be called
 * without SERV_CP_init, as on a CP; so may the three below.
 *
 * SERV_CP_set_type_of_station sets what the procimgd's station reports by DCP (the
 * controller's type of station, the device role's device type) from its next start on, as
 * on a CP after its reset: SERV_CP_reset. SERV_CP_download takes a configuration
 * (PNIO_CP_DLD_CONFIG: procimg's TOML text or PN Driver's XML, which runs on the
 * procimgd's interface; anything procimgd would refuse at start is
 * PNIO_ERR_CORRUPTED_DATA, a firmware file PNIO_ERR_PRM_TYPE):
 * every program attached to that procimgd gets PNIO_CBE_CP_STOP_REQ (a device program its
 * cbf_cp_stop_req) and is to close; once none is attached, procimgd starts anew with the
 * configuration (a procimgd started with -c FILE keeps it in FILE) and the call returns
 * PNIO_OK. A program still attached after 10 s makes it PNIO_ERR_MAX_REACHED, nothing
 * changed. SERV_CP_reset starts procimgd anew with its configuration: SAFE only when no
 * program is attached (else PNIO_ERR_MAX_REACHED), FORCE after asking them to stop, after
 * 10 s whoever stays. The caller itself must have no controller, device or interface open
 * (PNIO_ERR_MAX_REACHED: the manual's exclusive access).
 *
 * The info interface (SERV_CP_info_open, _register_cbf, _close) delivers, on a thread of
 * the library, one callback at a time: SERV_CP_INFO_STOP_REQ before a restart (close what is
 * open, outside the callback); of a controller's procimgd, SERV_CP_INFO_PDEV_DATA for each
 * alarm of its port (the topology and link check of pniousrx.h's own interface), with
 * SERV_CP_INFO_PDEV_INIT_DATA once when PDEV_DATA is registered (the interface and its port,
 * EXISTS, DISTURBED while a diagnosis is pending); and SERV_CP_INFO_LED_STATE, the current
 * state of both LEDs when it is registered and every change after: BF (bus fault) lit while
 * a device of the IO system is not in data exchange (a deactivated one does not count), or
 * in the device role while the station has no AR in data exchange; SF (group fault) while
 * the controller's port has a diagnosis. A NULL Cbf deregisters; a second registration is
 * PNIO_ERR_ALREADY_DONE.
 *
 * The layout of PNIO_DEBUG_SETTINGS_TYPE is the manual's (PN Driver V1.0: the callback,
 * then the levels); PN Driver V2.1 inserts a second callback between them, so a V2.1
 * program's DebugSetting does not fit.
 */
#ifndef SERVUSRX_H
#define SERVUSRX_H

#include "pniobase.h"
#include "pnioerrx.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- procimg's limits ------------------------------------------------------------------ */

/* Most entries SERV_CP_get_network_adapters writes (PN Driver's samples allow 50). */
#define PROCIMG_MAX_NETWORK_ADAPTERS 50
/* Bytes of trace gathered before CbfPntrcBufferFull is called. */
#define PROCIMG_TRACE_BUFFER_SIZE 65536

/* ---- Trace components and levels (PN Driver's public headers) --------------------------- */

typedef enum {
    PNIO_TRACE_COMP_ACP = 0,
    PNIO_TRACE_COMP_CLRPC = 1,
    PNIO_TRACE_COMP_CM = 2,
    PNIO_TRACE_COMP_DCP = 3,
    PNIO_TRACE_COMP_EDDI = 4,
    PNIO_TRACE_COMP_EDDS = 5,
    PNIO_TRACE_COMP_EPS = 6,
    PNIO_TRACE_COMP_GSY = 7,
    PNIO_TRACE_COMP_HIF = 8,
    PNIO_TRACE_COMP_LLDP = 9,
    PNIO_TRACE_COMP_NARE = 10,
    PNIO_TRACE_COMP_OHA = 11,
    PNIO_TRACE_COMP_PNTRC = 12,
    PNIO_TRACE_COMP_PSI = 13,
    PNIO_TRACE_COMP_SNMPX = 14,
    PNIO_TRACE_COMP_SOCK = 15,
    PNIO_TRACE_COMP_TCIP = 16,
    PNIO_TRACE_COMP_PND = 17,
    PNIO_TRACE_COMP_NUM = 18
} pnio_stack_comp;

typedef enum {
    PNIO_TRACE_LEVEL_OFF = 0,
    PNIO_TRACE_LEVEL_FATAL = 1,
    PNIO_TRACE_LEVEL_ERROR = 2,
    PNIO_TRACE_LEVEL_UNEXP = 3,
    PNIO_TRACE_LEVEL_WARN = 4,
    PNIO_TRACE_LEVEL_NOTE_HIGH = 5,
    PNIO_TRACE_LEVEL_NOTE = 6,
    PNIO_TRACE_LEVEL_NOTE_LOW = 7,
    PNIO_TRACE_LEVEL_CHAT = 8,
    PNIO_TRACE_LEVEL_NUM = 9
} pnio_trace_level;

/* ---- Chapter 9's types ------------------------------------------------------------------ */

typedef enum {
    PNIO_CP_SELECT_WITH_PCI_LOCATION = 1,
    PNIO_CP_SELECT_WITH_MAC_ADDRESS = 2
} PNIO_CP_SELECT_TYPE;

#define PNIO_MAC_ADDR_SIZE 6
typedef PNIO_UINT8 PNIO_MAC_ADDR_TYPE[PNIO_MAC_ADDR_SIZE];

typedef struct pnio_pci_location_s {
    PNIO_UINT16 BusNr;
    PNIO_UINT16 DeviceNr;
    PNIO_UINT16 FunctionNr;
} PNIO_PCI_LOCATION_TYPE, *PNIO_PCI_LOCATION_PTR_TYPE;

typedef void (*PNIO_PNTRC_BUFFER_FULL)(PNIO_UINT8 *pBuffer, PNIO_UINT32 BufferSize);
typedef void (*PNIO_PNTRC_SET_TRACE_LEVEL_DONE)(void);

typedef struct pnio_debug_settings_s {
    PNIO_PNTRC_BUFFER_FULL CbfPntrcBufferFull; /* receives the trace; NULL: no trace */
    PNIO_UINT8 TraceLevels[PNIO_TRACE_COMP_NUM]; /* the first level of each component */
} PNIO_DEBUG_SETTINGS_TYPE, *PNIO_DEBUG_SETTINGS_PTR_TYPE;

typedef struct pnio_cp_id_s {
    PNIO_CP_SELECT_TYPE CpSelection;
    PNIO_MAC_ADDR_TYPE CpMacAddr;
    PNIO_PCI_LOCATION_TYPE CpPciLocation;
    PNIO_UINT8 Description[300];
} PNIO_CP_ID_TYPE, *PNIO_CP_ID_PTR_TYPE;

typedef struct {
    PNIO_UINT8 revision_prefix;
    PNIO_UINT8 functional_enhancement;
    PNIO_UINT8 bug_fix;
    PNIO_UINT8 internal_change;
} PNIO_SW_VERSION_TYPE;

typedef struct {
    PNIO_UINT8 Vendor[128];
    PNIO_UINT8 ProductFamily[128];
    PNIO_UINT8 ProductSerialNr[128];
    PNIO_UINT8 IM_DeviceType[25 + 1];
    PNIO_UINT8 IM_OrderId[20 + 1];
    PNIO_UINT16 IM_HwRevision;
    PNIO_SW_VERSION_TYPE IM_SwVersion;
    PNIO_UINT16 IM_RevisionCounter;
    PNIO_UINT16 IM_Version;
    PNIO_UINT16 IM_Supported;
    PNIO_UINT16 IM_ProfileSpecificType;
    PNIO_UINT16 IM_ProfileId;
} PNIO_SYSTEM_DESCR;

/* ---- Chapter 8's firmware information --------------------------------------------------- */

typedef struct {
    PNIO_UINT16 v1, v2, v3, v4, v5, reserved; /* V1.2.3 -> v1 1, v2 2, v3 3 */
} SERV_FW_VERS_TYPE;

typedef struct {
    SERV_FW_VERS_TYPE fw_version;
    PNIO_UINT8 cp_ser_nr[16];       /* NUL-terminated */
    PNIO_UINT8 mlfb[32];            /* order number, NUL-terminated */
    PNIO_UINT16 hw_version;
    PNIO_UINT8 mac[6];
    PNIO_UINT32 ip_addr;            /* network byte order */
    PNIO_UINT32 ip_mask;            /* network byte order */
    PNIO_UINT32 default_router;     /* network byte order */
    PNIO_UINT8 name[256];           /* NameOfStation, NUL-terminated */
    PNIO_UINT8 TypeOfStation[256];  /* NUL-terminated */
} SERV_CP_FW_INFO_TYPE;

/* ---- Chapter 8's download and reset ------------------------------------------------------ */

typedef enum {
    PNIO_CP_DLD_FIRMWARE = 1, /* refused: procimgd is updated as a package */
    PNIO_CP_DLD_CONFIG = 2    /* a configuration: procimg's TOML or PN Driver's XML */
} PNIO_CP_DLD_TYPE;

typedef enum {
    PNIO_CP_RESET_SAFE = 0,  /* only with no program attached */
    PNIO_CP_RESET_FORCE = 1  /* programs are asked to stop, then it restarts anyway */
} PNIO_CP_RESET_TYPE;

/* ---- Chapter 8's info interface ----------------------------------------------------------- */

typedef enum {
    SERV_CP_INFO_STOP_REQ = 1,       /* the procimgd is to restart: close */
    SERV_CP_INFO_PDEV_DATA = 2,      /* an alarm of the controller's port */
    SERV_CP_INFO_PDEV_INIT_DATA = 3, /* the ports' states (with PDEV_DATA's registration) */
    SERV_CP_INFO_LED_STATE = 4       /* the BF or SF LED changed */
} SERV_CP_INFO_TYPE;

typedef struct {
    PNIO_UINT16 Channel;    /* 0x8000: the whole submodule */
    PNIO_UINT16 Properties; /* ChannelProperties */
    PNIO_UINT16 ErrType;    /* ChannelErrorType */
    PNIO_UINT16 ExtErrType; /* ExtChannelErrorType */
    PNIO_UINT16 ExtAdvAlLo; /* ExtChannelAddValue, low word */
    PNIO_UINT16 ExtAdvAlHi; /* ExtChannelAddValue, high word */
} ATTR_PACKED SERV_CIB_PDEV_EXTCHNL_DIAG;

typedef struct {
    PNIO_UINT32 Version;            /* 0 */
    PNIO_IO_TYPE IODataType;        /* PNIO_IO_IN */
    PNIO_UINT32 LogAddr;            /* the submodule's diagnostic address */
    PNIO_UINT32 Slot;
    PNIO_UINT32 Subslot;
    PNIO_ALARM_TYPE AlarmType;      /* PNIO_ALARM_PORT_DATA_CHANGED */
    PNIO_APRIO_TYPE AlarmPriority;
    PNIO_UINT32 AlarmSequence;
    PNIO_UINT32 StationNr;          /* 0: the controller's own station */
    PNIO_UINT8 Reserved1[4];
    PNIO_UINT8 Reserved2[48];
    PNIO_ALARM_TINFO AlarmTinfo;
    SERV_CIB_PDEV_EXTCHNL_DIAG Diagnostics; /* the alarm's extended channel diagnosis */
    PNIO_UINT8 DiagDs[4];
    PNIO_ALARM_INFO AlarmAinfo;     /* the alarm notification and its user data */
} ATTR_PACKED SERV_CIB_PDEV_DATA;

#define SERV_CIB_PDEV_MAX_PORT_ITEMS 8
#define SERV_CIB_PDEV_PORT_STATE_DISTURBED 0x0001
#define SERV_CIB_PDEV_PORT_STATE_EXISTS 0x0002
#define SERV_CIB_PDEV_PORT_STATE_NOT_AVAILABLE 0x0004
#define SERV_CIB_PDEV_PORT_STATE_MAINTENANCE_REQUIRED 0x0100
#define SERV_CIB_PDEV_PORT_STATE_MAINTENANCE_DEMANDED 0x0200

typedef struct {
    PNIO_UINT8 Reserved1;
    PNIO_UINT8 Reserved2;
    PNIO_UINT16 Reserved3;
    PNIO_IO_TYPE IODataType; /* PNIO_IO_IN */
    PNIO_UINT32 LogAddr;     /* diagnostic address */
    PNIO_UINT32 Slot;
    PNIO_UINT32 Subslot;     /* 0x8000 the interface, 0x8001 the port */
    PNIO_UINT16 PortState;   /* SERV_CIB_PDEV_PORT_STATE_* */
    PNIO_UINT16 Reserved4;
} ATTR_PACKED SERV_CIB_PDEV_INIT_STATE;

typedef struct {
    PNIO_UINT32 ItemNumber;
    SERV_CIB_PDEV_INIT_STATE InitState[SERV_CIB_PDEV_MAX_PORT_ITEMS];
} ATTR_PACKED SERV_CIB_PDEV_INIT_DATA;

typedef enum { SERV_CIB_LED_BF = 1, SERV_CIB_LED_SF = 2 } SERV_CIB_LED_TYPE;
typedef enum { SERV_CIB_LED_OFF = 1, SERV_CIB_LED_ON = 2 } SERV_CIB_LED_STATE;

typedef struct {
    SERV_CIB_LED_TYPE LedType;
    SERV_CIB_LED_STATE LedState;
    PNIO_UINT8 Reserved1[4];
} ATTR_PACKED SERV_CIB_LED;

typedef struct {
    PNIO_UINT32 Version;        /* 0 */
    PNIO_UINT32 Handle;         /* from SERV_CP_info_open */
    PNIO_UINT32 CpIndex;
    SERV_CP_INFO_TYPE InfoType;
    union {
        SERV_CIB_PDEV_DATA PdevData;
        SERV_CIB_PDEV_INIT_DATA PdevInitData;
        SERV_CIB_LED LedInfo;
    } u;
} ATTR_PACKED SERV_CP_INFO_PRM;

typedef void (*SERV_CP_INFO_CBF)(SERV_CP_INFO_PRM *pCbfPrm);

/* ---- Functions -------------------------------------------------------------------------- */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_info_open(
    PNIO_UINT32 CpIndex,   /* in */
    PNIO_UINT32 *Handle,   /* out */
    PNIO_UINT32 Reserved); /* in, 0 */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_info_close(PNIO_UINT32 Handle);

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_info_register_cbf(
    PNIO_UINT32 Handle,         /* in */
    SERV_CP_INFO_TYPE InfoType, /* in */
    SERV_CP_INFO_CBF Cbf,       /* in, NULL: deregister */
    PNIO_UINT32 Reserved);      /* in, 0 */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_set_type_of_station(
    PNIO_UINT32 CpIndex,  /* in */
    char *TypeName);      /* in, NUL-terminated, at most 255 bytes taken */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_download(
    PNIO_UINT32 CpIndex,        /* in */
    PNIO_CP_DLD_TYPE DataType,  /* in */
    PNIO_UINT8 *pData,          /* in */
    PNIO_UINT32 DataLen);       /* in */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_reset(
    PNIO_UINT32 CpIndex,          /* in */
    PNIO_CP_RESET_TYPE ResetType); /* in */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_get_fw_info(
    PNIO_UINT32 CpIndex,            /* in */
    SERV_CP_FW_INFO_TYPE *p_info);  /* out */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_init(
    PNIO_DEBUG_SETTINGS_PTR_TYPE DebugSetting); /* in, may be NULL */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_undo_init(void);

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_get_network_adapters(
    PNIO_CP_ID_PTR_TYPE CpList, /* out, PROCIMG_MAX_NETWORK_ADAPTERS entries */
    PNIO_UINT8 *NrOfCp);        /* out */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_startup(
    PNIO_CP_ID_PTR_TYPE CpList,  /* in, the adapter */
    PNIO_UINT32 NrOfCp,          /* in, 1 */
    PNIO_UINT8 *pConfigData,     /* in, PN Driver's XML or procimg's TOML */
    PNIO_UINT32 ConfigDataLen,   /* in, without a terminating NUL */
    PNIO_UINT8 *pRemaData,       /* in, may be NULL */
    PNIO_UINT32 RemaDataLen,     /* in, 0: none */
    PNIO_SYSTEM_DESCR *pSysDescr); /* in, may be NULL */

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_shutdown(void);

PNIO_UINT32 PNIO_CODE_ATTR SERV_CP_set_trace_level(
    PNIO_UINT32 Component,                                /* pnio_stack_comp */
    PNIO_UINT32 TraceLevel,                               /* pnio_trace_level */
    PNIO_PNTRC_SET_TRACE_LEVEL_DONE CbfSetTraceLevelDone); /* may be NULL */

#ifdef __cplusplus
}
#endif

#endif /* SERVUSRX_H */
