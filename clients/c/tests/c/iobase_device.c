/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The IO-Base device management and configuration functions of libprocimg as a DevEasy-like
 * program uses them, against `procimgd --demo-device` (CpIndex 1 = the instance in
 * PROCIMG_INSTANCE): the checks of PNIO_device_open, wrong handles, calls out of sequence,
 * plug and pull before start with their PNIO_CBF_PULL_PLUG_CONF on a library thread, start,
 * the AR indications in the manual's order (AR_CHECK_IND, AR_INFO_IND, PRM_END_IND, then
 * PNIO_set_appl_state_ready and AR_INDATA_IND; no CHECK_IND, as the demo PLC reads what
 * the station has plugged and expects that), ArNumber and SessionKey checks, PNIO_device_ar_abort and the PLC's
 * next AR, stop with AR_OFFLINE_IND before PNIO_CBF_DEVICE_STOPPED, pull, remove and close.
 * Between them the IO data: PNIO_initiate_data_write/_read(_ext) with their checks, one
 * inside AR_INDATA_IND, and a few hundred rounds of I data (a counter pattern, IOPS GOOD)
 * until the PLC's Q data came back as I + 1 with IOPS GOOD, then IOPS BAD until the PLC
 * took the I data as zeros.
 *
 * The demo's station: VendorID 0x0493, DeviceID 0x0100; the DAP in slot 0 (module and
 * submodule ident 1), slot 1 (module 0x10, submodule 1), slot 2 (module 0x20, submodule 1),
 * all in API 0. Prints "all checks held" at the end.
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrd.h"
#include "procimg.h"
#include "check.h"
#include "../../examples/device_example.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define WAIT_S 10

/* ---- What the library thread's callbacks saw ------------------------------------------ */

static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;
static pthread_t main_thread;

typedef struct {
    int count;
    PNIO_UINT32 handle;
    PNIO_UINT32 api;
    PNIO_DEV_ACTION action;
    PNIO_UINT32 slot;
    PNIO_UINT32 subslot;
    PNIO_UINT32 error;
    int on_main_thread;
    PNIO_UINT32 call_inside; /* what PNIO_device_start answered inside the callback */
} conf_t;

static conf_t conf;

/* The AR callbacks and DEVICE_STOPPED in the order they came. */
enum {
    EV_AR_CHECK = 1,
    EV_CHECK,
    EV_AR_INFO,
    EV_PRM_END,
    EV_INDATA,
    EV_ABORT,
    EV_OFFLINE,
    EV_APDU,
    EV_STOPPED,
    EV_REC_WRITE,
    EV_REC_READ,
    EV_REQ_DONE
};
static const char *const ev_names[] = {"?",          "AR_CHECK_IND",    "CHECK_IND",
                                       "AR_INFO_IND", "PRM_END_IND",     "AR_INDATA_IND",
                                       "AR_ABORT_IND", "AR_OFFLINE_IND", "APDU_STATUS_IND",
                                       "DEVICE_STOPPED", "REC_WRITE", "REC_READ",
                                       "REQ_DONE"};
typedef struct {
    int type;
    PNIO_UINT16 ar, sk;
    PNIO_UINT32 a, b, c;
    int on_main_thread;
} event_t;
#define MAX_EVENTS 64
static event_t events[MAX_EVENTS];
static int nevents;

static void record(int type, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_UINT32 a, PNIO_UINT32 b,
                   PNIO_UINT32 c) {
    pthread_mutex_lock(&mu);
    if (nevents < MAX_EVENTS) {
        event_t e = {type, ar, sk, a, b, c, pthread_equal(pthread_self(), main_thread)};
        events[nevents++] = e;
    }
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

static struct timespec deadline(void);

/* Waits for an event of `type` at index `from` or later; its index, or fails. */
static int wait_event(int line, int type, int from) {
    struct timespec until = deadline();
    pthread_mutex_lock(&mu);
    for (;;) {
        for (int i = from; i < nevents; i++) {
            if (events[i].type == type) {
                pthread_mutex_unlock(&mu);
                return i;
            }
        }
        if (pthread_cond_timedwait(&cv, &mu, &until) != 0) break;
    }
    char seen[512] = "";
    for (int i = 0; i < nevents; i++) {
        size_t used = strlen(seen);
        snprintf(seen + used, sizeof seen - used, " %s", ev_names[events[i].type]);
    }
    pthread_mutex_unlock(&mu);
    fail(line, "%s did not come after event %d; events:%s", ev_names[type], from, seen);
    return -1;
}

/* The events from index `from` to `to` (inclusive) without APDU_STATUS_IND must be the
 * types in `want` (0-terminated). */
static void expect_order(int line, int from, int to, const int *want) {
    pthread_mutex_lock(&mu);
    int w = 0;
    for (int i = from; i <= to; i++) {
        int t = events[i].type;
        /* RUN/STOP, records and alarm confirmations come between the AR's steps. */
        if (t == EV_APDU || t >= EV_REC_WRITE) continue;
        if (want[w] == 0 || want[w] != t) {
            pthread_mutex_unlock(&mu);
            fail(line, "event %d is %s, expected %s", i, ev_names[t],
                 want[w] ? ev_names[want[w]] : "nothing more");
        }
        w++;
    }
    pthread_mutex_unlock(&mu);
    if (want[w] != 0) fail(line, "%s did not come in order", ev_names[want[w]]);
}

static event_t event(int i) {
    pthread_mutex_lock(&mu);
    event_t e = events[i];
    pthread_mutex_unlock(&mu);
    return e;
}

static int stopped;
static PNIO_UINT32 stopped_handle, stopped_code;
static int stopped_on_main_thread;

static void pull_plug_conf(PNIO_UINT32 DevHndl, PNIO_UINT32 Api, PNIO_DEV_ACTION Action,
                           PNIO_DEV_ADDR *pAddr, PNIO_UINT32 ErrorCode) {
    /* Only the IO data functions are allowed here. */
    PNIO_UINT32 inside = PNIO_device_start(DevHndl);
    pthread_mutex_lock(&mu);
    conf.count++;
    conf.handle = DevHndl;
    conf.api = Api;
    conf.action = Action;
    conf.slot = pAddr ? pAddr->u.Geo.Slot : 0xFFFFFFFFu;
    conf.subslot = pAddr ? pAddr->u.Geo.Subslot : 0xFFFFFFFFu;
    conf.error = ErrorCode;
    conf.on_main_thread = pthread_equal(pthread_self(), main_thread);
    conf.call_inside = inside;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

static void device_stopped(PNIO_UINT32 DevHndl, PNIO_UINT32 ErrorCode) {
    pthread_mutex_lock(&mu);
    stopped = 1;
    stopped_handle = DevHndl;
    stopped_code = ErrorCode;
    stopped_on_main_thread = pthread_equal(pthread_self(), main_thread);
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
    record(EV_STOPPED, 0, 0, ErrorCode, 0, 0);
}

static struct timespec deadline(void) {
    struct timespec t;
    clock_gettime(CLOCK_REALTIME, &t);
    t.tv_sec += WAIT_S;
    return t;
}

/* Waits for confirmation number n and checks it. */
static void expect_conf(int line, int n, PNIO_UINT32 h, PNIO_DEV_ACTION action, PNIO_UINT32 slot,
                        PNIO_UINT32 subslot) {
    struct timespec until = deadline();
    pthread_mutex_lock(&mu);
    while (conf.count < n) {
        if (pthread_cond_timedwait(&cv, &mu, &until) != 0) break;
    }
    conf_t c = conf;
    pthread_mutex_unlock(&mu);
    if (c.count != n) fail(line, "confirmation %d did not come (%d came)", n, c.count);
    if (c.handle != h || c.api != 0 || c.action != action || c.slot != slot ||
        c.subslot != subslot || c.error != PNIO_OK)
        fail(line,
             "confirmation %d: handle %u api %u action %d slot %u subslot 0x%x error 0x%x; "
             "expected handle %u action %d slot %u subslot 0x%x PNIO_OK",
             n, (unsigned)c.handle, (unsigned)c.api, (int)c.action, (unsigned)c.slot,
             (unsigned)c.subslot, (unsigned)c.error, (unsigned)h, (int)action, (unsigned)slot,
             (unsigned)subslot);
    if (c.on_main_thread) fail(line, "confirmation %d came on the program's thread", n);
    if (c.call_inside != PNIO_ERR_SEQUENCE)
        fail(line, "PNIO_device_start inside the callback returned 0x%x, not SEQUENCE",
             (unsigned)c.call_inside);
}

/* ---- The other callbacks ---------------------------------------------------------------- */

/* The IO data callbacks: what they saw. The main loop sets `pattern` (written as I data)
 * and reads `q`, `q_iops` (the PLC's Q data and IOPS). */
typedef struct {
    int writes, reads;
    int bad_len, bad_addr, off_thread;
    int from_main; /* whether the current initiate_* call is the program's main loop */
    PNIO_UINT8 pattern;
    PNIO_UINT8 q[8];
    PNIO_IOXS q_iops;
    PNIO_IOXS iocs; /* the PLC's IOCS of the I data last written */
    PNIO_IOXS iops; /* what DATA_WRITE returns */
} io_t;
static io_t io;

static PNIO_IOXS data_write(PNIO_UINT32 h, PNIO_DEV_ADDR *a, PNIO_UINT32 len, PNIO_UINT8 *buf,
                            PNIO_IOXS rem) {
    (void)h;
    pthread_mutex_lock(&mu);
    io.writes++;
    if (len != 8) io.bad_len++;
    if (a == NULL || a->AddrType != PNIO_ADDR_GEO || a->IODataType != PNIO_IO_IN ||
        a->u.Geo.Slot != 1 || a->u.Geo.Subslot != 1)
        io.bad_addr++;
    if (io.from_main && !pthread_equal(pthread_self(), main_thread)) io.off_thread++;
    for (PNIO_UINT32 i = 0; i < len && i < 8; i++) buf[i] = (PNIO_UINT8)(io.pattern + i);
    io.iocs = rem;
    PNIO_IOXS iops = io.iops;
    pthread_mutex_unlock(&mu);
    return iops;
}
static PNIO_IOXS data_read(PNIO_UINT32 h, PNIO_DEV_ADDR *a, PNIO_UINT32 len, PNIO_UINT8 *buf,
                           PNIO_IOXS rem) {
    (void)h;
    pthread_mutex_lock(&mu);
    io.reads++;
    if (len != 8) io.bad_len++;
    if (a == NULL || a->AddrType != PNIO_ADDR_GEO || a->IODataType != PNIO_IO_OUT ||
        a->u.Geo.Slot != 1 || a->u.Geo.Subslot != 1)
        io.bad_addr++;
    if (io.from_main && !pthread_equal(pthread_self(), main_thread)) io.off_thread++;
    for (PNIO_UINT32 i = 0; i < len && i < 8; i++) io.q[i] = buf[i];
    io.q_iops = rem;
    pthread_mutex_unlock(&mu);
    return PNIO_S_GOOD;
}
/* The parameter record (index 1, 4 bytes) as the PLC last wrote it. */
static PNIO_UINT8 param[4];
static PNIO_UINT32 param_seq;
static void rec_write(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                      PNIO_UINT32 seq, PNIO_DEV_ADDR *a, PNIO_UINT32 idx, PNIO_UINT32 *len,
                      PNIO_UINT8 *buf, PNIO_ERR_STAT *st) {
    (void)h, (void)api;
    pthread_mutex_lock(&mu);
    if (idx == 1 && *len == sizeof param) {
        memcpy(param, buf, sizeof param);
        param_seq = seq;
    } else {
        /* IODWriteRes, PNIORW, "invalid index" */
        st->ErrCode = 0xDF, st->ErrDecode = 0x80, st->ErrCode1 = 0xB0;
    }
    pthread_mutex_unlock(&mu);
    record(EV_REC_WRITE, ar, sk, idx, *len, a->u.Geo.Slot << 16 | a->u.Geo.Subslot);
}
static void rec_read(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                     PNIO_UINT32 seq, PNIO_DEV_ADDR *a, PNIO_UINT32 idx, PNIO_UINT32 *len,
                     PNIO_UINT8 *buf, PNIO_ERR_STAT *st) {
    (void)h, (void)api, (void)seq;
    pthread_mutex_lock(&mu);
    if (idx == 1 && *len >= sizeof param) {
        memcpy(buf, param, sizeof param);
        *len = sizeof param;
    } else {
        /* IODReadRes, PNIORW, "invalid index" */
        st->ErrCode = 0xDE, st->ErrDecode = 0x80, st->ErrCode1 = 0xB0;
        *len = 0;
    }
    pthread_mutex_unlock(&mu);
    record(EV_REC_READ, ar, sk, idx, *len, a->u.Geo.Slot << 16 | a->u.Geo.Subslot);
}
static void req_done(PNIO_UINT32 h, PNIO_UINT32 u, PNIO_UINT32 s, PNIO_ERR_STAT *st) {
    (void)h;
    PNIO_UINT32 status = (PNIO_UINT32)st->ErrCode << 24 | (PNIO_UINT32)st->ErrDecode << 16 |
                         (PNIO_UINT32)st->ErrCode1 << 8 | st->ErrCode2;
    record(EV_REQ_DONE, 0, 0, u, s, status);
}

/* Waits for REQ_DONE with UserHndl `user` from event `from` on; checks that the PLC
 * acknowledged the alarm. */
static int expect_done(int line, PNIO_UINT32 user, int from) {
    for (;;) {
        int i = wait_event(line, EV_REQ_DONE, from);
        event_t e = event(i);
        if (e.a != user) {
            from = i + 1;
            continue;
        }
        if (e.b != PNIO_OK || e.c != 0)
            fail(line, "REQ_DONE of alarm %u: Status 0x%x, PNIO status %08x", (unsigned)user,
                 (unsigned)e.b, (unsigned)e.c);
        if (e.on_main_thread) fail(line, "REQ_DONE came on the program's thread");
        return i;
    }
}

/* Not called against the demo PLC, which expects what is plugged; were it, the program
 * would say that its submodule there is the proper one, ident 1. */
static void check_ind(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                      PNIO_DEV_ADDR *a, PNIO_UINT32 *mi, PNIO_UINT16 *ms, PNIO_UINT32 *si,
                      PNIO_UINT16 *ss) {
    (void)h, (void)api;
    record(EV_CHECK, ar, sk, a->u.Geo.Slot << 16 | a->u.Geo.Subslot, *si, *ss);
    (void)mi;
    *ms = PNIO_MOD_STATE_PROPER_MODULE;
    *si = 0x1;
    *ss = PNIO_SUB_CHECK_PROPER_SUBMODULE;
}
/* What the last AR_CHECK_IND said of the Connect besides ArNumber and SessionKey. */
static PNIO_UINT32 check_ip, check_properties;
static int check_cmi_set;
static void ar_check_ind(PNIO_UINT32 h, PNIO_UINT32 ip, PNIO_UINT16 t, PNIO_UUID_TYPE u,
                         PNIO_UINT32 p, PNIO_UUID_TYPE c, PNIO_UINT16 l, PNIO_UINT8 *n,
                         PNIO_AR_TYPE *ar) {
    (void)u, (void)n;
    pthread_mutex_lock(&mu);
    check_ip = ip;
    check_properties = p;
    check_cmi_set = c.TimeLow != 0 || c.TimeMid != 0 || c.TimeHiAndVersion != 0;
    pthread_mutex_unlock(&mu);
    /* Only the IO data functions are allowed here. */
    PNIO_UINT32 inside = PNIO_device_ar_abort(h, ar->ArNumber, ar->SessionKey);
    PNIO_UINT32 empty = ar->NumOfMod == 0 && ar->pModList == NULL;
    record(EV_AR_CHECK, ar->ArNumber, ar->SessionKey, t, inside, empty | (PNIO_UINT32)l << 1);
}
/* AR_INFO_IND's IOCRs, as the PLC's Connect asked for them. */
static PNIO_IOCR_TYPE info_iocr[2];
/* The offset of slot 1's data object in the input IOCR's frames, or 0xffff. */
static PNIO_UINT32 info_slot1_offset = 0xffff;
static void ar_info_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_TYPE *p) {
    (void)h;
    pthread_mutex_lock(&mu);
    for (PNIO_UINT32 i = 0; i < p->NumOfIocr && i < 2; i++)
        info_iocr[i] = p->pIoCrList[i];
    for (PNIO_UINT32 i = 0; i < p->NumOfIocr; i++)
        if (p->pIoCrList[i].Direction == PNIO_IOCR_TYPE_INPUT)
            for (PNIO_UINT32 k = 0; k < p->pIoCrList[i].NumOfIoCs; k++)
                if (p->pIoCrList[i].pIoCsList[k].SlotNum == 1)
                    info_slot1_offset = p->pIoCrList[i].pIoCsList[k].reserved;
    pthread_mutex_unlock(&mu);
    /* Slot 1's first submodule ident, or 0. */
    PNIO_UINT32 slot1 = 0;
    for (PNIO_UINT32 i = 0; i < p->NumOfMod; i++)
        if (p->pModList[i].SlotNum == 1 && p->pModList[i].NumOfSubmod > 0)
            slot1 = p->pModList[i].ModIdent << 8 | p->pModList[i].pSubList[0].SubMIdent;
    record(EV_AR_INFO, ar, sk, p->NumOfMod, p->NumOfIocr, slot1);
}
static void ar_indata_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk) {
    /* The IO data functions are allowed inside a callback. */
    PNIO_UINT32 rd = PNIO_initiate_data_read(h);
    record(EV_INDATA, ar, sk, rd, 0, 0);
}
static void ar_abort_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_REASON r) {
    (void)h;
    record(EV_ABORT, ar, sk, r, 0, 0);
}
static void ar_offline_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_REASON r) {
    (void)h;
    record(EV_OFFLINE, ar, sk, r, 0, 0);
}
static void apdu_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_APDU_STATUS_IND s) {
    (void)h;
    record(EV_APDU, ar, sk, s, 0, 0);
}
static void prm_end_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_UINT32 api,
                        PNIO_UINT16 slot, PNIO_UINT16 subslot) {
    (void)h;
    record(EV_PRM_END, ar, sk, api, (PNIO_UINT32)slot << 16 | subslot, 0);
}
static void cp_stop_req(PNIO_UINT32 h) { (void)h; }

static PNIO_CBF_FUNCTIONS table(void) {
    PNIO_CBF_FUNCTIONS c;
    memset(&c, 0, sizeof c);
    c.size = sizeof c;
    c.cbf_data_write = data_write;
    c.cbf_data_read = data_read;
    c.cbf_rec_read = rec_read;
    c.cbf_rec_write = rec_write;
    c.cbf_alarm_done = req_done;
    c.cbf_check_ind = check_ind;
    c.cbf_ar_check_ind = ar_check_ind;
    c.cbf_ar_info_ind = ar_info_ind;
    c.cbf_ar_indata_ind = ar_indata_ind;
    c.cbf_ar_abort_ind = ar_abort_ind;
    c.cbf_ar_offline_ind = ar_offline_ind;
    c.cbf_apdu_status_ind = apdu_ind;
    c.cbf_prm_end_ind = prm_end_ind;
    c.pnio_cbf_cp_stop_req = cp_stop_req;
    c.cbf_device_stopped = device_stopped;
    c.cbf_pull_plug_conf = pull_plug_conf; /* LED flashing stays NULL: optional */
    return c;
}

#define VENDOR 0x0493
#define DEVICE 0x0100
#define EXT PNIO_CEP_MODE_CTRL

int main(void) {
    main_thread = pthread_self();
    PNIO_ANNOTATION ann = example_annotation();
    PNIO_CBF_FUNCTIONS cbf = table();
    PNIO_UINT32 h = 0;

    /* ---- PNIO_device_open's checks ---- */
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR, DEVICE, 1, 1, &ann, &cbf, NULL), PNIO_ERR_PRM_HND);
    CHECK_RC(PNIO_device_open(0, EXT, VENDOR, DEVICE, 1, 1, &ann, &cbf, &h), PNIO_ERR_PRM_CP_ID);
    CHECK_RC(PNIO_device_open(1, 0, VENDOR, DEVICE, 1, 1, &ann, &cbf, &h), PNIO_ERR_PRM_EXT_PAR);
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR, DEVICE, 1, 0, &ann, &cbf, &h),
             PNIO_ERR_PRM_MAX_AR_VALUE);
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR, DEVICE, 1, 1, NULL, &cbf, &h),
             PNIO_ERR_PRM_DEV_ANNOTATION);
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR, DEVICE, 1, 1, &ann, NULL, &h), PNIO_ERR_PRM_PCBF);
    PNIO_CBF_FUNCTIONS small = cbf;
    small.size = 4;
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR, DEVICE, 1, 1, &ann, &small, &h), PNIO_ERR_PRM_PCBF);
    PNIO_CBF_FUNCTIONS missing = cbf;
    missing.cbf_ar_check_ind = NULL;
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR, DEVICE, 1, 1, &ann, &missing, &h),
             PNIO_ERR_PRM_CALLBACK);
    CHECK(strstr(procimg_last_error(), "cbf_ar_check_ind") != NULL, "the text names it");
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR + 1, DEVICE, 1, 1, &ann, &cbf, &h),
             PNIO_ERR_INVALID_CONFIG);
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR, DEVICE + 1, 1, 1, &ann, &cbf, &h),
             PNIO_ERR_INVALID_CONFIG);
    CHECK(h == 0, "a failed open wrote the handle");

    PNIO_CBF_FUNCTIONS optional_null = cbf;
    optional_null.cbf_start_led_flash = NULL;
    optional_null.cbf_stop_led_flash = NULL;
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR, DEVICE, 1, 1, &ann, &optional_null, &h), PNIO_OK);
    CHECK(h != 0, "no handle");
    PNIO_UINT32 h2 = 0;
    CHECK_RC(PNIO_device_open(1, EXT, VENDOR, DEVICE, 1, 1, &ann, &cbf, &h2), PNIO_ERR_SEQUENCE);

    /* ---- Wrong handles ---- */
    PNIO_UINT32 wrong = h + 1000;
    PNIO_DEV_ADDR a = geo(1, 1);
    CHECK_RC(PNIO_device_start(wrong), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_device_stop(wrong), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_device_close(wrong), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_api_add(wrong, 0, 2, 1), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_mod_plug(wrong, 0, &a, 0x10), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_sub_pull(wrong, 0, &a), PNIO_ERR_WRONG_HND);

    /* ---- Out of sequence before start ---- */
    CHECK_RC(PNIO_device_stop(h), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_api_add_ext(h, 0), PNIO_ERR_SEQUENCE); /* opened without _ext */
    CHECK_RC(PNIO_mod_plug(h, 0, &a, 0x10), PNIO_ERR_PRM_ADD); /* API 0 not added */
    CHECK_RC(PNIO_api_add(h, 0, 2, 0x8001), PNIO_OK);
    CHECK_RC(PNIO_api_add(h, 0, 2, 0x8001), PNIO_ERR_ALREADY_DONE);
    CHECK_RC(PNIO_sub_plug_ext_IM(h, 0, &a, 1, PNIO_ALARM_TYPE_PLUG, PNIO_PLUG_IM0_BITS_NOTHING),
             PNIO_ERR_SEQUENCE); /* the module first */
    CHECK_RC(PNIO_sub_pull(h, 0, &a), PNIO_ERR_SEQUENCE);                /* nothing plugged */
    CHECK_RC(PNIO_mod_pull(h, 0, &a), PNIO_ERR_SEQUENCE);

    /* ---- Plug the DAP and slot 1; each confirmed on the library thread ---- */
    int n = 0;
    PNIO_DEV_ADDR dap = geo(0, 1);
    CHECK_RC(PNIO_mod_plug(h, 0, &dap, 0x1), PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_MOD_PLUG, 0, 1);
    CHECK_RC(PNIO_sub_plug_ext_IM(h, 0, &dap, 0x1, PNIO_ALARM_TYPE_PLUG,
                                  PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV),
             PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_SUB_PLUG, 0, 1);
    CHECK_RC(PNIO_mod_plug(h, 0, &a, 0x10), PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_MOD_PLUG, 1, 1);
    CHECK_RC(PNIO_mod_plug(h, 0, &a, 0x10), PNIO_ERR_SEQUENCE); /* plugged already */
    CHECK_RC(PNIO_sub_plug_ext_IM(h, 0, &a, 0x1, PNIO_ALARM_TYPE_PLUG,
                                  PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MODULE),
             PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_SUB_PLUG, 1, 1);
    CHECK_RC(PNIO_sub_plug(h, 0, &a, 0x1), PNIO_ERR_SEQUENCE); /* plugged already */

    /* ---- Addresses the station does not have ---- */
    CHECK_RC(PNIO_sub_plug_ext_IM(h, 7, &a, 1, PNIO_ALARM_TYPE_PLUG, PNIO_PLUG_IM0_BITS_NOTHING),
             PNIO_ERR_PRM_ADD); /* API 7 not added */
    CHECK_RC(PNIO_api_add(h, 7, 2, 1), PNIO_ERR_PRM_ADD); /* nor configured */
    PNIO_DEV_ADDR far = geo(1, 0x9000);
    CHECK_RC(PNIO_sub_plug_ext_IM(h, 0, &far, 1, PNIO_ALARM_TYPE_PLUG, PNIO_PLUG_IM0_BITS_NOTHING),
             PNIO_ERR_PRM_ADD); /* above MaxSubslots */
    PNIO_DEV_ADDR zero = geo(1, 0);
    CHECK_RC(PNIO_sub_plug_ext(h, 0, &zero, 1, PNIO_ALARM_TYPE_PLUG), PNIO_ERR_PRM_ADD);
    PNIO_DEV_ADDR slot3 = geo(3, 1);
    CHECK_RC(PNIO_mod_plug(h, 0, &slot3, 0x30), PNIO_ERR_PRM_ADD); /* above MaxSlots */
    PNIO_DEV_ADDR unconfigured = geo(1, 2);
    CHECK_RC(PNIO_sub_plug_ext(h, 0, &unconfigured, 1, PNIO_ALARM_TYPE_PLUG), PNIO_ERR_PRM_ADD);
    CHECK_RC(PNIO_sub_plug_ext(h, 0, NULL, 1, PNIO_ALARM_TYPE_PLUG), PNIO_ERR_PRM_ADD);
    CHECK_RC(PNIO_sub_plug_ext(h, 0, &a, 1, 0x77), PNIO_ERR_PRM_INVALIDARG);

    /* ---- Pull and plug again before start ---- */
    CHECK_RC(PNIO_sub_pull(h, 0, &a), PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_SUB_PULL, 1, 1);
    /* Submodule ident 2, not the configured 1: the demo PLC expects it (AR_INFO_IND). */
    CHECK_RC(PNIO_sub_plug_ext(h, 0, &a, 0x2, PNIO_ALARM_TYPE_PLUG), PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_SUB_PLUG, 1, 1);
    CHECK_RC(PNIO_api_remove(h, 0), PNIO_ERR_SEQUENCE); /* it has modules */
    CHECK_RC(PNIO_set_appl_state_ready(h, 1, 0, NULL), PNIO_ERR_SEQUENCE); /* not started */
    CHECK_RC(PNIO_initiate_data_write(h), PNIO_ERR_SEQUENCE);              /* not started */
    CHECK_RC(PNIO_initiate_data_read(h), PNIO_ERR_SEQUENCE);

    /* ---- Start: slot 2, not plugged by the program, is pulled ---- */
    CHECK_RC(PNIO_device_start(h), PNIO_OK);
    CHECK_RC(PNIO_device_start(h), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_api_add(h, 0, 2, 1), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_api_remove(h, 0), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_device_close(h), PNIO_ERR_SEQUENCE);

    /* ---- The PLC's AR: the indications in the manual's order ---- */
    static const int setup[] = {EV_AR_CHECK, EV_AR_INFO, EV_PRM_END, 0};
    int iprm = wait_event(__LINE__, EV_PRM_END, 0);
    expect_order(__LINE__, 0, iprm, setup);
    event_t chk = event(0);
    PNIO_UINT16 ar = chk.ar, sk = chk.sk;
    CHECK(ar == 1, "the first AR's ArNumber is %u", (unsigned)ar);
    CHECK(chk.a == PNIO_AR_TYPE_SINGLE, "ArType %u", (unsigned)chk.a);
    CHECK(chk.b == PNIO_ERR_SEQUENCE, "PNIO_device_ar_abort inside AR_CHECK_IND: 0x%x",
          (unsigned)chk.b);
    CHECK((chk.c & 1) && (chk.c >> 1) > 0, "AR_CHECK_IND: pAr has modules or no PLC name");
    pthread_mutex_lock(&mu);
    PNIO_UINT8 ip[4];
    memcpy(ip, &check_ip, sizeof ip); /* network byte order, as struct in_addr's s_addr */
    CHECK(ip[0] != 0 && check_properties != 0 && check_cmi_set,
          "AR_CHECK_IND: HostIp %u.%u.%u.%u, ArProperties 0x%x, CmiObjUUID %s", ip[0], ip[1],
          ip[2], ip[3], (unsigned)check_properties, check_cmi_set ? "set" : "nil");
    /* The IOCRs as the demo PLC connects: RT, a frame every 1 ms (32 × 31.25 µs), the
     * input IOCR first with the FrameID of the station's frames in reserved[0] and its C_SDU
     * length in reserved[1], slot 1's data object inside it. */
    const PNIO_IOCR_TYPE *in = &info_iocr[0], *out = &info_iocr[1];
    CHECK(in->Direction == PNIO_IOCR_TYPE_INPUT && out->Direction == PNIO_IOCR_TYPE_OUTPUT,
          "AR_INFO_IND: IOCR directions %u, %u", (unsigned)in->Direction,
          (unsigned)out->Direction);
    for (int i = 0; i < 2; i++) {
        const PNIO_IOCR_TYPE *c = &info_iocr[i];
        PNIO_UINT32 rt = c->IOCRProperties & PNIO_IOCR_PROP_RT_CLASS_MASK;
        CHECK((rt == PNIO_IOCR_PROP_RT_CLASS_1 || rt == PNIO_IOCR_PROP_RT_CLASS_2) &&
                  c->SendClock * c->ReductioFactor == 32 && c->CycleTime == 1 &&
                  c->Phase >= 1 && c->reserved[0] != 0 && c->reserved[1] >= 40,
              "AR_INFO_IND IOCR %d: RT class %u, SendClock %u, ReductioFactor %u, CycleTime %u, "
              "Phase %u, FrameID 0x%x, C_SDU %u",
              i, (unsigned)rt, (unsigned)c->SendClock, (unsigned)c->ReductioFactor,
              (unsigned)c->CycleTime, (unsigned)c->Phase, (unsigned)c->reserved[0],
              (unsigned)c->reserved[1]);
    }
    CHECK(in->reserved[0] != out->reserved[0], "AR_INFO_IND: one FrameID 0x%x for both IOCRs",
          (unsigned)in->reserved[0]);
    CHECK(info_slot1_offset < in->reserved[1],
          "AR_INFO_IND: slot 1's data object at %u in a C_SDU of %u",
          (unsigned)info_slot1_offset, (unsigned)in->reserved[1]);
    pthread_mutex_unlock(&mu);
    for (int i = 0; i <= iprm; i++) {
        event_t e = event(i);
        CHECK(e.ar == ar && e.sk == sk, "%s for AR %u/%u, not %u/%u", ev_names[e.type],
              (unsigned)e.ar, (unsigned)e.sk, (unsigned)ar, (unsigned)sk);
        CHECK(!e.on_main_thread, "%s came on the program's thread", ev_names[e.type]);
        if (e.type == EV_AR_INFO)
            CHECK(e.a >= 2 && e.b == 2 && e.c == (0x10u << 8 | 2),
                  "AR_INFO_IND: %u modules, %u IOCRs, slot 1 0x%x", (unsigned)e.a,
                  (unsigned)e.b, (unsigned)e.c);
        if (e.type == EV_PRM_END)
            CHECK(e.a == 0 && e.b == 0, "PRM_END_IND for one submodule");
    }
    /* The manual's steps 14 and 15: after PRM_END_IND the program writes the I data the PLC
     * gets with the ApplicationReady, and reads the Q data, before it says it is ready. */
    pthread_mutex_lock(&mu);
    io.pattern = 0xa0;
    io.iops = PNIO_S_GOOD;
    int writes_before = io.writes, reads_before = io.reads;
    pthread_mutex_unlock(&mu);
    CHECK_RC(PNIO_initiate_data_write(h), PNIO_OK);
    CHECK_RC(PNIO_initiate_data_read(h), PNIO_OK);
    pthread_mutex_lock(&mu);
    CHECK(io.writes == writes_before + 1 && io.reads == reads_before + 1,
          "DATA_WRITE %d and DATA_READ %d times after PRM_END_IND, not once each",
          io.writes - writes_before, io.reads - reads_before);
    pthread_mutex_unlock(&mu);
    CHECK_RC(PNIO_set_appl_state_ready(h, ar, (PNIO_UINT16)(sk + 1), NULL), PNIO_ERR_SESSION);
    CHECK_RC(PNIO_set_appl_state_ready(h, (PNIO_UINT16)(ar + 1), sk, NULL), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_set_appl_state_ready(wrong, ar, sk, NULL), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_device_ar_abort(h, ar, (PNIO_UINT16)(sk + 1)), PNIO_ERR_SESSION);
    CHECK_RC(PNIO_device_ar_abort(h, 0, sk), PNIO_ERR_SEQUENCE);
    PNIO_UINT8 alarm_data[173] = {0xbe, 0xef};
    CHECK_RC(PNIO_process_alarm_send(h, 0, ar, sk, &a, alarm_data, 2, 1, 99), PNIO_ERR_SEQUENCE);
    PNIO_APPL_READY_LIST_TYPE ready;
    PNIO_LIST_INITIALIZE(&ready.ap_list);
    CHECK_RC(PNIO_set_appl_state_ready(h, ar, sk, &ready), PNIO_OK);
    CHECK_RC(PNIO_set_appl_state_ready(h, ar, sk, &ready), PNIO_ERR_SEQUENCE);
    static const int indata[] = {EV_PRM_END, EV_INDATA, 0};
    int iin = wait_event(__LINE__, EV_INDATA, iprm);
    expect_order(__LINE__, iprm, iin, indata);
    for (int i = 0; i < iin; i++)
        CHECK(event(i).type != EV_APDU, "APDU_STATUS_IND before AR_INDATA_IND");
    CHECK(event(iin).a == PNIO_OK, "PNIO_initiate_data_read inside AR_INDATA_IND: 0x%x",
          (unsigned)event(iin).a);

    /* ---- Data exchange: I = a counter pattern, Q comes back as I + 1 (the demo PLC) ---- */
    CHECK_RC(PNIO_initiate_data_write(wrong), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_initiate_data_read(wrong), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_initiate_data_write_ext(h, NULL, PNIO_ACCESS_ALL_WITH_LOCK),
             PNIO_ERR_PRM_ACCESS_TYPE);
    CHECK_RC(PNIO_initiate_data_read_ext(h, NULL, PNIO_ACCESS_IRT_WITH_LOCK),
             PNIO_ERR_PRM_ACCESS_TYPE);
    CHECK_RC(PNIO_initiate_data_read_ext(h, NULL, (PNIO_ACCESS_ENUM)9), PNIO_ERR_PRM_ACCESS_TYPE);
    PNIO_DEV_ADDR pulled = geo(2, 1);
    CHECK_RC(PNIO_initiate_data_write_ext(h, &pulled, PNIO_ACCESS_RT_WITH_LOCK), PNIO_ERR_PRM_ADD);
    /* No IRT data on this station: nothing to visit. */
    CHECK_RC(PNIO_initiate_data_read_ext(h, NULL, PNIO_ACCESS_IRT_WITHOUT_LOCK),
             PNIO_WARN_NO_SUBMODULES);
    pthread_mutex_lock(&mu);
    memset(&io, 0, sizeof io);
    io.iops = PNIO_S_GOOD;
    io.from_main = 1;
    pthread_mutex_unlock(&mu);
    PNIO_DEV_ADDR slot1 = geo(1, 0);
    int rounds = 0, echoed = 0, writes = 0, reads = 0;
    unsigned char written[256] = {0};
    /* A few hundred rounds, and on until the echo came (at most 4000 rounds). */
    while ((rounds < 300 || !echoed) && rounds < 4000) {
        PNIO_UINT8 c = (PNIO_UINT8)rounds;
        pthread_mutex_lock(&mu);
        io.pattern = c;
        pthread_mutex_unlock(&mu);
        written[c] = 1;
        if (rounds % 2)
            CHECK_RC(PNIO_initiate_data_write_ext(h, &slot1, PNIO_ACCESS_RT_WITHOUT_LOCK), PNIO_OK);
        else
            CHECK_RC(PNIO_initiate_data_write(h), PNIO_OK);
        writes++;
        if (rounds % 3)
            CHECK_RC(PNIO_initiate_data_read(h), PNIO_OK);
        else
            CHECK_RC(PNIO_initiate_data_read_ext(h, NULL, PNIO_ACCESS_ALL_WITHOUT_LOCK), PNIO_OK);
        reads++;
        pthread_mutex_lock(&mu);
        io_t seen = io;
        pthread_mutex_unlock(&mu);
        /* Q is some I written before, plus one: q[k] = c0 + k + 1. */
        int match = seen.q_iops == PNIO_S_GOOD && written[(PNIO_UINT8)(seen.q[0] - 1)];
        for (int k = 1; k < 8; k++)
            if (seen.q[k] != (PNIO_UINT8)(seen.q[0] + k)) match = 0;
        if (match) echoed++;
        rounds++;
        struct timespec pause = {0, 2 * 1000 * 1000};
        nanosleep(&pause, NULL);
    }
    pthread_mutex_lock(&mu);
    io_t seen = io;
    io.from_main = 0;
    pthread_mutex_unlock(&mu);
    CHECK(echoed > 0, "Q never came back as I + 1 with IOPS GOOD in %d rounds: Q %02x %02x .. "
          "IOPS 0x%x", rounds, seen.q[0], seen.q[1], (unsigned)seen.q_iops);
    CHECK(seen.writes == writes && seen.reads == reads,
          "DATA_WRITE %d times for %d calls, DATA_READ %d for %d", seen.writes, writes,
          seen.reads, reads);
    CHECK(seen.bad_len == 0 && seen.bad_addr == 0,
          "the IO data callbacks saw %d wrong lengths and %d wrong addresses", seen.bad_len,
          seen.bad_addr);
    CHECK(seen.off_thread == 0, "%d IO data callbacks came off the caller's thread",
          seen.off_thread);
    CHECK(seen.iocs == PNIO_S_GOOD, "the PLC's IOCS of the I data is 0x%x", (unsigned)seen.iocs);

    /* IOPS BAD: the demo PLC takes the I data as zeros, so Q comes back as 01 .. 01. */
    pthread_mutex_lock(&mu);
    io.iops = PNIO_S_BAD;
    io.from_main = 1;
    pthread_mutex_unlock(&mu);
    int zeros = 0;
    for (rounds = 0; !zeros && rounds < 4000; rounds++) {
        CHECK_RC(PNIO_initiate_data_write(h), PNIO_OK);
        CHECK_RC(PNIO_initiate_data_read(h), PNIO_OK);
        pthread_mutex_lock(&mu);
        io_t q = io;
        pthread_mutex_unlock(&mu);
        zeros = q.q_iops == PNIO_S_GOOD;
        for (int k = 0; k < 8; k++)
            if (q.q[k] != 1) zeros = 0;
        struct timespec pause = {0, 2 * 1000 * 1000};
        nanosleep(&pause, NULL);
    }
    pthread_mutex_lock(&mu);
    io.iops = PNIO_S_GOOD;
    io.from_main = 0;
    pthread_mutex_unlock(&mu);
    CHECK(zeros, "with IOPS BAD the PLC did not take the I data as zeros in %d rounds", rounds);

    /* ---- Records: the PLC's parameter record came to REC_WRITE ---- */
    {
        int iw = wait_event(__LINE__, EV_REC_WRITE, 0);
        event_t w = event(iw);
        CHECK(w.a == 1 && w.b == 4 && w.c == (1u << 16 | 1),
              "REC_WRITE of record %u, %u bytes, slot/subslot 0x%x", (unsigned)w.a,
              (unsigned)w.b, (unsigned)w.c);
        CHECK(w.ar == ar && w.sk == sk, "REC_WRITE for AR %u/%u", (unsigned)w.ar,
              (unsigned)w.sk);
        CHECK(!w.on_main_thread, "REC_WRITE came on the program's thread");
        pthread_mutex_lock(&mu);
        PNIO_UINT32 seq = param_seq;
        pthread_mutex_unlock(&mu);
        CHECK(seq >= 1, "REC_WRITE's SequenceNum is %u", (unsigned)seq);
    }

    /* ---- A process alarm, acknowledged by the PLC ---- */
    int ialarm;
    {
        pthread_mutex_lock(&mu);
        int from = nevents;
        pthread_mutex_unlock(&mu);
        CHECK_RC(PNIO_process_alarm_send(h, 0, ar, sk, &a, alarm_data, 173, 1, 1),
                 PNIO_ERR_VALUE_LEN);
        CHECK_RC(PNIO_process_alarm_send(h, 0, ar, (PNIO_UINT16)(sk + 1), &a, alarm_data, 2, 1,
                                         1),
                 PNIO_ERR_SESSION);
        CHECK_RC(PNIO_process_alarm_send(wrong, 0, ar, sk, &a, alarm_data, 2, 1, 1),
                 PNIO_ERR_WRONG_HND);
        CHECK_RC(PNIO_process_alarm_send(h, 0, ar, sk, NULL, alarm_data, 2, 1, 1),
                 PNIO_ERR_PRM_ADD);
        CHECK_RC(PNIO_process_alarm_send(h, 0, ar, sk, &a, NULL, 2, 1, 1), PNIO_ERR_PRM_BUF);
        CHECK_RC(PNIO_process_alarm_send(h, 0, ar, sk, &a, alarm_data, 2, 0x8000, 1),
                 PNIO_ERR_PRM_INVALIDARG);
        PNIO_DEV_ADDR none = geo(1, 2);
        CHECK_RC(PNIO_process_alarm_send(h, 0, ar, sk, &none, alarm_data, 2, 1, 1),
                 PNIO_ERR_UNKNOWN_ADDR);
        CHECK_RC(PNIO_process_alarm_send(h, 0, ar, sk, &a, alarm_data, 172, 1, 1), PNIO_OK);
        ialarm = expect_done(__LINE__, 1, from);
    }

    /* ---- A channel diagnosis appears and disappears, each with its alarm ---- */
    {
        PNIO_UINT16 appears = PNIO_build_channel_properties(
            h, PNIO_DIAG_CHANPROP_TYPE_SUBMOD, PNIO_DIAG_CHAN_SPEC_ERROR_APPEARS,
            PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE);
        CHECK(appears == 0x0800, "ChannelProperties 0x%x", (unsigned)appears);
        CHECK_RC(PNIO_diag_channel_add(h, 0, &a, 0x8000, appears, 0x0006, 0), PNIO_ERR_PRM_INVALIDARG);
        CHECK_RC(PNIO_diag_channel_add(wrong, 0, &a, 0x8000, appears, 0x0006, 7),
                 PNIO_ERR_WRONG_HND);
        CHECK_RC(PNIO_diag_channel_add(h, 0, NULL, 0x8000, appears, 0x0006, 7), PNIO_ERR_PRM_ADD);
        CHECK_RC(PNIO_diag_channel_add(h, 0, &a, 0x8000, appears, 0x0006, 7), PNIO_OK);
        /* ChannelNumber, ChannelProperties, ChannelErrorType: big-endian. */
        PNIO_UINT8 item[6] = {0x80, 0x00, (PNIO_UINT8)(appears >> 8), (PNIO_UINT8)appears,
                              0x00, 0x06};
        CHECK_RC(PNIO_diag_alarm_send(h, 0, ar, sk, 3, &a, item, sizeof item,
                                      PNIO_USR_STRUC_ID_CHANNEL_DIAG, 2),
                 PNIO_ERR_PRM_INVALIDARG);
        CHECK_RC(PNIO_diag_alarm_send(h, 0, ar, sk, PNIO_STATE_ALARM_APPEARS, &a, item,
                                      sizeof item, PNIO_USR_STRUC_ID_CHANNEL_DIAG, 2),
                 PNIO_OK);
        int i2 = expect_done(__LINE__, 2, ialarm + 1);
        PNIO_UINT16 gone = PNIO_build_channel_properties(
            h, PNIO_DIAG_CHANPROP_TYPE_SUBMOD, PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_FREE,
            PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE);
        CHECK_RC(PNIO_diag_channel_remove(h, 0, &a, 99), PNIO_OK); /* unknown tag: no error */
        CHECK_RC(PNIO_diag_channel_remove(h, 0, &a, 7), PNIO_OK);
        item[2] = (PNIO_UINT8)(gone >> 8), item[3] = (PNIO_UINT8)gone;
        CHECK_RC(PNIO_diag_alarm_send(h, 0, ar, sk, PNIO_STATE_ALARM_DISAPPEARS, &a, item,
                                      sizeof item, PNIO_USR_STRUC_ID_CHANNEL_DIAG, 3),
                 PNIO_OK);
        int i3 = expect_done(__LINE__, 3, i2 + 1);
        /* Manufacturer diagnosis: kept and removed; a wrong subslot in an alarm is no
         * error, its REQ_DONE says so. */
        PNIO_UINT8 info[4] = {1, 2, 3, 4};
        CHECK_RC(PNIO_diag_generic_add(h, 0, &a, 0, appears, 5, 0x0042, info, 1405),
                 PNIO_ERR_PRM_LEN);
        CHECK_RC(PNIO_diag_generic_add(h, 0, &a, 0, appears, 5, 0x0042, info, sizeof info),
                 PNIO_OK);
        CHECK_RC(PNIO_diag_generic_remove(h, 0, &a, 0), PNIO_OK);
        PNIO_DEV_ADDR none = geo(1, 2);
        CHECK_RC(PNIO_ret_of_sub_alarm_send(h, 0, ar, sk, &none, 4), PNIO_OK);
        int i4 = wait_event(__LINE__, EV_REQ_DONE, i3 + 1);
        CHECK(event(i4).a == 4 && event(i4).b == PNIO_ERR_UNKNOWN_ADDR,
              "REQ_DONE of the return alarm for no submodule: %u 0x%x", (unsigned)event(i4).a,
              (unsigned)event(i4).b);
    }

    /* ---- The station's state as the program reports it ---- */
    CHECK_RC(PNIO_set_dev_state(h, 3), PNIO_ERR_PRM_DEV_STATE);
    CHECK_RC(PNIO_set_dev_state(wrong, PNIO_DEVSTAT_OK), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_set_dev_state(h, PNIO_DEVSTAT_STATION_PROBLEM), PNIO_OK);
    CHECK_RC(PNIO_set_dev_state(h, PNIO_DEVSTAT_OK), PNIO_OK);

    /* ---- Pulled and plugged in data exchange: the PLC parameterizes the submodule again,
     * PRM_END_IND names it, and PNIO_set_appl_state_ready lets it go ---- */
    {
        pthread_mutex_lock(&mu);
        int from = nevents;
        pthread_mutex_unlock(&mu);
        CHECK_RC(PNIO_sub_pull(h, 0, &a), PNIO_OK);
        expect_conf(__LINE__, ++n, h, PNIO_SUB_PULL, 1, 1);
        CHECK_RC(PNIO_sub_plug(h, 0, &a, 0x2), PNIO_OK); /* what the PLC expects */
        expect_conf(__LINE__, ++n, h, PNIO_SUB_PLUG, 1, 1);
        int ip = wait_event(__LINE__, EV_PRM_END, from);
        event_t p = event(ip);
        CHECK(p.ar == ar && p.sk == sk && p.a == 0 && p.b == (1u << 16 | 1),
              "PRM_END_IND of the plugged submodule: AR %u/%u API %u slot/subslot 0x%x",
              (unsigned)p.ar, (unsigned)p.sk, (unsigned)p.a, (unsigned)p.b);
        CHECK_RC(PNIO_set_appl_state_ready(h, ar, sk, NULL), PNIO_OK);
        CHECK_RC(PNIO_set_appl_state_ready(h, ar, sk, NULL), PNIO_ERR_SEQUENCE);
        /* The submodule is the AR's again: its alarms go out. */
        int good = 0;
        for (int k = 0; !good && k < 500; k++) {
            PNIO_UINT32 rc = PNIO_process_alarm_send(h, 0, ar, sk, &a, alarm_data, 1, 1, 5);
            if (rc == PNIO_OK) {
                good = 1;
                expect_done(__LINE__, 5, from);
            } else {
                CHECK(rc == PNIO_ERR_UNKNOWN_ADDR, "alarm after the plug: 0x%x", (unsigned)rc);
                struct timespec pause = {0, 10 * 1000 * 1000};
                nanosleep(&pause, NULL);
            }
        }
        CHECK(good, "the plugged submodule never took an alarm again");
    }

    /* ---- The program aborts the AR: OFFLINE_IND, and the PLC connects again ---- */
    CHECK_RC(PNIO_device_ar_abort(h, ar, sk), PNIO_OK);
    int ioff = wait_event(__LINE__, EV_OFFLINE, iin);
    event_t off = event(ioff);
    /* That AR only: the station ends it with AbortRequest and stays on the wire. */
    CHECK(off.ar == ar && off.sk == sk && off.a == PNIO_AR_REASON_ABORT,
          "AR_OFFLINE_IND for AR %u/%u reason %u", (unsigned)off.ar, (unsigned)off.sk,
          (unsigned)off.a);
    static const int again[] = {EV_AR_CHECK, EV_AR_INFO, EV_PRM_END, 0};
    int iprm2 = wait_event(__LINE__, EV_PRM_END, ioff);
    expect_order(__LINE__, ioff + 1, iprm2, again);
    event_t chk2 = event(wait_event(__LINE__, EV_AR_CHECK, ioff));
    CHECK(chk2.ar == 2, "the second AR's ArNumber is %u", (unsigned)chk2.ar);
    CHECK_RC(PNIO_set_appl_state_ready(h, ar, sk, NULL), PNIO_ERR_SESSION); /* ended */
    /* Ready, but not for slot 1: the PLC gets it "application ready pending" until the
     * program's Return of Submodule alarm. */
    PNIO_APPL_READY_LIST_TYPE nr;
    PNIO_APPL_READY_AP_TYPE nr_api;
    PNIO_APPL_READY_MODULE_TYPE nr_slot;
    PNIO_APPL_READY_SUBMODULE_TYPE nr_sub;
    PNIO_LIST_INITIALIZE(&nr.ap_list);
    nr_api.api = 0;
    PNIO_LIST_INITIALIZE(&nr_api.module_list);
    PNIO_LIST_INSERT_TAIL(&nr.ap_list, &nr_api.link);
    nr_slot.slot_nr = 1;
    PNIO_LIST_INITIALIZE(&nr_slot.submodule_list);
    PNIO_LIST_INSERT_TAIL(&nr_api.module_list, &nr_slot.link);
    nr_sub.subslot_nr = 1;
    PNIO_LIST_INSERT_TAIL(&nr_slot.submodule_list, &nr_sub.link);
    CHECK_RC(PNIO_set_appl_state_ready(h, chk2.ar, chk2.sk, &nr), PNIO_OK);
    int iin2 = wait_event(__LINE__, EV_INDATA, iprm2);
    CHECK_RC(PNIO_ret_of_sub_alarm_send(h, 0, chk2.ar, chk2.sk, &a, 6), PNIO_OK);
    expect_done(__LINE__, 6, iin2);

    /* ---- Stop: OFFLINE_IND, then DEVICE_STOPPED, on the library thread ---- */
    CHECK_RC(PNIO_device_stop(h), PNIO_OK);
    CHECK_RC(PNIO_device_stop(h), PNIO_ERR_SEQUENCE);
    struct timespec until = deadline();
    pthread_mutex_lock(&mu);
    while (!stopped) {
        if (pthread_cond_timedwait(&cv, &mu, &until) != 0) break;
    }
    int got = stopped;
    pthread_mutex_unlock(&mu);
    CHECK(got, "PNIO_CBF_DEVICE_STOPPED did not come");
    CHECK(stopped_handle == h && stopped_code == PNIO_OK,
          "DEVICE_STOPPED(handle %u, code 0x%x)", (unsigned)stopped_handle, (unsigned)stopped_code);
    CHECK(!stopped_on_main_thread, "DEVICE_STOPPED came on the program's thread");
    static const int stop[] = {EV_INDATA, EV_OFFLINE, EV_STOPPED, 0};
    int istop = wait_event(__LINE__, EV_STOPPED, iin2);
    expect_order(__LINE__, iin2, istop, stop);
    CHECK(event(wait_event(__LINE__, EV_OFFLINE, iin2)).ar == chk2.ar,
          "OFFLINE_IND not for the second AR");
    CHECK_RC(PNIO_device_ar_abort(h, chk2.ar, chk2.sk), PNIO_ERR_SEQUENCE); /* stopped */
    CHECK_RC(PNIO_initiate_data_write(h), PNIO_WARN_NO_SUBMODULES);           /* no AR */
    CHECK_RC(PNIO_initiate_data_read(h), PNIO_WARN_NO_SUBMODULES);
    for (int i = 0; i < istop; i++) {
        event_t e = event(i);
        PNIO_UINT32 run = e.a & PNIO_EVENT_APDU_STATUS_RUN;
        PNIO_UINT32 stp = e.a & PNIO_EVENT_APDU_STATUS_STOP;
        /* The demo PLC is the primary, without a station problem. */
        if (e.type == EV_APDU)
            CHECK((e.a & PNIO_EVENT_APDU_STATUS_STATION_OK) &&
                      (e.a & PNIO_EVENT_APDU_STATUS_PRIMARY) && (!run != !stp) &&
                      !(e.a & (PNIO_EVENT_APDU_STATUS_STATION_PROBLEM |
                               PNIO_EVENT_APDU_STATUS_BACKUP)),
                  "APDU_STATUS_IND 0x%x", (unsigned)e.a);
    }

    /* ---- Pull, remove, close ---- */
    CHECK_RC(PNIO_mod_pull(h, 0, &a), PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_MOD_PULL, 1, 1);
    CHECK_RC(PNIO_sub_pull(h, 0, &a), PNIO_ERR_SEQUENCE); /* went with its module */
    CHECK_RC(PNIO_mod_pull(h, 0, &dap), PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_MOD_PULL, 0, 1);
    CHECK_RC(PNIO_api_remove(h, 0), PNIO_OK);
    CHECK_RC(PNIO_api_remove(h, 0), PNIO_ERR_PRM_ADD);
    CHECK_RC(PNIO_device_close(h), PNIO_OK);
    CHECK_RC(PNIO_device_close(h), PNIO_ERR_WRONG_HND);
    CHECK_RC(PNIO_api_add(h, 0, 2, 1), PNIO_ERR_WRONG_HND);

    /* The instance can be opened again, with _ext. */
    CHECK_RC(PNIO_device_open_ext(1, EXT, VENDOR, DEVICE, 1, 3, &ann, &cbf, 2, 0x8001, &h2),
             PNIO_OK);
    CHECK_RC(PNIO_api_add_ext(h2, 0), PNIO_OK);
    CHECK_RC(PNIO_device_close(h2), PNIO_OK);

    printf("all checks held\n");
    return 0;
}
