/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * An isochronous IO-Base program against procimgd --demo: the STARTOP callback reads this
 * cycle's inputs of the echo device (I 0..15), writes its outputs (Q 0..15) and ends the
 * cycle with PNIO_CP_set_opdone, all between STARTOP and OPDONE, where the data of a cycle
 * is consistent.
 *
 *   cc -std=c11 pnio_isochronous.c -I clients/c/include -I shm-layout/include -lprocimg \
 *       -lpthread -ldl -lm
 *   procimgd --demo &
 *   ./a.out [cycles]
 *
 * It counts the cycles, checks that PNIO_CYCLE_INFO.CycleCount grows by 32 (31.25 us units)
 * per 1 ms cycle (another step means cycles this program did not see), counts the echoes,
 * counts NEWCYCLE_IND, and once misses a cycle's deadline on purpose to see
 * PNIO_CP_CBE_OPFAULT_IND. Exits 0 when the cycles ran, the echo worked and the OPFAULT and
 * NEWCYCLE events came.
 *
 * IRT and RT data: the demo's echo data is IRT (rt_class = 3 in its configuration), the
 * other devices' RT. Outside the window the program reads both from its main thread: the
 * IRT data with PNIO_WARN_IRT_INCONSISTENT (it may not belong to the cycle the rest does),
 * the counter's RT data (I 16..19) with PNIO_OK, as any controller reads it.
 *
 * The server's mode: opening with PNIO_CEP_MODE_CTRL takes the server to OFFLINE and the
 * program ends there, as the manual's programs do; afterwards, outside that flow, it gives
 * the server back the mode it had before it opened, through procimg.h (see server_mode.h).
 *
 * Real time: PNIO_controller_open starts the library's callback threads, and they take the
 * scheduling policy and priority of the thread that calls it. So the program raises its own
 * thread to SCHED_FIFO (below procimgd's cycle thread, 80 by default) before opening, and
 * its STARTOP callback runs at that priority. Without the permission (root or
 * CAP_SYS_NICE) it goes on at normal priority and says so.
 */
#define _POSIX_C_SOURCE 200809L
#include "pniousrx.h"
#include "procimg.h"
#include "server_mode.h"
#include "pnio_example.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define ECHO_LEN 16
/* The cycle in which the program is late on purpose (counted in OPERATE). */
#define LATE_CYCLE 200
/* SCHED_FIFO priority of this program's threads and so of its callbacks. */
#define CALLBACK_PRIORITY 70

static PNIO_UINT32 handle;
static atomic_int mode_reports;
static atomic_int current_mode = PNIO_MODE_OFFLINE;
static atomic_long cycles;        /* STARTOPs in OPERATE */
static atomic_long opfaults;      /* OPFAULT_IND */
static atomic_long newcycles;     /* NEWCYCLE_IND */
static atomic_long steps_32;      /* CycleCount steps of exactly 32 */
static atomic_long steps_other;   /* steps of another multiple of 32 (cycles not seen) */
static atomic_long steps_wrong;   /* steps that are no multiple of 32 */
static atomic_long echoes;        /* inputs equal to outputs sent earlier, GOOD */
static atomic_long io_errors;     /* data_read/data_write/set_opdone failures in OPERATE */
static atomic_uint first_error;   /* the first of them */
static atomic_long window_over;   /* accesses after the window had ended (a late callback) */
static atomic_long late_done;     /* the late cycle happened */
static atomic_long second_opdone = -1; /* what a second PNIO_CP_set_opdone returned */
static long max_opdone_10ns;      /* longest STARTOP..OPDONE, 10 ns units (callback only) */
static atomic_int startop_policy = -1; /* scheduling of the STARTOP callback's thread */
static atomic_int startop_priority;
static PNIO_UINT32 last_count;
static int have_count;
static PNIO_UINT8 sent[ECHO_LEN];

/* Counts what an IO function returned in the STARTOP callback: PNIO_WARN_IRT_INCONSISTENT
 * means this callback ran so late that the next cycle had begun (its window was over). */
static void count_result(PNIO_UINT32 r, int operate) {
    if (r == PNIO_WARN_IRT_INCONSISTENT) {
        atomic_fetch_add(&window_over, 1);
    } else if (r != PNIO_OK && r != PNIO_ERR_NO_CONNECTION && operate) {
        unsigned none = 0;
        atomic_compare_exchange_strong(&first_error, &none, r);
        atomic_fetch_add(&io_errors, 1);
    }
}

static void on_mode(PNIO_CBE_PRM *p) {
    atomic_store(&current_mode, (int)p->ModeInd.Mode);
    atomic_fetch_add(&mode_reports, 1);
}

static void on_record(PNIO_CBE_PRM *p) {
    (void)p;
}

static void on_opfault(PNIO_CP_CBE_PRM *p) {
    (void)p;
    atomic_fetch_add(&opfaults, 1);
}

static void on_newcycle(PNIO_CP_CBE_PRM *p) {
    (void)p;
    atomic_fetch_add(&newcycles, 1);
}

/* The isochronous part: no file or screen output in here. STARTOP callbacks come one at a
 * time, so the statics used only here need no lock. */
static void on_startop(PNIO_CP_CBE_PRM *p) {
    PNIO_CYCLE_INFO done;
    PNIO_ADDR in = logical(PNIO_IO_IN, 0), out = logical(PNIO_IO_OUT, 0);
    PNIO_UINT8 i_data[ECHO_LEN], q[ECHO_LEN];
    PNIO_UINT32 len = 0, r;
    PNIO_IOXS in_remote = PNIO_S_BAD, out_remote = PNIO_S_BAD;
    PNIO_UINT32 count = p->u.StartOp.CycleInfo.CycleCount;
    int operate = atomic_load(&current_mode) == PNIO_MODE_OPERATE;
    long n;
    int k;

    if (!have_count) {
        struct sched_param sp;
        int policy;
        if (pthread_getschedparam(pthread_self(), &policy, &sp) == 0) {
            atomic_store(&startop_priority, sp.sched_priority);
            atomic_store(&startop_policy, policy);
        }
    } else {
        PNIO_UINT32 step = (count - last_count) & 0xFFFF;
        if (step == 32) {
            atomic_fetch_add(&steps_32, 1);
        } else if (step % 32 == 0 && step != 0) {
            atomic_fetch_add(&steps_other, 1);
        } else {
            atomic_fetch_add(&steps_wrong, 1);
        }
    }
    last_count = count;
    have_count = 1;

    r = PNIO_data_read(handle, &in, ECHO_LEN, &len, i_data, PNIO_S_GOOD, &in_remote);
    if (r == PNIO_OK && in_remote == PNIO_S_GOOD && memcmp(i_data, sent, ECHO_LEN) == 0) {
        atomic_fetch_add(&echoes, 1);
    }
    count_result(r, operate);
    n = operate ? atomic_fetch_add(&cycles, 1) + 1 : 0;
    /* A new pattern every 50 cycles: the echo of the last one has come back by then. */
    for (k = 0; k < ECHO_LEN; k++) {
        q[k] = (PNIO_UINT8)(n / 50 + k);
    }
    r = PNIO_data_write(handle, &out, ECHO_LEN, q, PNIO_S_GOOD, &out_remote);
    if (r == PNIO_OK || r == PNIO_WARN_IRT_INCONSISTENT) {
        memcpy(sent, q, ECHO_LEN);
    }
    count_result(r, operate);
    if (n == LATE_CYCLE) {
        /* Late on purpose: OPDONE after the deadline (half the 1 ms cycle). */
        sleep_ms(3);
        atomic_store(&late_done, 1);
    }
    r = PNIO_CP_set_opdone(handle, &done);
    if (n == 100) {
        /* The window is closed now: a second OPDONE in this cycle is refused. */
        atomic_store(&second_opdone, (long)PNIO_CP_set_opdone(handle, NULL));
    }
    count_result(r, 1);
    if (r == PNIO_OK && n != LATE_CYCLE) {
        long took = (long)(done.CountSinceCycleStart - p->u.StartOp.CycleInfo.CountSinceCycleStart);
        if (took > max_opdone_10ns) {
            max_opdone_10ns = took;
        }
    }
}

static int wait_mode_reports(int reports) {
    int i;
    for (i = 0; i < 1000 && atomic_load(&mode_reports) < reports; i++) {
        sleep_ms(10);
    }
    return atomic_load(&mode_reports) >= reports;
}

/* SCHED_FIFO for the calling thread, and so for the callback threads the library starts
 * from it. Returns 0 without the permission. */
static int go_real_time(void) {
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = CALLBACK_PRIORITY;
    return pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
}

/* A failed call: its code, and the library's text for this thread, which names the code
 * (PNIO_ERR_...) and says what to do (procimg_last_error() serves both APIs). */
static int check(const char *what, PNIO_UINT32 r) {
    if (r != PNIO_OK) {
        fprintf(stderr, "pnio_isochronous: %s failed with 0x%03x\n  %s\n", what, r,
                procimg_last_error());
        return 0;
    }
    return 1;
}

/* ---- The isochronous program ------------------------------------------------------------- */

static int isochronous(long want) {
    int i, ok = 1;
    long before, warnings = 0, rt_ok = 0;

    if (!go_real_time()) {
        printf("no permission for SCHED_FIFO: the callbacks run at normal priority\n");
    }
    if (!check("PNIO_controller_open",
               PNIO_controller_open(1, PNIO_CEP_MODE_CTRL, on_record, on_record, NULL, &handle))) {
        return 1;
    }
    /* In OFFLINE: the mode callback, then OPFAULT and NEWCYCLE before STARTOP (IO-Base's
     * order: PNIO_ERR_OPFAULT_NOT_REG and PNIO_ERR_NEWCYCLE_SEQUENCE_REG otherwise). */
    ok = check("PNIO_register_cbf(MODE_IND)", PNIO_register_cbf(handle, PNIO_CBE_MODE_IND, on_mode)) &&
         check("PNIO_CP_register_cbf(OPFAULT)",
               PNIO_CP_register_cbf(handle, PNIO_CP_CBE_OPFAULT_IND, on_opfault)) &&
         check("PNIO_CP_register_cbf(NEWCYCLE)",
               PNIO_CP_register_cbf(handle, PNIO_CP_CBE_NEWCYCLE_IND, on_newcycle)) &&
         check("PNIO_CP_register_cbf(STARTOP)",
               PNIO_CP_register_cbf(handle, PNIO_CP_CBE_STARTOP_IND, on_startop)) &&
         check("PNIO_set_mode(OPERATE)", PNIO_set_mode(handle, PNIO_MODE_OPERATE));
    if (ok && (!wait_mode_reports(2) || atomic_load(&current_mode) != PNIO_MODE_OPERATE)) {
        fprintf(stderr, "pnio_isochronous: OPERATE was not reported\n");
        ok = 0;
    }
    if (ok) {
        printf("isochronous controller %u in OPERATE\n", handle);
        /* Outside the STARTOP..OPDONE window IRT data is not consistent: reads from here
         * work, with a warning (unless they happen to fall into a window). RT data is read
         * as always. */
        for (i = 0; i < 6000 && atomic_load(&cycles) < want; i++) {
            PNIO_ADDR in = logical(PNIO_IO_IN, 0);
            PNIO_UINT8 b[ECHO_LEN];
            PNIO_UINT32 len, r;
            PNIO_IOXS rem;
            sleep_ms(10);
            r = PNIO_data_read(handle, &in, ECHO_LEN, &len, b, PNIO_S_GOOD, &rem);
            if (r == PNIO_WARN_IRT_INCONSISTENT) {
                warnings++;
            } else if (r != PNIO_OK && r != PNIO_ERR_NO_CONNECTION) {
                fprintf(stderr, "pnio_isochronous: PNIO_data_read outside the window: 0x%03x\n", r);
                ok = 0;
            }
            PNIO_ADDR counter = logical(PNIO_IO_IN, 16);
            r = PNIO_data_read(handle, &counter, 4, &len, b, PNIO_S_GOOD, &rem);
            if (r == PNIO_OK) {
                rt_ok++;
            } else if (r != PNIO_ERR_NO_CONNECTION) {
                fprintf(stderr, "pnio_isochronous: reading RT data outside the window: 0x%03x\n",
                        r);
                ok = 0;
            }
        }
        printf("IRT reads outside the window: %ld with PNIO_WARN_IRT_INCONSISTENT\n", warnings);
        printf("RT reads outside the window: %ld with PNIO_OK\n", rt_ok);
        if (rt_ok == 0) {
            fprintf(stderr, "pnio_isochronous: no RT read outside the window was PNIO_OK\n");
            ok = 0;
        }
        if (warnings == 0) {
            fprintf(stderr, "pnio_isochronous: no read outside the window was warned about\n");
            ok = 0;
        }
        before = atomic_load(&mode_reports);
        ok = check("PNIO_set_mode(OFFLINE)", PNIO_set_mode(handle, PNIO_MODE_OFFLINE));
        if (ok && (!wait_mode_reports((int)before + 2) ||
                   atomic_load(&current_mode) != PNIO_MODE_OFFLINE)) {
            fprintf(stderr, "pnio_isochronous: OFFLINE was not reported\n");
            ok = 0;
        }
    }
    if (!check("PNIO_controller_close", PNIO_controller_close(handle))) {
        ok = 0;
    }

    if (atomic_load(&startop_policy) == SCHED_FIFO) {
        printf("STARTOP callbacks at SCHED_FIFO %d\n", atomic_load(&startop_priority));
    } else {
        printf("STARTOP callbacks at normal priority\n");
    }
    printf("cycles in OPERATE: %ld (asked for %ld)\n", atomic_load(&cycles), want);
    printf("CycleCount steps: %ld of 32, %ld of another multiple of 32 (cycles not seen), "
           "%ld wrong\n",
           atomic_load(&steps_32), atomic_load(&steps_other), atomic_load(&steps_wrong));
    printf("echoes seen: %ld, OPFAULTs: %ld, NEWCYCLEs: %ld\n", atomic_load(&echoes),
           atomic_load(&opfaults), atomic_load(&newcycles));
    printf("accesses after a window had ended: %ld; IO errors: %ld (first 0x%03x)\n",
           atomic_load(&window_over), atomic_load(&io_errors), atomic_load(&first_error));
    printf("longest STARTOP..OPDONE: %ld us\n", max_opdone_10ns / 100);

    if (atomic_load(&cycles) < want) {
        fprintf(stderr, "pnio_isochronous: too few cycles\n");
        ok = 0;
    }
    if (atomic_load(&steps_wrong) != 0 || atomic_load(&steps_32) < atomic_load(&cycles) / 2) {
        fprintf(stderr, "pnio_isochronous: CycleCount does not grow by 32 per cycle\n");
        ok = 0;
    }
    if (atomic_load(&echoes) == 0) {
        fprintf(stderr, "pnio_isochronous: the inputs never echoed the outputs\n");
        ok = 0;
    }
    if (atomic_load(&late_done) && atomic_load(&opfaults) == 0) {
        fprintf(stderr, "pnio_isochronous: the late cycle got no OPFAULT_IND\n");
        ok = 0;
    }
    printf("a second PNIO_CP_set_opdone in one cycle: 0x%03lx\n", atomic_load(&second_opdone));
    if (atomic_load(&second_opdone) != PNIO_ERR_SEQUENCE) {
        fprintf(stderr, "pnio_isochronous: a second OPDONE was not refused with SEQUENCE\n");
        ok = 0;
    }
    if (atomic_load(&newcycles) == 0) {
        fprintf(stderr, "pnio_isochronous: no NEWCYCLE_IND came\n");
        ok = 0;
    }
    if (atomic_load(&io_errors) != 0) {
        fprintf(stderr, "pnio_isochronous: IO functions failed in the STARTOP callback\n");
        ok = 0;
    }
    return ok ? 0 : 1;
}

int main(int argc, char **argv) {
    long want = argc > 1 ? strtol(argv[1], NULL, 10) : 1000;
    const char *instance = cp_instance();
    uint32_t before = 0;
    int known, rc;

    if (want <= LATE_CYCLE) {
        fprintf(stderr, "usage: %s [cycles > %d]\n", argv[0], LATE_CYCLE);
        return 2;
    }
    /* Without a server this finds nothing, and PNIO_controller_open says what to do. */
    known = server_mode("pnio_isochronous", instance, &before);
    rc = isochronous(want);
    if (known && !restore_mode("pnio_isochronous", instance, before)) {
        rc = 1;
    }
    return rc;
}
