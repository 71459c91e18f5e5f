/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * An isochronous STARTOP/OPDONE loop with procimg.h, against `procimgd --demo`:
 * each cycle writes its cycle number into the outputs of the demo's echo device, in place in
 * shared memory, and reads back what the device echoes into its inputs.
 *
 *   cc -std=c11 native_cycle.c -I clients/c/include -I shm-layout/include -lprocimg
 *   procimgd --demo &
 *   ./a.out [instance [cycles]]
 *
 * The instance is argv[1], else $PROCIMG_INSTANCE, else "procimg"; cycles argv[2] (1000).
 * Exits 0 when the echo device sent back what earlier cycles wrote; 1 when a call failed or
 * nothing came back (then it says why: most often the server is not in OPERATE, e.g. an
 * IO-Base program took it to OFFLINE).
 */
#include "procimg.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Reports a failed call and ends the program (detaching first when attached). */
static void fail(const char *what, procimg_error_t code, procimg_client_t *c)
{
    fprintf(stderr, "native_cycle: %s: %s\n  %s\n", what, procimg_strerror(code),
            procimg_last_error());
    if (c != NULL)
        procimg_detach(c);
    exit(1);
}

int main(int argc, char **argv)
{
    const char *instance = argc > 1 ? argv[1] : getenv("PROCIMG_INSTANCE");
    long cycles = argc > 2 ? strtol(argv[2], NULL, 10) : 1000;
    procimg_client_t *c = NULL;
    procimg_attach_options_t opts;
    procimg_cycle_info_t info;
    procimg_event_t ev;
    procimg_error_t r;
    size_t echo, len, i;
    uint64_t first = 0, last = 0, echoed = 0, lag_max = 0;
    long n, opfaults = 0, missed = 0;

    if (instance == NULL || instance[0] == '\0')
        instance = "procimg";
    if (cycles <= 0) {
        fprintf(stderr, "usage: %s [instance [cycles]]\n", argv[0]);
        return 2;
    }

    procimg_attach_options_init(&opts);
    opts.role = PROCIMG_ROLE_SYNCHRONOUS;
    if ((r = procimg_attach(instance, "native_cycle", &opts, &c)) != PROCIMG_OK)
        fail("attach", r, NULL);
    if ((r = procimg_find_submodule(c, "echo", 1, 1, &echo)) != PROCIMG_OK)
        fail("find the echo module (is this `procimgd --demo`?)", r, c);
    if ((r = procimg_claim_device(c, "echo")) != PROCIMG_OK)
        fail("claim the echo outputs", r, c);

    for (n = 0; n < cycles; n++) {
        const uint8_t *in;
        uint8_t *out;
        uint64_t k, back = 0;

        if ((r = procimg_wait_startop(c, 1000, &info)) != PROCIMG_OK)
            fail("wait for STARTOP", r, c);
        k = info.cycle_number;
        if (first == 0)
            first = k;
        else if (k != last + 1)
            missed += (long)(k - last - 1);
        last = k;

        /* The echo inputs: the cycle number some earlier cycle wrote, little-endian. */
        if ((r = procimg_input(c, echo, &in, &len)) != PROCIMG_OK || len < 8)
            fail("read the echo inputs", r, c);
        for (i = 0; i < 8; i++)
            back |= (uint64_t)in[i] << (8 * i);
        if (back >= first && back < k) {
            echoed++;
            if (k - back > lag_max)
                lag_max = k - back;
        }

        /* This cycle's number into the echo outputs, in place. */
        if ((r = procimg_output(c, echo, &out, &len)) != PROCIMG_OK || len < 8)
            fail("write the echo outputs", r, c);
        for (i = 0; i < 8; i++)
            out[i] = (uint8_t)(k >> (8 * i));

        if ((r = procimg_set_opdone(c, NULL)) != PROCIMG_OK)
            fail("set OPDONE", r, c);
        while (procimg_next_event(c, &ev) == PROCIMG_OK)
            if (ev.kind == PROCIMG_EVENT_OPFAULT)
                opfaults++;
    }

    printf("native_cycle: %ld cycles on instance \"%s\" (%llu to %llu, %ld missed), "
           "%llu echoed at most %llu cycles later, %ld OPFAULT\n",
           cycles, instance, (unsigned long long)first, (unsigned long long)last, missed,
           (unsigned long long)echoed, (unsigned long long)lag_max, opfaults);
    if (echoed == 0) {
        /* Nothing came back: most likely the server is not exchanging data. */
        uint32_t mode = PROCIMG_MODE_OPERATE;
        if ((r = procimg_mode(c, &mode)) != PROCIMG_OK)
            fail("read the mode", r, c);
        if (mode != PROCIMG_MODE_OPERATE)
            fprintf(stderr,
                    "native_cycle: no echo in %ld cycles: instance \"%s\" is in mode %s, "
                    "not OPERATE; `procimg mode operate --instance %s` sets it (`procimg "
                    "status` shows the mode)\n",
                    cycles, instance, mode == PROCIMG_MODE_OFFLINE ? "OFFLINE" : "CLEAR",
                    instance);
        else
            fprintf(stderr,
                    "native_cycle: no echo in %ld cycles although instance \"%s\" is in "
                    "OPERATE: is the echo device in data exchange? `procimg status --instance "
                    "%s` shows its state\n",
                    cycles, instance, instance);
    }
    if ((r = procimg_detach(c)) != PROCIMG_OK)
        fail("detach", r, NULL);
    return echoed > 0 ? 0 : 1;
}
