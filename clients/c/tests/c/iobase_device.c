/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The IO-Base device management and configuration functions of libprocimg as a DevEasy-like
 * program uses them, against `procimgd --demo-device` (CpIndex 1 = the instance in
 * PROCIMG_INSTANCE): the checks of PNIO_device_open, wrong handles, calls out of sequence,
 * plug and pull before start with their PNIO_CBF_PULL_PLUG_CONF on a library thread, start,
 * stop with PNIO_CBF_DEVICE_STOPPED, pull, remove and close.
 *
 * The demo's station: VendorID 0x0493, DeviceID 0x0100; the DAP in slot 0 (module and
 * submodule ident 1), slot 1 (module 0x10, submodule 1), slot 2 (module 0x20, submodule 1),
 * all in API 0. Prints "all checks held" at the end.
 */
#define _POSIX_C_SOURCE 200809L

#include "pniousrd.h"
#include "procimg.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define WAIT_S 10

static void fail(int line, const char *fmt, ...) {
    va_list ap;
    fprintf(stderr, "line %d: ", line);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, " (last error: %s)\n", procimg_last_error());
    exit(1);
}

#define CHECK(cond, ...)                               \
    do {                                               \
        if (!(cond)) fail(__LINE__, __VA_ARGS__);      \
    } while (0)

#define CHECK_RC(call, expected)                                                         \
    do {                                                                                 \
        PNIO_UINT32 rc_ = (call);                                                        \
        if (rc_ != (PNIO_UINT32)(expected))                                              \
            fail(__LINE__, "%s returned 0x%x, expected 0x%x", #call, (unsigned)rc_,      \
                 (unsigned)(expected));                                                  \
    } while (0)

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

/* ---- The other callbacks: mandatory, not called by these functions -------------------- */

static PNIO_IOXS data_write(PNIO_UINT32 h, PNIO_DEV_ADDR *a, PNIO_UINT32 len, PNIO_UINT8 *buf,
                            PNIO_IOXS rem) {
    (void)h, (void)a, (void)len, (void)buf, (void)rem;
    return PNIO_S_GOOD;
}
static PNIO_IOXS data_read(PNIO_UINT32 h, PNIO_DEV_ADDR *a, PNIO_UINT32 len, PNIO_UINT8 *buf,
                           PNIO_IOXS rem) {
    (void)h, (void)a, (void)len, (void)buf, (void)rem;
    return PNIO_S_GOOD;
}
static void rec(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_UINT32 seq,
                PNIO_DEV_ADDR *a, PNIO_UINT32 idx, PNIO_UINT32 *len, PNIO_UINT8 *buf,
                PNIO_ERR_STAT *st) {
    (void)h, (void)api, (void)ar, (void)sk, (void)seq, (void)a, (void)idx, (void)len,
        (void)buf, (void)st;
}
static void req_done(PNIO_UINT32 h, PNIO_UINT32 u, PNIO_UINT32 s, PNIO_ERR_STAT *st) {
    (void)h, (void)u, (void)s, (void)st;
}
static void check_ind(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                      PNIO_DEV_ADDR *a, PNIO_UINT32 *mi, PNIO_UINT16 *ms, PNIO_UINT32 *si,
                      PNIO_UINT16 *ss) {
    (void)h, (void)api, (void)ar, (void)sk, (void)a, (void)mi, (void)ms, (void)si, (void)ss;
}
static void ar_check_ind(PNIO_UINT32 h, PNIO_UINT32 ip, PNIO_UINT16 t, PNIO_UUID_TYPE u,
                         PNIO_UINT32 p, PNIO_UUID_TYPE c, PNIO_UINT16 l, PNIO_UINT8 *n,
                         PNIO_AR_TYPE *ar) {
    (void)h, (void)ip, (void)t, (void)u, (void)p, (void)c, (void)l, (void)n, (void)ar;
}
static void ar_info_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_TYPE *p) {
    (void)h, (void)ar, (void)sk, (void)p;
}
static void ar_indata_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk) {
    (void)h, (void)ar, (void)sk;
}
static void ar_end_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_REASON r) {
    (void)h, (void)ar, (void)sk, (void)r;
}
static void apdu_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_APDU_STATUS_IND s) {
    (void)h, (void)ar, (void)sk, (void)s;
}
static void prm_end_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_UINT32 api,
                        PNIO_UINT16 slot, PNIO_UINT16 subslot) {
    (void)h, (void)ar, (void)sk, (void)api, (void)slot, (void)subslot;
}
static void cp_stop_req(PNIO_UINT32 h) { (void)h; }

static PNIO_CBF_FUNCTIONS table(void) {
    PNIO_CBF_FUNCTIONS c;
    memset(&c, 0, sizeof c);
    c.size = sizeof c;
    c.cbf_data_write = data_write;
    c.cbf_data_read = data_read;
    c.cbf_rec_read = rec;
    c.cbf_rec_write = rec;
    c.cbf_alarm_done = req_done;
    c.cbf_check_ind = check_ind;
    c.cbf_ar_check_ind = ar_check_ind;
    c.cbf_ar_info_ind = ar_info_ind;
    c.cbf_ar_indata_ind = ar_indata_ind;
    c.cbf_ar_abort_ind = ar_end_ind;
    c.cbf_ar_offline_ind = ar_end_ind;
    c.cbf_apdu_status_ind = apdu_ind;
    c.cbf_prm_end_ind = prm_end_ind;
    c.pnio_cbf_cp_stop_req = cp_stop_req;
    c.cbf_device_stopped = device_stopped;
    c.cbf_pull_plug_conf = pull_plug_conf; /* LED flashing stays NULL: optional */
    return c;
}

static PNIO_DEV_ADDR at(PNIO_UINT32 slot, PNIO_UINT32 subslot) {
    PNIO_DEV_ADDR a;
    memset(&a, 0, sizeof a);
    a.AddrType = PNIO_ADDR_GEO;
    a.IODataType = PNIO_IO_IN;
    a.u.Geo.Slot = slot;
    a.u.Geo.Subslot = subslot;
    return a;
}

#define VENDOR 0x0493
#define DEVICE 0x0100
#define EXT PNIO_CEP_MODE_CTRL

int main(void) {
    main_thread = pthread_self();
    PNIO_ANNOTATION ann;
    memset(&ann, 0, sizeof ann);
    strcpy((char *)ann.deviceType, "procimg device");
    strcpy((char *)ann.orderId, "PROCIMG-DEV");
    ann.hwRevision = 1;
    ann.swRevisionPrefix = 'V';
    ann.swRevision2 = 1;
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
    PNIO_DEV_ADDR a = at(1, 1);
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
    PNIO_DEV_ADDR dap = at(0, 1);
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
    PNIO_DEV_ADDR far = at(1, 0x9000);
    CHECK_RC(PNIO_sub_plug_ext_IM(h, 0, &far, 1, PNIO_ALARM_TYPE_PLUG, PNIO_PLUG_IM0_BITS_NOTHING),
             PNIO_ERR_PRM_ADD); /* above MaxSubslots */
    PNIO_DEV_ADDR zero = at(1, 0);
    CHECK_RC(PNIO_sub_plug_ext(h, 0, &zero, 1, PNIO_ALARM_TYPE_PLUG), PNIO_ERR_PRM_ADD);
    PNIO_DEV_ADDR slot3 = at(3, 1);
    CHECK_RC(PNIO_mod_plug(h, 0, &slot3, 0x30), PNIO_ERR_PRM_ADD); /* above MaxSlots */
    PNIO_DEV_ADDR unconfigured = at(1, 2);
    CHECK_RC(PNIO_sub_plug_ext(h, 0, &unconfigured, 1, PNIO_ALARM_TYPE_PLUG), PNIO_ERR_PRM_ADD);
    CHECK_RC(PNIO_sub_plug_ext(h, 0, NULL, 1, PNIO_ALARM_TYPE_PLUG), PNIO_ERR_PRM_ADD);
    CHECK_RC(PNIO_sub_plug_ext(h, 0, &a, 1, 0x77), PNIO_ERR_PRM_INVALIDARG);

    /* ---- Pull and plug again before start ---- */
    CHECK_RC(PNIO_sub_pull(h, 0, &a), PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_SUB_PULL, 1, 1);
    CHECK_RC(PNIO_sub_plug_ext(h, 0, &a, 0x1, PNIO_ALARM_TYPE_PLUG), PNIO_OK);
    expect_conf(__LINE__, ++n, h, PNIO_SUB_PLUG, 1, 1);
    CHECK_RC(PNIO_api_remove(h, 0), PNIO_ERR_SEQUENCE); /* it has modules */

    /* ---- Start: slot 2, not plugged by the program, is pulled ---- */
    CHECK_RC(PNIO_device_start(h), PNIO_OK);
    CHECK_RC(PNIO_device_start(h), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_api_add(h, 0, 2, 1), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_api_remove(h, 0), PNIO_ERR_SEQUENCE);
    CHECK_RC(PNIO_device_close(h), PNIO_ERR_SEQUENCE);

    /* ---- Stop, confirmed on the library thread ---- */
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
