/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The IO-Base services of libprocimg as an IO-Base program uses them, against
 * `procimgd --demo` (CpIndex 1 = the instance in PROCIMG_INSTANCE):
 *
 *   iobase_services_demo records   record read/write jobs and their confirmations, the
 *                                  refusals at the call, the configured submodules
 *                                  (opened without an alarm callback)
 *   iobase_services_demo alarms    a process alarm from a simulated device, device
 *                                  deactivation and activation with DEV_ACT_CONF and the
 *                                  station failure / return alarms, DEVICE_STATE
 *
 * The demo's IO system: echo (I 0..15, Q 0..15), counter (I 16..19), dio (I 20..21,
 * Q 16..17), station numbers 1, 2, 3. Prints "<part>: all checks held" at the end.
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrx.h"
#include "iobase_controller.h"
#include "procimg.h"
#include "check.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define WAIT_S 10

/* ---- What the callbacks saw ------------------------------------------------------------ */

typedef struct {
    int taken;
    PNIO_CBE_TYPE type;
    PNIO_UINT32 handle;
    PNIO_ADDR addr;
    PNIO_UINT32 index;
    PNIO_REF ref;
    PNIO_ERR_STAT err;
    PNIO_UINT32 mode;
    PNIO_UINT32 result;
    PNIO_CTRL_ALARM_DATA alarm;
    const PNIO_CTRL_DIAG *request;
    PNIO_UINT32 len;
    PNIO_UINT8 data[1024];
} event_t;

#define MAX_EVENTS 128
static event_t events[MAX_EVENTS];
static int n_events;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t changed = PTHREAD_COND_INITIALIZER;

static void copy_data(event_t *e, const void *p, PNIO_UINT32 len) {
    e->len = len;
    if (len > sizeof e->data) len = sizeof e->data;
    if (len > 0) memcpy(e->data, p, len);
}

static void on_event(PNIO_CBE_PRM *p) {
    event_t e;
    memset(&e, 0, sizeof e);
    e.type = p->CbeType;
    e.handle = p->Handle;
    switch (p->CbeType) {
    case PNIO_CBE_MODE_IND:
        e.mode = p->ModeInd.Mode;
        break;
    case PNIO_CBE_REC_READ_CONF:
        e.addr = *p->RecReadConf.pAddr;
        e.index = p->RecReadConf.RecordIndex;
        e.ref = p->RecReadConf.ReqRef;
        e.err = p->RecReadConf.Err;
        copy_data(&e, p->RecReadConf.pBuffer, p->RecReadConf.Length);
        break;
    case PNIO_CBE_REC_WRITE_CONF:
        e.addr = *p->RecWriteConf.pAddr;
        e.index = p->RecWriteConf.RecordIndex;
        e.ref = p->RecWriteConf.ReqRef;
        e.err = p->RecWriteConf.Err;
        break;
    case PNIO_CBE_ALARM_IND:
        e.addr = *p->AlarmInd.pAddr;
        e.ref = p->AlarmInd.IndRef;
        e.alarm = *p->AlarmInd.pAlarmData;
        break;
    case PNIO_CBE_DEV_ACT_CONF:
        e.addr = *p->DevActConf.pAddr;
        e.mode = p->DevActConf.Mode;
        e.result = p->DevActConf.Result;
        break;
    case PNIO_CBE_CTRL_DIAG_CONF:
        e.request = p->CtrlDiagConf.pDiagData;
        e.result = p->CtrlDiagConf.ErrorCode;
        copy_data(&e, p->CtrlDiagConf.pDiagDataBuffer, p->CtrlDiagConf.DiagDataBufferLen);
        break;
    default:
        break;
    }
    pthread_mutex_lock(&lock);
    if (n_events == MAX_EVENTS) {
        /* Full: forget the events already taken. */
        int kept = 0;
        for (int i = 0; i < n_events; i++)
            if (!events[i].taken) events[kept++] = events[i];
        n_events = kept;
    }
    if (n_events < MAX_EVENTS) events[n_events++] = e;
    pthread_cond_broadcast(&changed);
    pthread_mutex_unlock(&lock);
}

typedef int (*match_fn)(const event_t *e, const void *what);

/* Waits for the first event not yet taken that `match` accepts; takes and returns a copy. */
static event_t wait_for(int line, const char *name, match_fn match, const void *what) {
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += WAIT_S;
    pthread_mutex_lock(&lock);
    for (;;) {
        for (int i = 0; i < n_events; i++) {
            if (!events[i].taken && match(&events[i], what)) {
                events[i].taken = 1;
                event_t e = events[i];
                pthread_mutex_unlock(&lock);
                return e;
            }
        }
        if (pthread_cond_timedwait(&changed, &lock, &until) != 0) {
            pthread_mutex_unlock(&lock);
            fail(line, "no %s within %d s (%d events seen)", name, WAIT_S, n_events);
        }
    }
}

static int is_mode(const event_t *e, const void *what) {
    return e->type == PNIO_CBE_MODE_IND && e->mode == *(const PNIO_UINT32 *)what;
}
static int is_read(const event_t *e, const void *what) {
    return e->type == PNIO_CBE_REC_READ_CONF && e->ref == *(const PNIO_REF *)what;
}
static int is_write(const event_t *e, const void *what) {
    return e->type == PNIO_CBE_REC_WRITE_CONF && e->ref == *(const PNIO_REF *)what;
}
static int is_alarm(const event_t *e, const void *what) {
    return e->type == PNIO_CBE_ALARM_IND && e->alarm.AlarmType == *(const PNIO_UINT32 *)what;
}
typedef struct {
    PNIO_UINT32 type;
    PNIO_UINT16 station;
} station_alarm_t;
static int is_station_alarm(const event_t *e, const void *what) {
    const station_alarm_t *w = what;
    return e->type == PNIO_CBE_ALARM_IND && e->alarm.AlarmType == w->type &&
           e->alarm.DeviceNum == w->station;
}
static int is_activation(const event_t *e, const void *what) {
    return e->type == PNIO_CBE_DEV_ACT_CONF && e->mode == *(const PNIO_UINT32 *)what;
}
static int is_diag(const event_t *e, const void *what) {
    return e->type == PNIO_CBE_CTRL_DIAG_CONF && e->request == (const PNIO_CTRL_DIAG *)what;
}

static event_t wait_mode(PNIO_UINT32 mode) { return wait_for(__LINE__, "MODE_IND", is_mode, &mode); }
static event_t wait_read(PNIO_REF ref) { return wait_for(__LINE__, "REC_READ_CONF", is_read, &ref); }
static event_t wait_write(PNIO_REF ref) { return wait_for(__LINE__, "REC_WRITE_CONF", is_write, &ref); }
static event_t wait_alarm(PNIO_UINT32 type) { return wait_for(__LINE__, "ALARM_IND", is_alarm, &type); }
static event_t wait_station(PNIO_UINT32 type, PNIO_UINT16 station) {
    station_alarm_t w = {type, station};
    return wait_for(__LINE__, "station alarm", is_station_alarm, &w);
}
static event_t wait_activation(PNIO_UINT32 mode) {
    return wait_for(__LINE__, "DEV_ACT_CONF", is_activation, &mode);
}

/* ---- Helpers ----------------------------------------------------------------------------- */

static int ok_stat(PNIO_ERR_STAT s) {
    return s.ErrCode == 0 && s.ErrDecode == 0 && s.ErrCode1 == 0 && s.ErrCode2 == 0;
}

/* A diagnosis request and its confirmation. */
static event_t diag(PNIO_UINT32 h, PNIO_CTRL_DIAG_ENUM service, PNIO_ADDR a) {
    static PNIO_CTRL_DIAG req; /* the library's until the confirmation */
    memset(&req, 0, sizeof req);
    req.DiagService = service;
    req.u.Addr = a;
    req.ReqRef = 0x5EED;
    CHECK_RC(PNIO_ctrl_diag_req(h, &req), PNIO_OK);
    event_t e = wait_for(__LINE__, "CTRL_DIAG_CONF", is_diag, &req);
    CHECK(e.request == &req && req.ReqRef == 0x5EED, "the confirmation hands back the request");
    return e;
}

static PNIO_CTRL_DIAG_DEVICE device_state(PNIO_UINT32 h, PNIO_ADDR a) {
    event_t e = diag(h, PNIO_CTRL_DIAG_DEVICE_STATE, a);
    PNIO_CTRL_DIAG_DEVICE d;
    CHECK(e.result == PNIO_OK, "DEVICE_STATE ErrorCode 0x%x", (unsigned)e.result);
    CHECK(e.len == sizeof d, "DEVICE_STATE answered %u bytes", (unsigned)e.len);
    memcpy(&d, e.data, sizeof d);
    return d;
}

/* Waits until the device at `a` is in data exchange, as DEVICE_STATE says. */
static void wait_in_data(PNIO_UINT32 h, PNIO_ADDR a) {
    for (int i = 0; i < WAIT_S * 20; i++) {
        PNIO_CTRL_DIAG_DEVICE d = device_state(h, a);
        if (d.DiagState & PNIO_CTRL_DEV_DIAG_AR_IN_DATA) {
            CHECK(d.Mode == PNIO_DA_TRUE && d.Reason == PNIO_CTRL_REASON_NONE,
                  "a device in data: Mode %u, Reason 0x%x", (unsigned)d.Mode, (unsigned)d.Reason);
            return;
        }
        struct timespec t = {0, 50 * 1000 * 1000};
        nanosleep(&t, NULL);
    }
    fail(__LINE__, "the device at I/Q %u never reached data exchange", (unsigned)a.u.Addr);
}

/* Opens controller 1, registers the other callbacks, goes to OPERATE and waits for every
 * device to be in data exchange. */
static PNIO_UINT32 open_operate(int with_alarms) {
    PNIO_UINT32 h = 0;
    CHECK_RC(PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_event, on_event,
                                  with_alarms ? on_event : NULL, &h),
             PNIO_OK);
    CHECK_RC(PNIO_register_cbf(h, PNIO_CBE_MODE_IND, on_event), PNIO_OK);
    CHECK_RC(PNIO_register_cbf(h, PNIO_CBE_DEV_ACT_CONF, on_event), PNIO_OK);
    /* Without its callback a diagnosis has nowhere to go. */
    PNIO_CTRL_DIAG early;
    memset(&early, 0, sizeof early);
    early.DiagService = PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST;
    CHECK_RC(PNIO_ctrl_diag_req(h, &early), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_register_cbf(h, PNIO_CBE_CTRL_DIAG_CONF, on_event), PNIO_OK);
    CHECK_RC(PNIO_set_mode(h, PNIO_MODE_OPERATE), PNIO_OK);
    wait_mode(PNIO_MODE_CLEAR);
    wait_mode(PNIO_MODE_OPERATE);
    wait_in_data(h, logical(PNIO_IO_IN, 0));
    wait_in_data(h, logical(PNIO_IO_IN, 16));
    wait_in_data(h, logical(PNIO_IO_OUT, 16));
    return h;
}

static void offline_close(PNIO_UINT32 h) {
    CHECK_RC(PNIO_set_mode(h, PNIO_MODE_OFFLINE), PNIO_OK);
    wait_mode(PNIO_MODE_OFFLINE);
    CHECK_RC(PNIO_controller_close(h), PNIO_OK);
}

/* ---- records ------------------------------------------------------------------------------ */

static void records(void) {
    PNIO_UINT32 h = open_operate(0);
    PNIO_ADDR echo_in = logical(PNIO_IO_IN, 0);
    PNIO_ADDR echo_out = logical(PNIO_IO_OUT, 3);

    /* I&M0 of the echo module: the simulated device's identity. */
    CHECK_RC(PNIO_rec_read_req(h, &echo_in, 0xAFF0, 4711, 4096), PNIO_OK);
    event_t e = wait_read(4711);
    CHECK(e.handle == h, "Handle %u, expected %u", (unsigned)e.handle, (unsigned)h);
    CHECK(ok_stat(e.err), "I&M0 read failed: %02x %02x %02x %02x", e.err.ErrCode,
          e.err.ErrDecode, e.err.ErrCode1, e.err.ErrCode2);
    CHECK(e.index == 0xAFF0, "RecordIndex 0x%x", (unsigned)e.index);
    CHECK(e.addr.AddrType == PNIO_ADDR_LOG && e.addr.IODataType == PNIO_IO_IN &&
              e.addr.u.Addr == 0,
          "pAddr is not the job's address");
    CHECK(e.len == 60, "I&M0 has 60 bytes, got %u", (unsigned)e.len);
    CHECK(e.data[6] == 0x04 && e.data[7] == 0x93, "vendor id %02x%02x", e.data[6], e.data[7]);
    CHECK(memcmp(e.data + 8, "PROCIMG-SIM", 11) == 0, "order id");

    /* I&M0 of the echo device's DAP (slot 0), a submodule without IO data: through its
     * diagnostic address, an input address of length 0. It has no IO data to read, and in
     * the Q space it is no address. */
    PNIO_ADDR echo_dap = logical(PNIO_IO_IN, 22);
    CHECK_RC(PNIO_rec_read_req(h, &echo_dap, 0xAFF0, 4712, 4096), PNIO_OK);
    e = wait_read(4712);
    CHECK(ok_stat(e.err) && e.len == 60 && e.addr.IODataType == PNIO_IO_IN && e.addr.u.Addr == 22,
          "I&M0 of the DAP: %02x %02x, %u bytes", e.err.ErrCode, e.err.ErrDecode,
          (unsigned)e.len);
    {
        PNIO_UINT8 b[4];
        PNIO_UINT32 n = 0;
        PNIO_IOXS rem;
        PNIO_ADDR dap_out = logical(PNIO_IO_OUT, 22);
        CHECK_RC(PNIO_data_read(h, &echo_dap, sizeof b, &n, b, PNIO_S_GOOD, &rem),
                 PNIO_ERR_UNKNOWN_ADDR);
        CHECK(strstr(procimg_last_error(), "diagnostic address") != NULL,
              "the text says what I 22 is: %s", procimg_last_error());
        CHECK_RC(PNIO_rec_read_req(h, &dap_out, 0xAFF0, 10, 16), PNIO_ERR_PRM_ADD);
    }

    /* A record written through the module's output address, read back through its input
     * address. */
    PNIO_UINT8 record[3] = {1, 2, 3};
    CHECK_RC(PNIO_rec_write_req(h, &echo_out, 0x10, 1, sizeof record, record), PNIO_OK);
    e = wait_write(1);
    CHECK(ok_stat(e.err), "record write failed: %02x %02x %02x", e.err.ErrCode,
          e.err.ErrDecode, e.err.ErrCode1);
    CHECK(e.index == 0x10 && e.addr.IODataType == PNIO_IO_OUT && e.addr.u.Addr == 3,
          "REC_WRITE_CONF names the job");
    CHECK_RC(PNIO_rec_read_req(h, &echo_in, 0x10, 2, 16), PNIO_OK);
    e = wait_read(2);
    CHECK(ok_stat(e.err) && e.len == 3 && memcmp(e.data, record, 3) == 0,
          "the record read back has %u bytes", (unsigned)e.len);

    /* A record the device does not have: the device's PNIORW read error. */
    CHECK_RC(PNIO_rec_read_req(h, &echo_in, 0x1234, 3, 16), PNIO_OK);
    e = wait_read(3);
    CHECK(e.err.ErrCode == 0xDE && e.err.ErrDecode == 0x80 && e.len == 0,
          "a missing record gave %02x %02x, %u bytes", e.err.ErrCode, e.err.ErrDecode,
          (unsigned)e.len);

    /* Refused at the call. */
    PNIO_ADDR nowhere = logical(PNIO_IO_IN, 100);
    PNIO_ADDR geo = echo_in;
    geo.AddrType = PNIO_ADDR_GEO;
    static PNIO_UINT8 big[4097];
    CHECK_RC(PNIO_rec_read_req(h, &nowhere, 0xAFF0, 10, 16), PNIO_ERR_PRM_ADD);
    CHECK_RC(PNIO_rec_read_req(h, &geo, 0xAFF0, 10, 16), PNIO_ERR_PRM_ADD);
    CHECK_RC(PNIO_rec_read_req(h, &echo_in, 0x10000, 10, 16), PNIO_ERR_PRM_REC_INDEX);
    CHECK_RC(PNIO_rec_read_req(h, &echo_in, 0xAFF0, 10, 0), PNIO_ERR_VALUE_LEN);
    CHECK_RC(PNIO_rec_read_req(h, &echo_in, 0xAFF0, 10, 4097), PNIO_ERR_VALUE_LEN);
    CHECK_RC(PNIO_rec_write_req(h, &nowhere, 0x10, 10, 1, big), PNIO_ERR_PRM_ADD);
    CHECK_RC(PNIO_rec_write_req(h, &echo_in, 0x10000, 10, 1, big), PNIO_ERR_PRM_REC_INDEX);
    CHECK_RC(PNIO_rec_write_req(h, &echo_in, 0x10, 10, 0, big), PNIO_ERR_VALUE_LEN);
    CHECK_RC(PNIO_rec_write_req(h, &echo_in, 0x10, 10, 4097, big), PNIO_ERR_VALUE_LEN);
    CHECK(strstr(procimg_last_error(), "4096") != NULL, "the text names the limit: %s",
          procimg_last_error());

    /* The configured submodules: one element per direction of every submodule with data,
     * and one of length 0 at the diagnostic address of each data-less one (the DAPs). */
    e = diag(h, PNIO_CTRL_DIAG_CONFIG_SUBMODULE_LIST, echo_in);
    CHECK(e.result == PNIO_OK, "CONFIG_SUBMODULE_LIST ErrorCode 0x%x", (unsigned)e.result);
    static const struct {
        PNIO_IO_TYPE io;
        PNIO_UINT32 addr, len, stat, slot;
    } want[] = {
        {PNIO_IO_IN, 22, 0, 1, 0}, {PNIO_IO_IN, 0, 16, 1, 1},  {PNIO_IO_OUT, 0, 16, 1, 1},
        {PNIO_IO_IN, 23, 0, 2, 0}, {PNIO_IO_IN, 16, 4, 2, 1},  {PNIO_IO_IN, 24, 0, 3, 0},
        {PNIO_IO_IN, 20, 2, 3, 1}, {PNIO_IO_OUT, 16, 2, 3, 2},
    };
    size_t n = e.len / sizeof(PNIO_CTRL_DIAG_CONFIG_SUBMODULE);
    CHECK(e.len % sizeof(PNIO_CTRL_DIAG_CONFIG_SUBMODULE) == 0 && n == 8,
          "%u bytes: not 8 submodule elements", (unsigned)e.len);
    for (size_t i = 0; i < n; i++) {
        PNIO_CTRL_DIAG_CONFIG_SUBMODULE s;
        memcpy(&s, e.data + i * sizeof s, sizeof s);
        CHECK(s.Address.AddrType == PNIO_ADDR_LOG && s.Address.IODataType == want[i].io &&
                  s.Address.u.Addr == want[i].addr && s.DataLength == want[i].len &&
                  s.StatNo == want[i].stat && s.Slot == want[i].slot && s.Subslot == 1,
              "element %u: %s %u, %u bytes, station %u slot %u", (unsigned)i,
              s.Address.IODataType == PNIO_IO_IN ? "I" : "Q", (unsigned)s.Address.u.Addr,
              (unsigned)s.DataLength, (unsigned)s.StatNo, (unsigned)s.Slot);
        /* The echo's data is IRT (rt_class = 3 in the demo), the others' RT. */
        PNIO_DATA_TYPE type = (i == 1 || i == 2) ? PNIO_DATA_IRT : PNIO_DATA_RT;
        CHECK(s.DataType == type && s.ComType == PNIO_COM_UNICAST && s.Api == 0 &&
                  s.ReductionFactor == 1 && s.Phase == 0 && s.CycleTime == 32,
              "element %u: type %u, reduction %u, cycle %u", (unsigned)i, (unsigned)s.DataType,
              (unsigned)s.ReductionFactor, (unsigned)s.CycleTime);
    }

    /* Every output bit is this program's to write. */
    e = diag(h, PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE_LIST, echo_in);
    CHECK(e.result == PNIO_OK && e.len == 2 * sizeof(PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE),
          "OUTPUT_SLICE_LIST: %u bytes", (unsigned)e.len);
    PNIO_CTRL_DIAG_CONFIG_OUTPUT_SLICE slices[2];
    memcpy(slices, e.data, sizeof slices);
    CHECK(slices[0].Address.IODataType == PNIO_IO_OUT && slices[0].Address.u.Addr == 0 &&
              slices[0].BitOffset == 0 && slices[0].BitLength == 128 &&
              slices[1].Address.u.Addr == 16 && slices[1].BitLength == 16,
          "output slices Q %u/%u bits, Q %u/%u bits", (unsigned)slices[0].Address.u.Addr,
          slices[0].BitLength, (unsigned)slices[1].Address.u.Addr, slices[1].BitLength);

    /* The device diagnostic of a device in data exchange. */
    e = diag(h, PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC, logical(PNIO_IO_IN, 18));
    PNIO_CTRL_DIAG_DEVICE_DIAGNOSTIC_DATA dd;
    CHECK(e.result == PNIO_OK && e.len == sizeof dd, "DEVICE_DIAGNOSTIC: 0x%x, %u bytes",
          (unsigned)e.result, (unsigned)e.len);
    memcpy(&dd, e.data, sizeof dd);
    CHECK(dd.Mode == PNIO_DA_TRUE && dd.ErrorCause == 0, "DEVICE_DIAGNOSTIC Mode %u",
          (unsigned)dd.Mode);

    /* No IO router: the answer is its length, 0. */
    e = diag(h, PNIO_CTRL_DIAG_CONFIG_IOROUTER_PRESENT, echo_in);
    CHECK(e.result == PNIO_OK && e.len == 0, "IOROUTER_PRESENT: %u", (unsigned)e.len);

    /* The controller's own station: its name (from the instance), type and address (the
     * simulated network's 192.168.0.1/24, in network byte order as struct in_addr). */
    e = diag(h, PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO, echo_in);
    PNIO_CTRL_DIAG_CONFIG_NAME_ADDR_INFO_DATA na;
    CHECK(e.result == PNIO_OK && e.len == sizeof na, "NAME_ADDR_INFO: 0x%x, %u bytes",
          (unsigned)e.result, (unsigned)e.len);
    memcpy(&na, e.data, sizeof na);
    const PNIO_UINT8 *ip = (const PNIO_UINT8 *)&na.ip_addr;
    const PNIO_UINT8 *mask = (const PNIO_UINT8 *)&na.ip_mask;
    CHECK(strncmp((const char *)na.name, "procimgd-", 9) == 0 &&
              strcmp((const char *)na.TypeOfStation, "procimg controller") == 0,
          "NAME_ADDR_INFO name \"%s\" type \"%s\"", (const char *)na.name,
          (const char *)na.TypeOfStation);
    CHECK(ip[0] == 192 && ip[1] == 168 && mask[0] == 255 && mask[3] == 0,
          "NAME_ADDR_INFO ip %u.%u.%u.%u mask %u.%u.%u.%u", ip[0], ip[1], ip[2], ip[3], mask[0],
          mask[1], mask[2], mask[3]);

    /* The communication counters: the simulated network has no Ethernet port to count. */
    e = diag(h, PNIO_CTRL_DIAG_GET_COMM_COUNTER_DATA, echo_in);
    PNIO_CTRL_COMM_COUNTER_DATA cc;
    CHECK(e.result == PNIO_OK && e.len == sizeof cc, "GET_COMM_COUNTER_DATA: 0x%x, %u bytes",
          (unsigned)e.result, (unsigned)e.len);
    memcpy(&cc, e.data, sizeof cc);
    CHECK(cc.NumberOfPorts == 0, "GET_COMM_COUNTER_DATA: %u ports", (unsigned)cc.NumberOfPorts);
    e = diag(h, PNIO_CTRL_DIAG_RESET_COMM_COUNTERS, echo_in);
    CHECK(e.result == PNIO_OK && e.len == sizeof cc, "RESET_COMM_COUNTERS: 0x%x, %u bytes",
          (unsigned)e.result, (unsigned)e.len);

    /* A service that is none of PNIO_ctrl_diag_req's. */
    PNIO_CTRL_DIAG unknown;
    memset(&unknown, 0, sizeof unknown);
    unknown.DiagService = (PNIO_CTRL_DIAG_ENUM)9;
    CHECK_RC(PNIO_ctrl_diag_req(h, &unknown), PNIO_ERR_PRM_INVALIDARG);
    unknown.DiagService = PNIO_CTRL_DIAG_DEVICE_STATE;
    unknown.u.Addr = nowhere;
    CHECK_RC(PNIO_ctrl_diag_req(h, &unknown), PNIO_ERR_PRM_ADD);

    offline_close(h);
}

/* ---- alarms -------------------------------------------------------------------------------- */

static void alarms(void) {
    PNIO_UINT32 h = open_operate(1);
    PNIO_ADDR echo_in = logical(PNIO_IO_IN, 0);

    /* Every device that reached data exchange after OPERATE reported a station return, at
     * its base address: the diagnostic address of its DAP. */
    static const PNIO_UINT32 first[3] = {22, 23, 24};
    for (PNIO_UINT16 station = 1; station <= 3; station++) {
        event_t r = wait_station(PNIO_ALARM_DEV_RETURN, station);
        CHECK(r.addr.IODataType == PNIO_IO_IN && r.addr.u.Addr == first[station - 1] &&
                  r.alarm.AlarmPriority == PNIO_APRIO_HIGH,
              "DEV_RETURN of station %u at I %u", station, (unsigned)r.addr.u.Addr);
    }

    /* The simulated device raises a process alarm with the bytes written to record 0x7FF0. */
    PNIO_UINT8 trigger[2] = {0xAB, 0xCD};
    CHECK_RC(PNIO_rec_write_req(h, &echo_in, 0x7FF0, 20, sizeof trigger, trigger), PNIO_OK);
    event_t e = wait_write(20);
    CHECK(ok_stat(e.err), "the alarm trigger was not written");
    e = wait_alarm(PNIO_ALARM_PROCESS);
    const PNIO_CTRL_ALARM_DATA *a = &e.alarm;
    CHECK(e.handle == h, "alarm for handle %u", (unsigned)e.handle);
    CHECK(e.addr.IODataType == PNIO_IO_IN && e.addr.u.Addr == 0, "the alarm's pAddr is I %u",
          (unsigned)e.addr.u.Addr);
    CHECK(a->AlarmPriority == PNIO_APRIO_HIGH && a->DeviceNum == 1 && a->SlotNum == 1 &&
              a->SubslotNum == 1,
          "alarm from station %u slot %u subslot %u", a->DeviceNum, a->SlotNum, a->SubslotNum);
    CHECK(a->AlarmAinfo.BlockType == 0x0001 && a->AlarmAinfo.Api == 0 &&
              a->AlarmAinfo.ModIdent == 0x20 && a->AlarmAinfo.SubIdent == 1,
          "alarm block type 0x%x, module 0x%x", a->AlarmAinfo.BlockType,
          (unsigned)a->AlarmAinfo.ModIdent);
    CHECK(a->AlarmAinfo.UserStrucIdent == 0x0001 && a->AlarmAinfo.UserAlarmDataLen == 2 &&
              a->AlarmAinfo.UAData.UserAlarmData[0] == 0xAB &&
              a->AlarmAinfo.UAData.UserAlarmData[1] == 0xCD,
          "alarm user data: USI 0x%x, %u bytes", a->AlarmAinfo.UserStrucIdent,
          a->AlarmAinfo.UserAlarmDataLen);
    CHECK(a->AlarmTinfo.PnioVendorIdent == 0x0493 && a->AlarmTinfo.PnioDevIdent == 0x0001,
          "alarm source vendor 0x%x device 0x%x", a->AlarmTinfo.PnioVendorIdent,
          a->AlarmTinfo.PnioDevIdent);

    /* Deactivating dio (by its output address): DEV_ACT_CONF and a station failure alarm,
     * in either order. */
    PNIO_ADDR dio_out = logical(PNIO_IO_OUT, 16);
    PNIO_ADDR dio_in = logical(PNIO_IO_IN, 21);
    CHECK_RC(PNIO_device_activate(h, &dio_out, PNIO_DA_FALSE), PNIO_OK);
    e = wait_activation(PNIO_DA_FALSE);
    CHECK(e.result == PNIO_OK && e.addr.IODataType == PNIO_IO_OUT && e.addr.u.Addr == 16,
          "DEV_ACT_CONF: Result 0x%x, pAddr %u", (unsigned)e.result, (unsigned)e.addr.u.Addr);
    e = wait_station(PNIO_ALARM_DEV_FAILURE, 3);
    CHECK(e.alarm.DeviceNum == 3 && e.addr.IODataType == PNIO_IO_IN && e.addr.u.Addr == 24,
          "DEV_FAILURE of station %u at %u", e.alarm.DeviceNum, (unsigned)e.addr.u.Addr);
    PNIO_CTRL_DIAG_DEVICE d = device_state(h, dio_in);
    CHECK(d.Mode == PNIO_DA_FALSE && (d.DiagState & PNIO_CTRL_DEV_DIAG_AR_OFFLINE) &&
              !(d.DiagState & PNIO_CTRL_DEV_DIAG_AR_IN_DATA),
          "a deactivated device: Mode %u, DiagState 0x%x", (unsigned)d.Mode,
          (unsigned)d.DiagState);

    /* And back: DEV_ACT_CONF and a station return alarm. */
    CHECK_RC(PNIO_device_activate(h, &dio_in, PNIO_DA_TRUE), PNIO_OK);
    e = wait_activation(PNIO_DA_TRUE);
    CHECK(e.result == PNIO_OK && e.addr.u.Addr == 21, "DEV_ACT_CONF: Result 0x%x",
          (unsigned)e.result);
    e = wait_station(PNIO_ALARM_DEV_RETURN, 3);
    CHECK(e.alarm.DeviceNum == 3 && e.addr.u.Addr == 24, "DEV_RETURN of station %u",
          e.alarm.DeviceNum);
    wait_in_data(h, dio_in);

    PNIO_ADDR nowhere = logical(PNIO_IO_OUT, 99);
    CHECK_RC(PNIO_device_activate(h, &nowhere, PNIO_DA_TRUE), PNIO_ERR_PRM_ADD);

    /* Going OFFLINE ends every connection: a station failure for each device. */
    CHECK_RC(PNIO_set_mode(h, PNIO_MODE_OFFLINE), PNIO_OK);
    wait_mode(PNIO_MODE_OFFLINE);
    for (PNIO_UINT16 station = 1; station <= 3; station++)
        wait_station(PNIO_ALARM_DEV_FAILURE, station);
    CHECK_RC(PNIO_controller_close(h), PNIO_OK);
}

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s records|alarms\n", argv[0]);
        return 2;
    }
    check_part = argv[1];
    if (strcmp(check_part, "records") == 0) {
        records();
    } else if (strcmp(check_part, "alarms") == 0) {
        alarms();
    } else {
        fprintf(stderr, "unknown part %s\n", check_part);
        return 2;
    }
    printf("%s: all checks held\n", check_part);
    return 0;
}
