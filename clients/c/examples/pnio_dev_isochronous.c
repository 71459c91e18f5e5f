/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * An isochronous IO-Base device program against procimgd in the device role: DevEasy's
 * start (open, API 0, the DAP and an IO module in slot 1), then, before PNIO_device_start,
 * PNIO_CP_register_cbf for PNIO_CP_CBE_OPFAULT_IND and then PNIO_CP_CBE_STARTOP_IND (the
 * manual's step 7: OPFAULT first). From then on every cycle's STARTOP callback reads the
 * PLC's outputs (PNIO_initiate_data_read_ext), writes them back as inputs
 * (PNIO_initiate_data_write_ext) and ends the cycle with PNIO_CP_set_opdone, all between
 * STARTOP and OPDONE, where a cycle's data is consistent. The demo PLC adds one to every
 * input byte, so the outputs count the round trips.
 *
 *   cc -std=c11 pnio_dev_isochronous.c $(pkg-config --cflags --libs procimg)
 *   procimgd --demo-device-program &
 *   ./a.out [cycles [vendor_id device_id]]
 *
 * The AR comes as in DevEasy (AR_CHECK_IND, AR_INFO_IND, PRM_END_IND, then
 * PNIO_set_appl_state_ready, AR_INDATA_IND); STARTOP comes in every cycle from registration
 * on, with or without an AR, and before the AR's PRM_END_IND the IO data calls answer
 * PNIO_WARN_NO_SUBMODULES, which the program counts and goes on. After `cycles` cycles with
 * data exchanged (default 1000) it stops, pulls and closes, and prints what the cycles saw;
 * exits 0 when they ran, the outputs came back and no call failed.
 *
 * The IO data calls use PNIO_ACCESS_ALL_WITHOUT_LOCK: procimgd's station cycles its
 * submodules' data as RT (the demo has no IRT submodules, so PNIO_ACCESS_IRT_WITHOUT_LOCK
 * would visit none), and ALL takes RT and IRT data alike.
 *
 * CP 1 is the instance in $PROCIMG_CP1, else $PROCIMG_INSTANCE, else "procimg"; VendorID and
 * DeviceID are the demo station's 0x0493 and 0x0100 unless $PNIO_VENDOR_ID and
 * $PNIO_DEVICE_ID or the command line say otherwise.
 */
#define _POSIX_C_SOURCE 200809L
#include "pniousrd.h"
#include "procimg.h"
#include "device_example.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define CP_INDEX 1
/* The DAP and the IO module as the station's GSDML file describes them (the demo's module
 * 0x10: 8 bytes in and out); the program defines its station, as pnio_dev_easy.c says. */
#define DAP_MOD_IDENT 0x00000001u
#define DAP_SUB_IDENT 0x00000001u
#define IO_MOD_IDENT 0x00000010u
#define IO_SUB_IDENT 0x00000001u
#define IO_SLOT 1
#define IO_LEN 8
#define PARAM_INDEX 1
#define PARAM_LEN 4
#define WAIT_S 30

static PNIO_UINT32 handle;

/* ---- The isochronous part: no file or screen output in here ---------------------------- */

/* STARTOP callbacks come one at a time, and the IO data callbacks on their thread inside
 * them: the buffers used only there need no lock. */
static PNIO_UINT8 q[IO_LEN];     /* the PLC's outputs of this cycle */
static PNIO_UINT8 sent[IO_LEN];  /* the inputs written last */
static PNIO_IOXS q_iops;

static atomic_long startops;     /* STARTOP_IND */
static atomic_long exchanged;    /* cycles in which read and write returned PNIO_OK */
static atomic_long trips;        /* outputs that came back as the inputs sent + 1 */
static atomic_long no_submodules; /* PNIO_WARN_NO_SUBMODULES: no AR past PRM_END_IND yet */
static atomic_long inconsistent; /* PNIO_WARN_IRT_INCONSISTENT: the window was over */
static atomic_long io_errors;    /* any other result of the IO data calls or set_opdone */
static atomic_uint first_error;
static atomic_long opfaults;     /* OPFAULT_IND */
/* After PNIO_device_start returned and before PNIO_device_stop: outside, STARTOP comes too
 * and the IO data calls answer PNIO_ERR_SEQUENCE, which is no failure. */
static atomic_int started_flag;

static PNIO_IOXS data_read(PNIO_UINT32 h, PNIO_DEV_ADDR *a, PNIO_UINT32 len, PNIO_UINT8 *buf,
                           PNIO_IOXS iops) {
    (void)h, (void)a;
    PNIO_UINT32 n = len < IO_LEN ? len : IO_LEN;
    int plus_one = iops == PNIO_S_GOOD && n == IO_LEN && memcmp(buf, q, IO_LEN) != 0;
    for (PNIO_UINT32 k = 0; k < n; k++)
        if (buf[k] != (PNIO_UINT8)(sent[k] + 1)) plus_one = 0;
    if (plus_one) atomic_fetch_add(&trips, 1);
    memcpy(q, buf, n);
    q_iops = iops;
    return PNIO_S_GOOD;
}

static PNIO_IOXS data_write(PNIO_UINT32 h, PNIO_DEV_ADDR *a, PNIO_UINT32 len, PNIO_UINT8 *buf,
                            PNIO_IOXS iocs) {
    (void)h, (void)a, (void)iocs;
    PNIO_UINT32 n = len < IO_LEN ? len : IO_LEN;
    memcpy(buf, q, n); /* the outputs, back to the PLC */
    memcpy(sent, q, n);
    return PNIO_S_GOOD;
}

/* Counts result `r` of a call made while the device was started from before the call
 * (`started_before`) to after it: a call that began before PNIO_device_start returned, or
 * ended after PNIO_device_stop was asked for, may answer PNIO_ERR_SEQUENCE by right. */
static void count(PNIO_UINT32 r, int started_before) {
    if (!started_before || !atomic_load(&started_flag)) {
        return;
    } else if (r == PNIO_WARN_NO_SUBMODULES) {
        atomic_fetch_add(&no_submodules, 1);
    } else if (r == PNIO_WARN_IRT_INCONSISTENT) {
        atomic_fetch_add(&inconsistent, 1);
    } else if (r != PNIO_OK) {
        unsigned none = 0;
        atomic_compare_exchange_strong(&first_error, &none, r);
        atomic_fetch_add(&io_errors, 1);
    }
}

static void on_startop(PNIO_CP_CBE_PRM *p) {
    (void)p;
    atomic_fetch_add(&startops, 1);
    int started = atomic_load(&started_flag);
    PNIO_UINT32 rd = PNIO_initiate_data_read_ext(handle, NULL, PNIO_ACCESS_ALL_WITHOUT_LOCK);
    PNIO_UINT32 wr = PNIO_initiate_data_write_ext(handle, NULL, PNIO_ACCESS_ALL_WITHOUT_LOCK);
    PNIO_UINT32 od = PNIO_CP_set_opdone(handle, NULL);
    count(rd, started);
    if (wr != rd) count(wr, started);
    if (rd == PNIO_OK && wr == PNIO_OK) atomic_fetch_add(&exchanged, 1);
    count(od, started);
}

static void on_opfault(PNIO_CP_CBE_PRM *p) {
    (void)p;
    atomic_fetch_add(&opfaults, 1);
}

/* ---- The other callbacks: flags for the main thread ------------------------------------- */

enum { AR_NONE, AR_CHECKED, AR_INFO, AR_PRM_END, AR_INDATA, AR_ENDED };

static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;
static int confs, ar_phase, out_of_order, stopped;
static PNIO_UINT32 conf_error, stopped_code;
static PNIO_UINT16 ar_number, session_key;
static PNIO_UINT8 param[PARAM_LEN];

static void set_phase(int phase) {
    pthread_mutex_lock(&mu);
    if (phase != AR_CHECKED && phase != AR_ENDED && ar_phase != phase - 1) out_of_order++;
    ar_phase = phase;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

static int is_param(PNIO_UINT32 api, const PNIO_DEV_ADDR *a, PNIO_UINT32 index) {
    return api == 0 && a != NULL && a->u.Geo.Slot == IO_SLOT && a->u.Geo.Subslot == 1 &&
           index == PARAM_INDEX;
}

/* The parameter record the PLC writes is kept and given back on a read; others are
 * refused (ErrorCode 0xDE read / 0xDF write, PNIORW, invalid index or length). */
static void rec_read(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                     PNIO_UINT32 seq, PNIO_DEV_ADDR *a, PNIO_UINT32 index, PNIO_UINT32 *len,
                     PNIO_UINT8 *buf, PNIO_ERR_STAT *st) {
    (void)h, (void)ar, (void)sk, (void)seq;
    memset(st, 0, sizeof *st);
    pthread_mutex_lock(&mu);
    if (is_param(api, a, index) && *len >= PARAM_LEN) {
        memcpy(buf, param, PARAM_LEN);
        *len = PARAM_LEN;
    } else {
        *len = 0;
        st->ErrCode = 0xDE, st->ErrDecode = 0x80, st->ErrCode1 = 0xB0;
    }
    pthread_mutex_unlock(&mu);
}

static void rec_write(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                      PNIO_UINT32 seq, PNIO_DEV_ADDR *a, PNIO_UINT32 index, PNIO_UINT32 *len,
                      PNIO_UINT8 *buf, PNIO_ERR_STAT *st) {
    (void)h, (void)ar, (void)sk, (void)seq;
    memset(st, 0, sizeof *st);
    pthread_mutex_lock(&mu);
    if (is_param(api, a, index) && *len == PARAM_LEN)
        memcpy(param, buf, PARAM_LEN);
    else
        st->ErrCode = 0xDF, st->ErrDecode = 0x80, st->ErrCode1 = is_param(api, a, index) ? 0xB1 : 0xB0;
    pthread_mutex_unlock(&mu);
}

static void req_done(PNIO_UINT32 h, PNIO_UINT32 u, PNIO_UINT32 s, PNIO_ERR_STAT *st) {
    (void)h, (void)u, (void)s, (void)st; /* this program sends no alarms */
}

static void check_ind(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                      PNIO_DEV_ADDR *a, PNIO_UINT32 *mi, PNIO_UINT16 *ms, PNIO_UINT32 *si,
                      PNIO_UINT16 *ss) {
    (void)h, (void)api, (void)ar, (void)sk, (void)a, (void)mi, (void)si;
    *ms = PNIO_MOD_STATE_PROPER_MODULE;
    *ss = PNIO_SUB_CHECK_PROPER_SUBMODULE;
}

static void ar_check_ind(PNIO_UINT32 h, PNIO_UINT32 ip, PNIO_UINT16 t, PNIO_UUID_TYPE u,
                         PNIO_UINT32 props, PNIO_UUID_TYPE c, PNIO_UINT16 l, PNIO_UINT8 *n,
                         PNIO_AR_TYPE *ar) {
    (void)h, (void)ip, (void)t, (void)u, (void)props, (void)c, (void)l, (void)n;
    pthread_mutex_lock(&mu);
    ar_number = ar->ArNumber;
    session_key = ar->SessionKey;
    pthread_mutex_unlock(&mu);
    set_phase(AR_CHECKED);
}

static void ar_info_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_TYPE *p) {
    (void)h, (void)ar, (void)sk, (void)p;
    set_phase(AR_INFO);
}

static void prm_end_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_UINT32 api,
                        PNIO_UINT16 slot, PNIO_UINT16 subslot) {
    (void)h, (void)ar, (void)sk, (void)api, (void)slot;
    if (subslot == 0) set_phase(AR_PRM_END);
}

static void ar_indata_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk) {
    (void)h, (void)ar, (void)sk;
    set_phase(AR_INDATA);
}

static void ar_end_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_REASON r) {
    (void)h, (void)ar, (void)sk, (void)r;
    set_phase(AR_ENDED);
}

static void apdu_status_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk,
                            PNIO_APDU_STATUS_IND s) {
    (void)h, (void)ar, (void)sk, (void)s;
}

static void cp_stop_req(PNIO_UINT32 h) { (void)h; }

static void device_stopped(PNIO_UINT32 h, PNIO_UINT32 code) {
    (void)h;
    pthread_mutex_lock(&mu);
    stopped = 1;
    stopped_code = code;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

static void pull_plug_conf(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_DEV_ACTION action,
                           PNIO_DEV_ADDR *a, PNIO_UINT32 error) {
    (void)h, (void)api, (void)action, (void)a;
    pthread_mutex_lock(&mu);
    confs++;
    if (error != PNIO_OK && conf_error == PNIO_OK) conf_error = error;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

/* ---- The main thread -------------------------------------------------------------------- */

static int wait_for(const int *value, int at_least, const char *what) {
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += WAIT_S;
    pthread_mutex_lock(&mu);
    while (*value < at_least) {
        if (pthread_cond_timedwait(&cv, &mu, &until) != 0) break;
    }
    int came = *value >= at_least;
    pthread_mutex_unlock(&mu);
    if (!came) fprintf(stderr, "pnio_dev_isochronous: %s did not come within %d s\n", what, WAIT_S);
    return came;
}

static int call(const char *what, PNIO_UINT32 r) {
    if (r == PNIO_OK) return 1;
    fprintf(stderr, "pnio_dev_isochronous: %s failed with 0x%03x\n  %s\n", what, (unsigned)r,
            procimg_last_error());
    return 0;
}

static int plug(PNIO_DEV_ADDR *a, PNIO_UINT32 mod, PNIO_UINT32 sub, PNIO_PLUG_IM0_BITS im0) {
    int n = confs;
    return call("PNIO_mod_plug", PNIO_mod_plug(handle, 0, a, mod)) &&
           wait_for(&confs, n + 1, "PULL_PLUG_CONF") &&
           call("PNIO_sub_plug_ext_IM",
                PNIO_sub_plug_ext_IM(handle, 0, a, sub, PNIO_ALARM_TYPE_PLUG, im0)) &&
           wait_for(&confs, n + 2, "PULL_PLUG_CONF") && call("plugging", conf_error);
}

int main(int argc, char **argv) {
    long want = argc > 1 ? strtol(argv[1], NULL, 10) : 1000;
    unsigned long vendor = parse_id(argc > 2 ? argv[2] : NULL, "PNIO_VENDOR_ID", DEMO_VENDOR_ID);
    unsigned long device = parse_id(argc > 3 ? argv[3] : NULL, "PNIO_DEVICE_ID", DEMO_DEVICE_ID);
    if (want <= 0 || vendor > 0xFFFF || device > 0xFFFF) {
        fprintf(stderr, "usage: %s [cycles [vendor_id device_id]]\n", argv[0]);
        return 2;
    }
    setvbuf(stdout, NULL, _IOLBF, 0);

    PNIO_ANNOTATION ann = example_annotation();
    PNIO_CBF_FUNCTIONS cbf;
    memset(&cbf, 0, sizeof cbf);
    cbf.size = sizeof cbf;
    cbf.cbf_data_write = data_write;
    cbf.cbf_data_read = data_read;
    cbf.cbf_rec_read = rec_read;
    cbf.cbf_rec_write = rec_write;
    cbf.cbf_alarm_done = req_done;
    cbf.cbf_check_ind = check_ind;
    cbf.cbf_ar_check_ind = ar_check_ind;
    cbf.cbf_ar_info_ind = ar_info_ind;
    cbf.cbf_ar_indata_ind = ar_indata_ind;
    cbf.cbf_ar_abort_ind = ar_end_ind;
    cbf.cbf_ar_offline_ind = ar_end_ind;
    cbf.cbf_apdu_status_ind = apdu_status_ind;
    cbf.cbf_prm_end_ind = prm_end_ind;
    cbf.pnio_cbf_cp_stop_req = cp_stop_req;
    cbf.pnio_cbf_device_stopped = device_stopped;
    cbf.cbf_pull_plug_conf = pull_plug_conf;

    PNIO_UINT32 r = PNIO_device_open(CP_INDEX, PNIO_CEP_MODE_CTRL, (PNIO_UINT16)vendor,
                                     (PNIO_UINT16)device, 1, 1, &ann, &cbf, &handle);
    if (!call("PNIO_device_open", r)) return 1;
    printf("isochronous device open: handle %u\n", (unsigned)handle);

    PNIO_DEV_ADDR dap = geo(0, 1), io = geo(IO_SLOT, 1);
    int ok = call("PNIO_api_add", PNIO_api_add(handle, 0, IO_SLOT, 1)) &&
             plug(&dap, DAP_MOD_IDENT, DAP_SUB_IDENT, PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV) &&
             plug(&io, IO_MOD_IDENT, IO_SUB_IDENT, PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MODULE);
    if (ok) printf("plugged the DAP and the IO module\n");

    /* Before start, OPFAULT first. */
    ok = ok && call("PNIO_CP_register_cbf(OPFAULT_IND)",
                    PNIO_CP_register_cbf(handle, PNIO_CP_CBE_OPFAULT_IND, on_opfault));
    ok = ok && call("PNIO_CP_register_cbf(STARTOP_IND)",
                    PNIO_CP_register_cbf(handle, PNIO_CP_CBE_STARTOP_IND, on_startop));
    if (ok) printf("registered OPFAULT_IND, then STARTOP_IND\n");

    int started = ok && call("PNIO_device_start", PNIO_device_start(handle));
    atomic_store(&started_flag, started);
    ok = started;
    if (ok) printf("device started\n");
    ok = ok && wait_for(&ar_phase, AR_PRM_END, "AR_CHECK_IND .. PRM_END_IND");
    if (ok) {
        /* The STARTOP callbacks have been giving the first IO data all along. */
        pthread_mutex_lock(&mu);
        PNIO_UINT16 ar = ar_number, sk = session_key;
        pthread_mutex_unlock(&mu);
        ok = call("PNIO_set_appl_state_ready", PNIO_set_appl_state_ready(handle, ar, sk, NULL));
        ok = ok && wait_for(&ar_phase, AR_INDATA, "AR_INDATA_IND");
        if (ok) printf("AR %u in data exchange\n", (unsigned)ar);
    }

    /* The cycles run in the STARTOP callback; here only their count is watched. */
    long before = atomic_load(&exchanged), waited = 0;
    while (ok && atomic_load(&exchanged) - before < want && waited < WAIT_S * 1000L) {
        sleep_ms(10);
        waited += 10;
    }
    long cycles = atomic_load(&exchanged) - before;

    atomic_store(&started_flag, 0);
    if (started) {
        ok = call("PNIO_device_stop", PNIO_device_stop(handle)) &&
             wait_for(&stopped, 1, "DEVICE_STOPPED") && call("DEVICE_STOPPED", stopped_code) && ok;
        if (stopped) printf("device stopped\n");
    }
    int n = confs;
    if (call("PNIO_mod_pull", PNIO_mod_pull(handle, 0, &io))) wait_for(&confs, ++n, "PULL_PLUG_CONF");
    if (call("PNIO_mod_pull", PNIO_mod_pull(handle, 0, &dap))) wait_for(&confs, ++n, "PULL_PLUG_CONF");
    PNIO_api_remove(handle, 0);
    ok = call("PNIO_device_close", PNIO_device_close(handle)) && ok;

    /* After close no callback runs: the counts are final. */
    printf("STARTOP cycles: %ld in all, %ld with data exchanged, %ld round trips through the PLC\n",
           atomic_load(&startops), cycles, atomic_load(&trips));
    printf("before PRM_END_IND (PNIO_WARN_NO_SUBMODULES): %ld, late (PNIO_WARN_IRT_INCONSISTENT): "
           "%ld, OPFAULT_IND: %ld\n",
           atomic_load(&no_submodules), atomic_load(&inconsistent), atomic_load(&opfaults));
    printf("failed IO data calls and PNIO_CP_set_opdone: %ld (first 0x%03x)\n",
           atomic_load(&io_errors), atomic_load(&first_error));
    pthread_mutex_lock(&mu);
    int disorder = out_of_order;
    pthread_mutex_unlock(&mu);
    if (cycles < want || atomic_load(&trips) == 0 || atomic_load(&io_errors) != 0 || disorder) {
        fprintf(stderr, "pnio_dev_isochronous: %ld of %ld cycles, %ld round trips, %ld errors, %d "
                        "AR indications out of order\n",
                cycles, want, atomic_load(&trips), atomic_load(&io_errors), disorder);
        ok = 0;
    }
    if (ok) printf("isochronous device: all steps done\n");
    return ok ? 0 : 1;
}
