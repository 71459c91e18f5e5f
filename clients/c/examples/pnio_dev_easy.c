/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * DevEasy, the IO-Base manual's first IO device program, against procimgd in the device role:
 *
 *   1. PNIO_device_open with the station's VendorID and DeviceID, PNIO_api_add(API 0),
 *   2. plug the DAP (slot 0, subslot 1) and an IO module (slot 1, subslot 1), each confirmed
 *      by PNIO_CBF_PULL_PLUG_CONF,
 *   3. PNIO_device_start, then the PLC's AR through the indications: AR_CHECK_IND (keep
 *      ArNumber and SessionKey), AR_INFO_IND, the parameter records in REC_WRITE,
 *      PRM_END_IND, then the first IO data and PNIO_set_appl_state_ready, AR_INDATA_IND,
 *   4. cyclic IO data for a few seconds: PNIO_initiate_data_read takes the PLC's outputs,
 *      PNIO_initiate_data_write gives them back as inputs (the demo PLC adds one to every
 *      input byte, so the bytes count the round trips),
 *   5. a process alarm, acknowledged in PNIO_CBF_REQ_DONE,
 *   6. a channel diagnosis with its alarm (appears), then removed with its alarm
 *      (disappears), each acknowledged in PNIO_CBF_REQ_DONE,
 *   7. PNIO_device_stop (the AR ends, PNIO_CBF_DEVICE_STOPPED), pull, PNIO_api_remove,
 *      PNIO_device_close.
 *
 * All the while REC_WRITE keeps the parameter record the PLC writes (record 1 of the IO
 * module, 4 bytes) and REC_READ gives it back.
 *
 *   cc -std=c11 pnio_dev_easy.c $(pkg-config --cflags --libs procimg)
 *   procimgd --demo-device-program &
 *   ./a.out [seconds [vendor_id device_id]]
 *
 * CP 1 is the instance in $PROCIMG_CP1, else $PROCIMG_INSTANCE, else "procimg". The VendorID
 * and DeviceID must be those of procimgd's station (`procimg status --json`, or
 * `vendor_id`/`device_id` in its configuration): the demo's 0x0493 and 0x0100 unless
 * $PNIO_VENDOR_ID and $PNIO_DEVICE_ID or the command line say otherwise. Prints each step;
 * exits 0 when all of them happened, in this order.
 *
 * The program defines its station: against `procimgd --demo-device-program` (or any
 * configuration with `[station] gsdml` and no submodules) its plugs are the station's tree,
 * each checked against the station's GSDML file, which gives the IO lengths (the demo's
 * module 0x10: 8 bytes in and out, parameter record 1). Against a station whose
 * configuration gives the tree (`procimgd --demo-device`) the plugs must lie at its
 * positions. See "A station the program defines" and "Plugging" in pniousrd.h. VendorID
 * 0x0493 is the demo's; a product needs a VendorID of its own from PROFIBUS & PROFINET
 * International, and its own GSDML file.
 */
#define _POSIX_C_SOURCE 200809L
#include "pniousrd.h"
#include "procimg.h"
#include "device_example.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define CP_INDEX 1

/* The program's ident numbers, as the station's GSDML file describes them: the DAP (the
 * demo's 1 and 1) and an IO module (the demo's 0x10 with submodule 1). */
#define DAP_MOD_IDENT 0x00000001u
#define DAP_SUB_IDENT 0x00000001u
#define IO_MOD_IDENT 0x00000010u
#define IO_SUB_IDENT 0x00000001u
#define IO_SLOT 1
#define IO_SUBSLOT 1
#define IO_LEN 8 /* the module's IO lengths in the GSDML file */

/* The parameter record of the IO module the PLC writes. */
#define PARAM_INDEX 1
#define PARAM_LEN 4

/* UserHndl of the alarms, given back in PNIO_CBF_REQ_DONE. */
#define H_PROCESS 1
#define H_DIAG_APPEARS 2
#define H_DIAG_DISAPPEARS 3
#define DIAG_TAG 1

/* How long a step may take before the program gives up. */
#define WAIT_S 30

/* ---- What the callbacks saw ------------------------------------------------------------- */

/* Callbacks run on a library thread: they note what came under `mu` and wake the main
 * loop, which makes the calls the manual allows outside callbacks only. */
static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;

/* The AR's phases, in the manual's order. */
enum { AR_NONE, AR_CHECKED, AR_INFO, AR_PRM_END, AR_INDATA, AR_ENDED };

static struct {
    int confs;              /* PULL_PLUG_CONF */
    PNIO_UINT32 conf_error; /* the first one's error that was not PNIO_OK */
    int ar_phase;
    int out_of_order;       /* AR indications not in the manual's order */
    PNIO_UINT16 ar, sk;     /* from AR_CHECK_IND */
    int offline_before_stopped;
    int stopped;
    PNIO_UINT32 stopped_code;
    int rec_writes, rec_reads;
    PNIO_UINT8 param[PARAM_LEN];
    int done[4]; /* REQ_DONE per UserHndl */
    PNIO_UINT32 done_status[4];
    /* IO data */
    PNIO_UINT8 q[IO_LEN];
    PNIO_IOXS q_iops;
} s;

static void note_phase(int phase, const char *what) {
    /* Each indication must follow the one before it (a new AR starts over). */
    if (phase != AR_CHECKED && s.ar_phase != phase - 1) {
        s.out_of_order++;
        printf("%s out of order (after phase %d)\n", what, s.ar_phase);
    }
    s.ar_phase = phase;
    pthread_cond_broadcast(&cv);
}

static PNIO_IOXS data_write(PNIO_UINT32 h, PNIO_DEV_ADDR *addr, PNIO_UINT32 len,
                            PNIO_UINT8 *buf, PNIO_IOXS iocs) {
    (void)h, (void)addr, (void)iocs;
    pthread_mutex_lock(&mu);
    /* The inputs: the outputs last read, back to the PLC. */
    memcpy(buf, s.q, len < IO_LEN ? len : IO_LEN);
    pthread_mutex_unlock(&mu);
    return PNIO_S_GOOD;
}

static PNIO_IOXS data_read(PNIO_UINT32 h, PNIO_DEV_ADDR *addr, PNIO_UINT32 len,
                           PNIO_UINT8 *buf, PNIO_IOXS iops) {
    (void)h, (void)addr;
    pthread_mutex_lock(&mu);
    memcpy(s.q, buf, len < IO_LEN ? len : IO_LEN);
    s.q_iops = iops;
    pthread_mutex_unlock(&mu);
    return PNIO_S_GOOD;
}

static int is_param(PNIO_UINT32 api, const PNIO_DEV_ADDR *a, PNIO_UINT32 index) {
    return api == 0 && a != NULL && a->u.Geo.Slot == IO_SLOT && a->u.Geo.Subslot == IO_SUBSLOT &&
           index == PARAM_INDEX;
}

/* A refusal: ErrorCode (0xDE read, 0xDF write), ErrorDecode PNIORW, ErrorCode1. */
static void refuse(PNIO_ERR_STAT *st, PNIO_UINT8 code, PNIO_UINT8 code1) {
    st->ErrCode = code;
    st->ErrDecode = 0x80;
    st->ErrCode1 = code1;
}

static void rec_read(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                     PNIO_UINT32 seq, PNIO_DEV_ADDR *addr, PNIO_UINT32 index, PNIO_UINT32 *len,
                     PNIO_UINT8 *buf, PNIO_ERR_STAT *st) {
    (void)h, (void)ar, (void)sk, (void)seq;
    pthread_mutex_lock(&mu);
    memset(st, 0, sizeof *st);
    if (is_param(api, addr, index)) {
        PNIO_UINT32 n = *len < PARAM_LEN ? *len : PARAM_LEN;
        memcpy(buf, s.param, n);
        *len = n;
        s.rec_reads++;
        printf("REC_READ: record %u given back\n", (unsigned)index);
    } else {
        *len = 0;
        refuse(st, 0xDE, 0xB0); /* invalid index */
        printf("REC_READ: record %u refused\n", (unsigned)index);
    }
    pthread_mutex_unlock(&mu);
}

static void rec_write(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                      PNIO_UINT32 seq, PNIO_DEV_ADDR *addr, PNIO_UINT32 index, PNIO_UINT32 *len,
                      PNIO_UINT8 *buf, PNIO_ERR_STAT *st) {
    (void)h, (void)ar, (void)sk, (void)seq;
    pthread_mutex_lock(&mu);
    memset(st, 0, sizeof *st);
    if (!is_param(api, addr, index)) {
        refuse(st, 0xDF, 0xB0); /* invalid index */
        printf("REC_WRITE: record %u refused\n", (unsigned)index);
    } else if (*len != PARAM_LEN) {
        refuse(st, 0xDF, 0xB1); /* write length error */
        printf("REC_WRITE: record %u of %u bytes refused\n", (unsigned)index, (unsigned)*len);
    } else {
        memcpy(s.param, buf, PARAM_LEN);
        s.rec_writes++;
        printf("REC_WRITE: record %u = %02x %02x %02x %02x kept\n", (unsigned)index, buf[0],
               buf[1], buf[2], buf[3]);
    }
    pthread_mutex_unlock(&mu);
}

static void req_done(PNIO_UINT32 h, PNIO_UINT32 user, PNIO_UINT32 status, PNIO_ERR_STAT *st) {
    (void)h, (void)st;
    pthread_mutex_lock(&mu);
    if (user < 4) {
        s.done[user]++;
        s.done_status[user] = status;
    }
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

/* Called only where the PLC expects other ident numbers than the program plugged: say
 * that what is plugged is the right one. */
static void check_ind(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_UINT16 ar, PNIO_UINT16 sk,
                      PNIO_DEV_ADDR *addr, PNIO_UINT32 *mod_ident, PNIO_UINT16 *mod_state,
                      PNIO_UINT32 *sub_ident, PNIO_UINT16 *sub_state) {
    (void)h, (void)api, (void)ar, (void)sk;
    printf("CHECK_IND: slot %u subslot %u: the PLC expects module 0x%x submodule 0x%x\n",
           (unsigned)addr->u.Geo.Slot, (unsigned)addr->u.Geo.Subslot, (unsigned)*mod_ident,
           (unsigned)*sub_ident);
    *mod_state = PNIO_MOD_STATE_PROPER_MODULE;
    *sub_state = PNIO_SUB_CHECK_PROPER_SUBMODULE;
}

static void ar_check_ind(PNIO_UINT32 h, PNIO_UINT32 ip, PNIO_UINT16 type, PNIO_UUID_TYPE ar_uuid,
                         PNIO_UINT32 props, PNIO_UUID_TYPE cmi_uuid, PNIO_UINT16 name_len,
                         PNIO_UINT8 *name, PNIO_AR_TYPE *ar) {
    (void)h, (void)ip, (void)ar_uuid, (void)props, (void)cmi_uuid;
    pthread_mutex_lock(&mu);
    s.ar = ar->ArNumber;
    s.sk = ar->SessionKey;
    printf("AR_CHECK_IND: AR %u, session key %u, type %u, from \"%.*s\"\n",
           (unsigned)ar->ArNumber, (unsigned)ar->SessionKey, (unsigned)type, (int)name_len,
           (const char *)name);
    note_phase(AR_CHECKED, "AR_CHECK_IND");
    pthread_mutex_unlock(&mu);
}

static void ar_info_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_TYPE *p) {
    (void)h, (void)sk;
    pthread_mutex_lock(&mu);
    printf("AR_INFO_IND: AR %u, %u IOCRs, %u modules\n", (unsigned)ar, (unsigned)p->NumOfIocr,
           (unsigned)p->NumOfMod);
    for (PNIO_UINT32 m = 0; m < p->NumOfMod; m++) {
        const PNIO_MODULE_TYPE *mod = &p->pModList[m];
        for (PNIO_UINT32 k = 0; k < mod->NumOfSubmod; k++)
            printf("  slot %u subslot 0x%x: module 0x%x submodule 0x%x, %u bytes in, %u out\n",
                   (unsigned)mod->SlotNum, (unsigned)mod->pSubList[k].SubSlotNum,
                   (unsigned)mod->ModIdent, (unsigned)mod->pSubList[k].SubMIdent,
                   (unsigned)mod->pSubList[k].InDatLen, (unsigned)mod->pSubList[k].OutDatLen);
    }
    note_phase(AR_INFO, "AR_INFO_IND");
    pthread_mutex_unlock(&mu);
}

static void prm_end_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_UINT32 api,
                        PNIO_UINT16 slot, PNIO_UINT16 subslot) {
    (void)h, (void)sk, (void)api, (void)slot;
    pthread_mutex_lock(&mu);
    printf("PRM_END_IND: AR %u, subslot %u\n", (unsigned)ar, (unsigned)subslot);
    if (subslot == 0) note_phase(AR_PRM_END, "PRM_END_IND");
    pthread_mutex_unlock(&mu);
}

static void ar_indata_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk) {
    (void)h, (void)sk;
    pthread_mutex_lock(&mu);
    printf("AR_INDATA_IND: AR %u in data exchange\n", (unsigned)ar);
    note_phase(AR_INDATA, "AR_INDATA_IND");
    pthread_mutex_unlock(&mu);
}

static void ar_abort_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_REASON r) {
    (void)h, (void)sk;
    pthread_mutex_lock(&mu);
    printf("AR_ABORT_IND: AR %u, reason %d\n", (unsigned)ar, (int)r);
    s.ar_phase = AR_ENDED;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

static void ar_offline_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk, PNIO_AR_REASON r) {
    (void)h, (void)sk;
    pthread_mutex_lock(&mu);
    printf("AR_OFFLINE_IND: AR %u, reason %d\n", (unsigned)ar, (int)r);
    s.ar_phase = AR_ENDED;
    if (!s.stopped) s.offline_before_stopped = 1;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

static void apdu_status_ind(PNIO_UINT32 h, PNIO_UINT16 ar, PNIO_UINT16 sk,
                            PNIO_APDU_STATUS_IND status) {
    (void)h, (void)ar, (void)sk;
    printf("APDU_STATUS_IND: PLC %s\n", (status & PNIO_EVENT_APDU_STATUS_RUN) ? "RUN" : "STOP");
}

static void cp_stop_req(PNIO_UINT32 h) {
    (void)h;
    printf("CP_STOP_REQ: the device should close\n");
}

static void device_stopped(PNIO_UINT32 h, PNIO_UINT32 code) {
    (void)h;
    pthread_mutex_lock(&mu);
    s.stopped = 1;
    s.stopped_code = code;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

static void pull_plug_conf(PNIO_UINT32 h, PNIO_UINT32 api, PNIO_DEV_ACTION action,
                           PNIO_DEV_ADDR *addr, PNIO_UINT32 error) {
    (void)h, (void)api, (void)action, (void)addr;
    pthread_mutex_lock(&mu);
    s.confs++;
    if (error != PNIO_OK && s.conf_error == PNIO_OK) s.conf_error = error;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

/* ---- Waiting and failing ---------------------------------------------------------------- */

/* Waits until *value >= at_least (under `mu`), at most WAIT_S; whether it came. */
static int wait_for(const int *value, int at_least) {
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += WAIT_S;
    pthread_mutex_lock(&mu);
    while (*value < at_least) {
        if (pthread_cond_timedwait(&cv, &mu, &until) != 0) break;
    }
    int came = *value >= at_least;
    pthread_mutex_unlock(&mu);
    return came;
}

/* A call that failed: its code and the library's text for this thread. */
static int failed(const char *what, PNIO_UINT32 code) {
    fprintf(stderr, "pnio_dev_easy: %s failed with 0x%03x\n  %s\n", what, (unsigned)code,
            procimg_last_error());
    return 0;
}

static int call(const char *what, PNIO_UINT32 code) {
    return code == PNIO_OK ? 1 : failed(what, code);
}

static int missing(const char *what) {
    fprintf(stderr, "pnio_dev_easy: %s did not come within %d s\n", what, WAIT_S);
    return 0;
}

static double now_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec / 1e9;
}

static void put16(PNIO_UINT8 *p, PNIO_UINT16 v) {
    p[0] = (PNIO_UINT8)(v >> 8);
    p[1] = (PNIO_UINT8)v;
}

/* ---- The steps -------------------------------------------------------------------------- */

/* The AR the program serves (main thread only): the alarms go to it. */
static PNIO_UINT16 ar_now, sk_now;

/* Plugs a module and its submodule 1, each confirmed. */
static int plug(PNIO_UINT32 h, PNIO_DEV_ADDR *a, PNIO_UINT32 mod, PNIO_UINT32 sub,
                PNIO_PLUG_IM0_BITS im0, const char *what) {
    int confs = s.confs;
    if (!call("PNIO_mod_plug", PNIO_mod_plug(h, 0, a, mod))) return 0;
    if (!wait_for(&s.confs, confs + 1)) return missing("PULL_PLUG_CONF of PNIO_mod_plug");
    if (!call("PNIO_sub_plug_ext_IM",
              PNIO_sub_plug_ext_IM(h, 0, a, sub, PNIO_ALARM_TYPE_PLUG, im0)))
        return 0;
    if (!wait_for(&s.confs, confs + 2)) return missing("PULL_PLUG_CONF of PNIO_sub_plug_ext_IM");
    if (s.conf_error != PNIO_OK) return failed("plugging", s.conf_error);
    printf("plugged %s: slot %u subslot %u, module 0x%x submodule 0x%x\n", what,
           (unsigned)a->u.Geo.Slot, (unsigned)a->u.Geo.Subslot, (unsigned)mod, (unsigned)sub);
    return 1;
}

/* Waits for the AR's parameters, gives the first IO data and says the application is
 * ready; then waits for data exchange. */
static int connect_ar(PNIO_UINT32 h) {
    PNIO_UINT32 r;
    if (!wait_for(&s.ar_phase, AR_PRM_END)) return missing("AR_CHECK_IND .. PRM_END_IND");
    /* Before application-ready the inputs are set GOOD and the outputs taken (the
     * manual's steps 14 and 15): the I data written now is what the PLC gets with the
     * ApplicationReady. */
    r = PNIO_initiate_data_write(h);
    if (r != PNIO_OK) return failed("PNIO_initiate_data_write", r);
    r = PNIO_initiate_data_read(h);
    if (r != PNIO_OK) return failed("PNIO_initiate_data_read", r);
    pthread_mutex_lock(&mu);
    ar_now = s.ar;
    sk_now = s.sk;
    pthread_mutex_unlock(&mu);
    /* All submodules are ready: an empty list. */
    PNIO_APPL_READY_LIST_TYPE ready;
    ready.ap_list.Flink = ready.ap_list.Blink = NULL;
    /* Said before the call: AR_INDATA_IND may come on the library thread before the call
     * returns. */
    printf("application ready for AR %u\n", (unsigned)ar_now);
    if (!call("PNIO_set_appl_state_ready", PNIO_set_appl_state_ready(h, ar_now, sk_now, &ready)))
        return 0;
    if (!wait_for(&s.ar_phase, AR_INDATA)) return missing("AR_INDATA_IND");
    return 1;
}

/* Reads the outputs and writes them back as inputs for `seconds`. */
static int cycle(PNIO_UINT32 h, double seconds) {
    long rounds = 0, trips = 0;
    PNIO_UINT8 last[IO_LEN] = {0}, first = 0;
    int have_first = 0;
    double end = now_s() + seconds;
    while (now_s() < end) {
        if (!call("PNIO_initiate_data_read", PNIO_initiate_data_read(h))) return 0;
        if (!call("PNIO_initiate_data_write", PNIO_initiate_data_write(h))) return 0;
        rounds++;
        pthread_mutex_lock(&mu);
        PNIO_UINT8 q[IO_LEN];
        memcpy(q, s.q, IO_LEN);
        PNIO_IOXS iops = s.q_iops;
        pthread_mutex_unlock(&mu);
        /* A round trip: the PLC's outputs are the inputs written before, plus one. */
        if (iops == PNIO_S_GOOD && memcmp(q, last, IO_LEN) != 0) {
            int plus_one = 1;
            for (int k = 0; k < IO_LEN; k++)
                if (q[k] != (PNIO_UINT8)(last[k] + 1)) plus_one = 0;
            trips += plus_one;
            if (!have_first) first = q[0], have_first = 1;
            memcpy(last, q, IO_LEN);
        }
        sleep_ms(2);
    }
    printf("cyclic data: %ld rounds, %ld round trips through the PLC (outputs 0x%02x .. 0x%02x)\n",
           rounds, trips, first, last[0]);
    if (trips == 0) {
        fprintf(stderr, "pnio_dev_easy: the PLC's outputs never came back as the inputs + 1\n");
        return 0;
    }
    return 1;
}

/* Sends an alarm with call `what` (already made, its code `r`) and waits for its REQ_DONE. */
static int acknowledged(const char *what, PNIO_UINT32 r, int handle) {
    if (!call(what, r)) return 0;
    if (!wait_for(&s.done[handle], 1)) return missing("REQ_DONE");
    if (s.done_status[handle] != PNIO_OK) return failed("the alarm (REQ_DONE)", s.done_status[handle]);
    return 1;
}

static int process_alarm(PNIO_UINT32 h, PNIO_DEV_ADDR *io) {
    PNIO_UINT8 data[4] = {0x12, 0x34, 0x56, 0x78}; /* the program's, big-endian */
    if (!acknowledged("PNIO_process_alarm_send",
                      PNIO_process_alarm_send(h, 0, ar_now, sk_now, io, data, sizeof data, 0x0001,
                                              H_PROCESS),
                      H_PROCESS))
        return 0;
    printf("process alarm acknowledged (REQ_DONE, handle %d)\n", H_PROCESS);
    return 1;
}

/* The manual's sequence: store the diagnosis, then its alarm (appears); remove it, then its
 * alarm (disappears). The alarm data is the channel diagnosis (UserStructIdent 0x8000):
 * ChannelNumber, ChannelProperties, ChannelErrorType, big-endian. */
static int diagnosis(PNIO_UINT32 h, PNIO_DEV_ADDR *io) {
    const PNIO_UINT16 channel = 0x8000; /* the whole submodule */
    const PNIO_UINT16 error = PNIO_DIAG_CHAN_ERROR_OVERTEMPERATURE;
    PNIO_UINT8 data[6];
    PNIO_UINT16 prop = PNIO_build_channel_properties(h, PNIO_DIAG_CHANPROP_TYPE_SUBMOD,
                                                     PNIO_DIAG_CHAN_SPEC_ERROR_APPEARS,
                                                     PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE);
    if (!call("PNIO_diag_channel_add",
              PNIO_diag_channel_add(h, 0, io, channel, prop, error, DIAG_TAG)))
        return 0;
    put16(data, channel);
    put16(data + 2, prop);
    put16(data + 4, error);
    if (!acknowledged("PNIO_diag_alarm_send(APPEARS)",
                      PNIO_diag_alarm_send(h, 0, ar_now, sk_now, PNIO_STATE_ALARM_APPEARS, io, data,
                                           sizeof data, PNIO_USR_STRUC_ID_CHANNEL_DIAG,
                                           H_DIAG_APPEARS),
                      H_DIAG_APPEARS))
        return 0;
    printf("channel diagnosis added, diagnosis alarm (appears) acknowledged\n");

    prop = PNIO_build_channel_properties(h, PNIO_DIAG_CHANPROP_TYPE_SUBMOD,
                                         PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_FREE,
                                         PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE);
    if (!call("PNIO_diag_channel_remove", PNIO_diag_channel_remove(h, 0, io, DIAG_TAG))) return 0;
    put16(data + 2, prop);
    if (!acknowledged("PNIO_diag_alarm_send(DISAPPEARS)",
                      PNIO_diag_alarm_send(h, 0, ar_now, sk_now, PNIO_STATE_ALARM_DISAPPEARS, io,
                                           data, sizeof data, PNIO_USR_STRUC_ID_CHANNEL_DIAG,
                                           H_DIAG_DISAPPEARS),
                      H_DIAG_DISAPPEARS))
        return 0;
    printf("channel diagnosis removed, diagnosis alarm (disappears) acknowledged\n");
    return 1;
}

/* Stops the device: the AR ends (AR_OFFLINE_IND), then DEVICE_STOPPED. */
static int stop(PNIO_UINT32 h) {
    if (!call("PNIO_device_stop", PNIO_device_stop(h))) return 0;
    if (!wait_for(&s.stopped, 1)) return missing("DEVICE_STOPPED");
    if (s.stopped_code != PNIO_OK) return failed("PNIO_device_stop (DEVICE_STOPPED)", s.stopped_code);
    printf("device stopped%s\n", s.offline_before_stopped ? " (AR_OFFLINE_IND first)" : "");
    return 1;
}

int main(int argc, char **argv) {
    double seconds = argc > 1 ? strtod(argv[1], NULL) : 5.0;
    unsigned long vendor = parse_id(argc > 2 ? argv[2] : NULL, "PNIO_VENDOR_ID", DEMO_VENDOR_ID);
    unsigned long device = parse_id(argc > 3 ? argv[3] : NULL, "PNIO_DEVICE_ID", DEMO_DEVICE_ID);
    if (seconds <= 0 || vendor > 0xFFFF || device > 0xFFFF) {
        fprintf(stderr, "usage: %s [seconds [vendor_id device_id]]\n", argv[0]);
        return 2;
    }
    /* Each line as it happens, also into a pipe. */
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
    cbf.cbf_ar_abort_ind = ar_abort_ind;
    cbf.cbf_ar_offline_ind = ar_offline_ind;
    cbf.cbf_apdu_status_ind = apdu_status_ind;
    cbf.cbf_prm_end_ind = prm_end_ind;
    cbf.pnio_cbf_cp_stop_req = cp_stop_req;
    cbf.pnio_cbf_device_stopped = device_stopped;
    cbf.cbf_pull_plug_conf = pull_plug_conf; /* the LED callbacks are optional */

    /* 1. Open. Until the station has an IP address: PNIO_ERR_CONFIG_IN_UPDATE, open again. */
    PNIO_UINT32 h = 0, r;
    for (int tries = 0;; tries++) {
        r = PNIO_device_open(CP_INDEX, PNIO_CEP_MODE_CTRL, (PNIO_UINT16)vendor,
                             (PNIO_UINT16)device, 1, 1, &ann, &cbf, &h);
        if (r != PNIO_ERR_CONFIG_IN_UPDATE || tries == WAIT_S) break;
        sleep_ms(1000);
    }
    if (r != PNIO_OK) {
        failed("PNIO_device_open", r);
        return 1;
    }
    printf("device open: handle %u, VendorID 0x%04lx, DeviceID 0x%04lx\n", (unsigned)h, vendor,
           device);

    int ok = 1, started = 0;
    PNIO_DEV_ADDR dap = geo(0, 1), io = geo(IO_SLOT, IO_SUBSLOT);

    /* 2. API 0 (its highest slot and subslot), the DAP and the IO module. */
    ok = call("PNIO_api_add", PNIO_api_add(h, 0, IO_SLOT, 1));
    ok = ok && plug(h, &dap, DAP_MOD_IDENT, DAP_SUB_IDENT,
                    PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV, "the DAP");
    ok = ok && plug(h, &io, IO_MOD_IDENT, IO_SUB_IDENT, PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MODULE,
                    "the IO module");

    /* 3. Start; the PLC connects. */
    ok = ok && call("PNIO_device_start", PNIO_device_start(h));
    started = ok;
    if (ok) printf("device started\n");
    ok = ok && connect_ar(h);

    /* 4.-6. Data, alarms, diagnosis. */
    ok = ok && cycle(h, seconds);
    ok = ok && process_alarm(h, &io);
    ok = ok && diagnosis(h, &io);

    pthread_mutex_lock(&mu);
    int writes = s.rec_writes, reads = s.rec_reads, disorder = s.out_of_order;
    pthread_mutex_unlock(&mu);
    printf("parameter record %d: written %d times, read %d times\n", PARAM_INDEX, writes, reads);
    if (ok && writes == 0) {
        fprintf(stderr, "pnio_dev_easy: the PLC wrote no parameter record\n");
        ok = 0;
    }
    if (disorder) {
        fprintf(stderr, "pnio_dev_easy: %d AR indications out of order\n", disorder);
        ok = 0;
    }

    /* 7. Stop, pull, remove, close (also after a failure, as far as it goes). */
    if (started) ok = stop(h) && ok;
    int confs = s.confs;
    if (started || s.confs > 0) {
        if (call("PNIO_mod_pull", PNIO_mod_pull(h, 0, &io)) && wait_for(&s.confs, confs + 1))
            confs++;
        if (call("PNIO_mod_pull", PNIO_mod_pull(h, 0, &dap)) && wait_for(&s.confs, confs + 1))
            confs++;
    }
    PNIO_api_remove(h, 0);
    ok = call("PNIO_device_close", PNIO_device_close(h)) && ok;
    printf("device closed\n");
    if (ok) printf("DevEasy: all steps done\n");
    return ok ? 0 : 1;
}
