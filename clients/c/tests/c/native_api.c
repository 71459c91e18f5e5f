/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The native C API (procimg.h) as a C program uses it. One program, one part per run:
 *
 *   native_api errors   no server: NULL arguments, bad options, a missing instance
 *   native_api sync     a synchronous client against `procimgd --demo`: 300 cycles through
 *                       the echo device in place, the window's errors, claims, threads
 *   native_api async    an asynchronous client: access by address and the caches
 *   native_api modes    OFFLINE and back to OPERATE, with the MODE events
 *
 * The instance comes from $PROCIMG_INSTANCE. Exit 0 when every check held; each failed
 * check prints its line, the call, the code and the last error text.
 */
#define _POSIX_C_SOURCE 200809L

#include "procimg.h"

#include <poll.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int failures;

static void expect_code(procimg_error_t got, procimg_error_t want, const char *call, int line)
{
    if (got != want) {
        fprintf(stderr, "line %d: %s\n  returned %d (%s), want %d (%s)\n  last error: %s\n",
                line, call, got, procimg_strerror(got), want, procimg_strerror(want),
                procimg_last_error());
        failures++;
    }
}

#define EXPECT(want, call) expect_code((call), (want), #call, __LINE__)
#define OK(call) EXPECT(PROCIMG_OK, call)
#define NP(call) EXPECT(PROCIMG_ERR_NULL_POINTER, call)
#define CHECK(cond)                                                        \
    do {                                                                   \
        if (!(cond)) {                                                     \
            fprintf(stderr, "line %d: %s does not hold\n", __LINE__, #cond); \
            failures++;                                                    \
        }                                                                  \
    } while (0)
/* A step later checks build on: stop the program when it fails. */
#define MUST(call)                                                                    \
    do {                                                                              \
        procimg_error_t must_ = (call);                                               \
        if (must_ != PROCIMG_OK) {                                                    \
            fprintf(stderr, "line %d: %s failed: %s\n  last error: %s\n", __LINE__, #call, \
                    procimg_strerror(must_), procimg_last_error());                   \
            exit(2);                                                                  \
        }                                                                             \
    } while (0)

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec / 1e9;
}

static void sleep_ms(long ms)
{
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

static const char *instance(void)
{
    const char *i = getenv("PROCIMG_INSTANCE");
    if (i == NULL) {
        fprintf(stderr, "set PROCIMG_INSTANCE\n");
        exit(2);
    }
    return i;
}

static procimg_client_t *attach(const char *name, uint32_t role)
{
    procimg_attach_options_t opts;
    procimg_client_t *c = NULL;
    procimg_attach_options_init(&opts);
    opts.role = role;
    MUST(procimg_attach(instance(), name, &opts, &c));
    return c;
}

static size_t find(procimg_client_t *c, const char *device, uint16_t slot)
{
    size_t index = 0;
    MUST(procimg_find_submodule(c, device, slot, 1, &index));
    return index;
}

static const procimg_submodule_entry_t *entry(procimg_client_t *c, size_t index)
{
    const procimg_submodule_entry_t *table = NULL;
    size_t count = 0;
    MUST(procimg_submodules(c, &table, &count));
    if (index >= count) {
        fprintf(stderr, "submodule %zu not in a table of %zu\n", index, count);
        exit(2);
    }
    return &table[index];
}

/* Every function with each required pointer NULL, `c` being NULL or a live client. */
static void null_arguments(procimg_client_t *c)
{
    const procimg_submodule_entry_t *table;
    const uint8_t *in;
    uint8_t *out;
    uint8_t buf[4] = {0};
    size_t count, index, len, data_len, sub = 0;
    procimg_client_t *made;
    const uint8_t good = PROCIMG_IOXS_GOOD;

    NP(procimg_attach(NULL, "n", NULL, &made));
    NP(procimg_attach("i", NULL, NULL, &made));
    NP(procimg_attach("i", "n", NULL, NULL));
    NP(procimg_submodules(c, NULL, &count));
    NP(procimg_submodules(c, &table, NULL));
    NP(procimg_find_submodule(c, NULL, 1, 1, &index));
    NP(procimg_find_submodule(c, "echo", 1, 1, NULL));
    NP(procimg_device_name(c, 0, NULL));
    NP(procimg_layout_hash(c, NULL));
    NP(procimg_claim(c, NULL, 1));
    NP(procimg_release(c, NULL, 1));
    NP(procimg_claim_device(c, NULL));
    NP(procimg_inputs(c, NULL, &len));
    NP(procimg_inputs(c, &in, NULL));
    NP(procimg_input(c, sub, NULL, &len));
    NP(procimg_input(c, sub, &in, NULL));
    NP(procimg_outputs(c, NULL, &len));
    NP(procimg_outputs(c, &out, NULL));
    NP(procimg_output(c, sub, NULL, &len));
    NP(procimg_output(c, sub, &out, NULL));
    NP(procimg_submodule_status(c, sub, NULL));
    NP(procimg_data_read(c, 0, NULL, sizeof buf, &data_len, good, NULL));
    NP(procimg_data_read(c, 0, buf, sizeof buf, NULL, good, NULL));
    NP(procimg_output_data_read(c, 0, NULL, sizeof buf, &data_len, NULL, NULL));
    NP(procimg_output_data_read(c, 0, buf, sizeof buf, NULL, NULL, NULL));
    NP(procimg_data_write(c, 0, NULL, sizeof buf, good, NULL));
    NP(procimg_read_cache(c, 0, NULL, sizeof buf, &data_len, good, NULL));
    NP(procimg_read_cache(c, 0, buf, sizeof buf, NULL, good, NULL));
    NP(procimg_write_cache(c, 0, NULL, sizeof buf, good, NULL));
    NP(procimg_mode(c, NULL));
    NP(procimg_next_event(c, NULL));
    NP(procimg_event_fd(c, NULL));
}

/* Every function with a NULL client and valid other arguments. */
static void null_client(void)
{
    const procimg_submodule_entry_t *table;
    const char *name;
    const uint8_t *in;
    uint8_t *out;
    uint8_t buf[4] = {0}, st;
    size_t count, index, len, data_len, sub = 0;
    uint64_t hash;
    uint32_t mode;
    int fd;
    procimg_cycle_info_t info;
    procimg_event_t ev;
    procimg_submodule_ioxs_t ioxs;
    const uint8_t good = PROCIMG_IOXS_GOOD;

    NP(procimg_detach(NULL));
    NP(procimg_submodules(NULL, &table, &count));
    NP(procimg_find_submodule(NULL, "echo", 1, 1, &index));
    NP(procimg_device_name(NULL, 0, &name));
    NP(procimg_layout_hash(NULL, &hash));
    NP(procimg_claim(NULL, &sub, 1));
    NP(procimg_release(NULL, &sub, 1));
    NP(procimg_claim_device(NULL, "echo"));
    NP(procimg_wait_startop(NULL, 0, &info));
    NP(procimg_wait_startop(NULL, 0, NULL));
    NP(procimg_inputs(NULL, &in, &len));
    NP(procimg_input(NULL, sub, &in, &len));
    NP(procimg_outputs(NULL, &out, &len));
    NP(procimg_output(NULL, sub, &out, &len));
    NP(procimg_submodule_status(NULL, sub, &ioxs));
    NP(procimg_set_output_status(NULL, sub, good));
    NP(procimg_set_opdone(NULL, &info));
    NP(procimg_set_opdone(NULL, NULL));
    NP(procimg_data_read(NULL, 0, buf, sizeof buf, &data_len, good, &st));
    NP(procimg_output_data_read(NULL, 0, buf, sizeof buf, &data_len, &st, &st));
    NP(procimg_data_write(NULL, 0, buf, sizeof buf, good, &st));
    NP(procimg_read_cache_refresh(NULL));
    NP(procimg_read_cache(NULL, 0, buf, sizeof buf, &data_len, good, &st));
    NP(procimg_write_cache(NULL, 0, buf, sizeof buf, good, &st));
    NP(procimg_write_cache_flush(NULL));
    NP(procimg_set_mode(NULL, PROCIMG_MODE_OPERATE));
    NP(procimg_mode(NULL, &mode));
    NP(procimg_next_event(NULL, &ev));
    NP(procimg_event_fd(NULL, &fd));
}

static void errors(void)
{
    static const procimg_error_t codes[] = {
        PROCIMG_OK, PROCIMG_ERR_NULL_POINTER, PROCIMG_ERR_INVALID_ARGUMENT,
        PROCIMG_ERR_NO_SERVER, PROCIMG_ERR_REFUSED, PROCIMG_ERR_LAYOUT, PROCIMG_ERR_TIMEOUT,
        PROCIMG_ERR_SERVER_GONE, PROCIMG_ERR_NOT_IN_CYCLE, PROCIMG_ERR_UNKNOWN_ADDRESS,
        PROCIMG_ERR_LENGTH, PROCIMG_ERR_NOT_CLAIMED, PROCIMG_ERR_NO_IMAGE,
        PROCIMG_ERR_NOT_DELIVERED, PROCIMG_ERR_WRONG_ROLE, PROCIMG_ERR_NO_EVENT,
        PROCIMG_ERR_BUSY, PROCIMG_ERR_INTERNAL};
    const char *unknown = "unknown procimg error code";
    procimg_attach_options_t opts;
    procimg_client_t *c = (procimg_client_t *)&opts; /* must come back NULL */
    double t0;
    size_t i;

    CHECK(procimg_last_error() != NULL && strcmp(procimg_last_error(), "") == 0);
    for (i = 0; i < sizeof codes / sizeof codes[0]; i++) {
        const char *s = procimg_strerror(codes[i]);
        CHECK(s != NULL && strlen(s) > 0 && strcmp(s, unknown) != 0);
    }
    CHECK(strcmp(procimg_strerror(17), unknown) == 0);
    CHECK(strcmp(procimg_strerror(-1), unknown) == 0);

    procimg_attach_options_init(NULL);
    memset(&opts, 0xff, sizeof opts);
    procimg_attach_options_init(&opts);
    CHECK(opts.struct_size == sizeof opts);
    CHECK(opts.role == PROCIMG_ROLE_SYNCHRONOUS);
    CHECK(opts.flags == PROCIMG_ATTACH_SLICE_ACCESS);
    CHECK(opts.timeout_ms == 3000 && opts.layout_hash == 0);

    null_client();
    null_arguments(NULL);

    /* Bad options are refused before any server is asked. */
    opts.flags = 0x100;
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_attach(instance(), "n", &opts, &c));
    CHECK(c == NULL);
    CHECK(strstr(procimg_last_error(), "0x100") != NULL);
    procimg_attach_options_init(&opts);
    opts.role = 7;
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_attach(instance(), "n", &opts, &c));
    procimg_attach_options_init(&opts);
    opts.struct_size = 4;
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_attach(instance(), "n", &opts, &c));
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_attach(instance(), "\xff\xfe", NULL, &c));

    /* No server: refused quickly, the text names the instance. */
    procimg_attach_options_init(&opts);
    opts.timeout_ms = 200;
    t0 = now_s();
    EXPECT(PROCIMG_ERR_NO_SERVER, procimg_attach(instance(), "n", &opts, &c));
    CHECK(now_s() - t0 < 2.0);
    CHECK(c == NULL);
    CHECK(strstr(procimg_last_error(), instance()) != NULL);
    opts.role = PROCIMG_ROLE_ASYNCHRONOUS;
    EXPECT(PROCIMG_ERR_NO_SERVER, procimg_attach(instance(), "n", &opts, &c));
}

/* Calls on one handle from a second thread while the first waits for STARTOP. */
struct contender {
    procimg_client_t *c;
    atomic_int stop;
    int busy, ok, other, layout_failed;
};

static void *contend(void *arg)
{
    struct contender *k = arg;
    while (!atomic_load(&k->stop)) {
        uint32_t mode;
        uint64_t hash;
        procimg_error_t r = procimg_mode(k->c, &mode);
        if (r == PROCIMG_ERR_BUSY)
            k->busy++;
        else if (r == PROCIMG_OK)
            k->ok++;
        else
            k->other++;
        if (procimg_layout_hash(k->c, &hash) != PROCIMG_OK)
            k->layout_failed++;
        {
            /* Leave the CPUs to the server's simulated devices now and then. */
            struct timespec t = {0, 200000L};
            nanosleep(&t, NULL);
        }
    }
    return NULL;
}

/* Retries a call that another thread of this test may find busy. */
#define UNBUSY(call) \
    do {             \
        r = (call);  \
    } while (r == PROCIMG_ERR_BUSY)

static void threads(procimg_client_t *c)
{
    struct contender k;
    pthread_t t;
    procimg_error_t r;
    int n;

    k.c = c;
    atomic_init(&k.stop, 0);
    k.busy = k.ok = k.other = k.layout_failed = 0;
    if (pthread_create(&t, NULL, contend, &k) != 0) {
        fprintf(stderr, "pthread_create failed\n");
        exit(2);
    }
    for (n = 0; n < 100; n++) {
        UNBUSY(procimg_wait_startop(c, 1000, NULL));
        EXPECT(PROCIMG_OK, r);
        UNBUSY(procimg_set_opdone(c, NULL));
        EXPECT(PROCIMG_OK, r);
    }
    atomic_store(&k.stop, 1);
    pthread_join(t, NULL);
    fprintf(stderr, "threads: %d busy, %d ok\n", k.busy, k.ok);
    CHECK(k.busy > 0);
    CHECK(k.other == 0);
    CHECK(k.layout_failed == 0);
}

static void sync_part(void)
{
    procimg_client_t *c = attach("c-sync", PROCIMG_ROLE_SYNCHRONOUS);
    procimg_client_t *second;
    size_t echo = find(c, "echo", 1), dio_out = find(c, "dio", 2);
    const procimg_submodule_entry_t *e = entry(c, echo);
    const procimg_submodule_entry_t *table;
    size_t count, len, all_len, bad = 999, data_len, n;
    const char *name;
    const uint8_t *in, *in_all;
    uint8_t *out, *out_all;
    uint8_t buf[17] = {0}, remote;
    uint64_t hash, last = 0;
    uint64_t written[256];
    int gaps = 0, echoed = 0, stale = 0, opfaults = 0;
    procimg_cycle_info_t info, done;
    procimg_submodule_ioxs_t st;
    procimg_event_t ev;
    int fd;
    struct pollfd p;

    /* The layout. */
    MUST(procimg_submodules(c, &table, &count));
    CHECK(count >= 4 && table == entry(c, 0));
    CHECK(e->input_address == 0 && e->input_length == 16);
    CHECK(e->output_address == 0 && e->output_length == 16);
    OK(procimg_device_name(c, e->device, &name));
    CHECK(strcmp(name, "echo") == 0);
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_device_name(c, 999, &name));
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_find_submodule(c, "echo", 7, 1, &n));
    OK(procimg_layout_hash(c, &hash));
    CHECK(hash != 0);
    null_arguments(c);

    /* Outside a window. */
    EXPECT(PROCIMG_ERR_NOT_IN_CYCLE, procimg_outputs(c, &out, &len));
    EXPECT(PROCIMG_ERR_NOT_IN_CYCLE, procimg_output(c, echo, &out, &len));
    EXPECT(PROCIMG_ERR_NOT_IN_CYCLE, procimg_set_output_status(c, echo, PROCIMG_IOXS_GOOD));
    EXPECT(PROCIMG_ERR_NOT_IN_CYCLE, procimg_set_opdone(c, NULL));
    CHECK(strstr(procimg_last_error(), "procimg_wait_startop") != NULL);

    /* Claims. */
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_claim(c, &bad, 1));
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_claim_device(c, "no-such-device"));
    OK(procimg_claim(c, NULL, 0));
    OK(procimg_claim_device(c, "echo"));
    second = attach("c-second", PROCIMG_ROLE_ASYNCHRONOUS);
    EXPECT(PROCIMG_ERR_REFUSED, procimg_claim(second, &echo, 1));
    CHECK(strstr(procimg_last_error(), "c-sync") != NULL);
    EXPECT(PROCIMG_ERR_WRONG_ROLE, procimg_wait_startop(second, 10, NULL));
    OK(procimg_detach(second));

    /* The descriptor wakes up for STARTOP. */
    OK(procimg_event_fd(c, &fd));
    p.fd = fd;
    p.events = POLLIN;
    p.revents = 0;
    CHECK(poll(&p, 1, 1000) == 1 && (p.revents & POLLIN));

    /* 300 cycles: a per-cycle pattern out through the echo device, back in a cycle later. */
    memset(written, 0, sizeof written);
    /* 300 cycles, more (up to 10 s) if a stalled device echoed too few of them. */
    for (n = 0; n < 300 || (echoed < 150 && n < 10000); n++) {
        uint64_t k;
        size_t i;
        MUST(procimg_wait_startop(c, 1000, &info));
        k = info.cycle_number;
        CHECK(k > last);
        if (last != 0 && k != last + 1)
            gaps++;
        last = k;
        CHECK(info.clock_ns >= info.cycle_start_ns);
        CHECK(info.since_cycle_start_ns == info.clock_ns - info.cycle_start_ns);
        CHECK(info.since_cycle_start_ns < 1000000000u);
        CHECK(info.cycle_count == (uint32_t)((k * 32u) & 0xffffu)); /* 31.25 us units, 1 ms */

        /* In place: the submodule's view lies inside the whole area, no copy. */
        MUST(procimg_inputs(c, &in_all, &all_len));
        MUST(procimg_input(c, echo, &in, &len));
        CHECK(len == 16 && in == in_all + e->input_offset && all_len >= 22);
        /* The echo shows a whole pattern of one of the last 32 cycles, never a torn one and
         * never one from the future. Before the first echo it shows the device's zeros; on a
         * loaded machine the simulated device may stall for a while and the inputs stay as
         * they were: both are counted, not failed. */
        OK(procimg_submodule_status(c, echo, &st));
        {
            int whole = 1, zero = 1;
            for (i = 0; i < 16; i++) {
                whole &= in[i] == (uint8_t)(in[0] + i);
                zero &= in[i] == 0;
            }
            if (whole && written[in[0]] != 0 && written[in[0]] < k &&
                k - written[in[0]] <= 32) {
                CHECK(st.input_remote == PROCIMG_IOXS_GOOD);
                echoed++;
            } else if (!whole && !zero) {
                fprintf(stderr, "cycle %llu: torn echo:", (unsigned long long)k);
                for (i = 0; i < 16; i++)
                    fprintf(stderr, " %02x", in[i]);
                fprintf(stderr, "\n");
                failures++;
            } else {
                stale++;
            }
        }

        /* Even cycles through the submodule's view, odd ones through the whole Q area. */
        if (n % 2 == 0) {
            MUST(procimg_output(c, echo, &out, &len));
            CHECK(len == 16);
        } else {
            MUST(procimg_outputs(c, &out_all, &all_len));
            MUST(procimg_output(c, echo, &out, &len));
            CHECK(out == out_all + e->output_offset && all_len >= 18);
        }
        for (i = 0; i < 16; i++)
            out[i] = (uint8_t)(k + i);
        written[(uint8_t)k] = k;

        /* The window's errors. */
        if (n == 150) {
            EXPECT(PROCIMG_ERR_LENGTH, procimg_data_write(c, 0, buf, 17, PROCIMG_IOXS_GOOD, NULL));
            EXPECT(PROCIMG_ERR_UNKNOWN_ADDRESS,
                   procimg_data_read(c, 9999, buf, 4, &data_len, PROCIMG_IOXS_GOOD, NULL));
            EXPECT(PROCIMG_ERR_NOT_CLAIMED,
                   procimg_data_write(c, 16, buf, 2, PROCIMG_IOXS_GOOD, &remote));
            EXPECT(PROCIMG_ERR_NOT_CLAIMED, procimg_output(c, dio_out, &out, &len));
            EXPECT(PROCIMG_ERR_INVALID_ARGUMENT,
                   procimg_data_read(c, 0, buf, 4, &data_len, 0x42, NULL));
            EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_output(c, 999, &out, &len));
            /* Access by address acts on the window: this cycle's inputs, its output sample. */
            OK(procimg_data_read(c, 2, buf, 4, &data_len, PROCIMG_IOXS_GOOD, &remote));
            CHECK(data_len == 14 && memcmp(buf, in + 2, 4) == 0);
            OK(procimg_data_write(c, 3, buf, 1, PROCIMG_IOXS_GOOD, &remote));
            CHECK(out[3] == buf[0]);
            out[3] = (uint8_t)(k + 3);
        }
        OK(procimg_set_opdone(c, &done));
        CHECK(done.cycle_number == k && done.since_cycle_start_ns >= info.since_cycle_start_ns);
        while (procimg_next_event(c, &ev) == PROCIMG_OK)
            opfaults += ev.kind == PROCIMG_EVENT_OPFAULT;
    }
    fprintf(stderr, "sync: %zu cycles, %d gaps, %d echoed, %d stale, %d OPFAULT\n", n, gaps,
            echoed, stale, opfaults);
    /* Gaps (cycles this client missed) and stale echoes tell how busy the machine was: they
     * are printed, not checked. The echo must come back whole at least once. */
    CHECK(echoed >= 1);
    EXPECT(PROCIMG_ERR_NOT_IN_CYCLE, procimg_output(c, echo, &out, &len));
    EXPECT(PROCIMG_ERR_NOT_IN_CYCLE, procimg_set_opdone(c, NULL));

    /* A second STARTOP drops the window still open, outputs unsent. */
    OK(procimg_wait_startop(c, 1000, NULL));
    OK(procimg_output(c, echo, &out, &len));
    OK(procimg_wait_startop(c, 1000, NULL));
    OK(procimg_set_output_status(c, echo, PROCIMG_IOXS_GOOD));
    OK(procimg_set_opdone(c, NULL));

    threads(c);
    OK(procimg_detach(c));
}

static void async_part(void)
{
    procimg_client_t *c = attach("c-async", PROCIMG_ROLE_ASYNCHRONOUS);
    size_t echo = find(c, "echo", 1);
    const procimg_submodule_entry_t *e = entry(c, echo);
    uint8_t a[16], b[16], buf[16], local, remote;
    size_t data_len, len, i;
    const uint8_t *in;
    uint8_t *out;
    uint32_t mode;
    procimg_submodule_ioxs_t st;
    double until;
    int seen;

    EXPECT(PROCIMG_ERR_WRONG_ROLE, procimg_wait_startop(c, 10, NULL));
    EXPECT(PROCIMG_ERR_WRONG_ROLE, procimg_set_opdone(c, NULL));
    EXPECT(PROCIMG_ERR_WRONG_ROLE, procimg_outputs(c, &out, &len));
    EXPECT(PROCIMG_ERR_WRONG_ROLE, procimg_output(c, echo, &out, &len));
    EXPECT(PROCIMG_ERR_NOT_CLAIMED, procimg_data_write(c, 0, a, 16, PROCIMG_IOXS_GOOD, NULL));
    EXPECT(PROCIMG_ERR_NO_IMAGE,
           procimg_read_cache(c, 0, buf, 16, &data_len, PROCIMG_IOXS_GOOD, NULL));
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_set_mode(c, 7));
    OK(procimg_mode(c, &mode));
    CHECK(mode == PROCIMG_MODE_OPERATE);
    MUST(procimg_claim_device(c, "echo"));

    /* data_write, then data_read until the echo device sent it back. */
    for (i = 0; i < 16; i++) {
        a[i] = (uint8_t)(0xa0 + i);
        b[i] = (uint8_t)(0x30 + 2 * i);
    }
    OK(procimg_data_write(c, 0, a, 16, PROCIMG_IOXS_GOOD, &remote));
    CHECK(remote == PROCIMG_IOXS_GOOD || remote == PROCIMG_IOXS_BAD);
    EXPECT(PROCIMG_ERR_LENGTH, procimg_data_write(c, 0, a, 17, PROCIMG_IOXS_GOOD, NULL));
    EXPECT(PROCIMG_ERR_LENGTH, procimg_data_write(c, 0, a, 0, PROCIMG_IOXS_GOOD, NULL));
    EXPECT(PROCIMG_ERR_UNKNOWN_ADDRESS, procimg_data_write(c, 100, a, 1, PROCIMG_IOXS_GOOD, NULL));
    EXPECT(PROCIMG_ERR_NOT_CLAIMED, procimg_data_write(c, 16, a, 2, PROCIMG_IOXS_GOOD, NULL));
    EXPECT(PROCIMG_ERR_UNKNOWN_ADDRESS,
           procimg_data_read(c, 999, buf, 4, &data_len, PROCIMG_IOXS_GOOD, NULL));
    EXPECT(PROCIMG_ERR_INVALID_ARGUMENT, procimg_data_write(c, 0, a, 16, 0x60, NULL));
    for (seen = 0, until = now_s() + 10.0; !seen && now_s() < until; sleep_ms(2)) {
        OK(procimg_data_read(c, 0, buf, 16, &data_len, PROCIMG_IOXS_GOOD, &remote));
        seen = memcmp(buf, a, 16) == 0;
    }
    CHECK(seen);
    CHECK(data_len == 16 && remote == PROCIMG_IOXS_GOOD);

    /* Slices: from I 2 the data is 14 bytes long; 4 of them fit. */
    memset(buf, 0, sizeof buf);
    OK(procimg_data_read(c, 2, buf, 4, &data_len, PROCIMG_IOXS_GOOD, NULL));
    CHECK(data_len == 14 && memcmp(buf, a + 2, 4) == 0 && buf[4] == 0);
    OK(procimg_data_read(c, 0, NULL, 0, &data_len, PROCIMG_IOXS_GOOD, NULL));
    CHECK(data_len == 16);

    /* The newest image in place, and the outputs as sent. */
    OK(procimg_input(c, echo, &in, &len));
    CHECK(len == 16 && memcmp(in, a, 16) == 0);
    OK(procimg_submodule_status(c, echo, &st));
    CHECK(st.input_remote == PROCIMG_IOXS_GOOD && st.output_local == PROCIMG_IOXS_GOOD);
    OK(procimg_output_data_read(c, 0, buf, 16, &data_len, &local, &remote));
    CHECK(data_len == 16 && memcmp(buf, a, 16) == 0 && local == PROCIMG_IOXS_GOOD);
    OK(procimg_output_data_read(c, 0, buf, 16, &data_len, NULL, NULL));
    (void)e;

    /* The caches: write, flush, refresh and read until it came back. */
    OK(procimg_write_cache(c, 0, b, 16, PROCIMG_IOXS_GOOD, &remote));
    OK(procimg_write_cache_flush(c));
    OK(procimg_write_cache_flush(c)); /* nothing left to send */
    for (seen = 0, until = now_s() + 10.0; !seen && now_s() < until; sleep_ms(2)) {
        OK(procimg_read_cache_refresh(c));
        OK(procimg_read_cache(c, 0, buf, 16, &data_len, PROCIMG_IOXS_GOOD, &remote));
        seen = memcmp(buf, b, 16) == 0;
    }
    CHECK(seen);
    CHECK(data_len == 16 && remote == PROCIMG_IOXS_GOOD);
    OK(procimg_release(c, &echo, 1));
    EXPECT(PROCIMG_ERR_NOT_CLAIMED, procimg_write_cache(c, 0, b, 16, PROCIMG_IOXS_GOOD, NULL));
    OK(procimg_detach(c));
}

/* Waits (polling the event descriptor) for MODE events until `target`; returns them. */
static int mode_events(procimg_client_t *c, uint32_t target, uint32_t *modes, int max)
{
    int n = 0, fd;
    double until = now_s() + 10.0;
    procimg_event_t ev;
    while (now_s() < until) {
        struct pollfd p;
        OK(procimg_event_fd(c, &fd));
        p.fd = fd;
        p.events = POLLIN;
        p.revents = 0;
        (void)poll(&p, 1, 50);
        while (procimg_next_event(c, &ev) == PROCIMG_OK) {
            if (ev.kind != PROCIMG_EVENT_MODE)
                continue;
            CHECK(ev.cycle == 0 && ev.generation == 0 && ev.submodule == 0);
            if (n < max)
                modes[n++] = ev.mode;
            if (ev.mode == target)
                return n;
        }
    }
    fprintf(stderr, "no MODE event for mode %u within 10 s (%d others)\n", target, n);
    failures++;
    return n;
}

static void modes_part(void)
{
    procimg_client_t *c = attach("c-modes", PROCIMG_ROLE_ASYNCHRONOUS);
    uint32_t modes[8], mode;
    int n;
    procimg_event_t ev;

    while (procimg_next_event(c, &ev) == PROCIMG_OK) {
    }
    EXPECT(PROCIMG_ERR_NO_EVENT, procimg_next_event(c, &ev));

    OK(procimg_set_mode(c, PROCIMG_MODE_OFFLINE));
    n = mode_events(c, PROCIMG_MODE_OFFLINE, modes, 8);
    CHECK(n == 2 && modes[0] == PROCIMG_MODE_CLEAR && modes[1] == PROCIMG_MODE_OFFLINE);
    OK(procimg_mode(c, &mode));
    CHECK(mode == PROCIMG_MODE_OFFLINE);

    OK(procimg_set_mode(c, PROCIMG_MODE_OPERATE));
    n = mode_events(c, PROCIMG_MODE_OPERATE, modes, 8);
    CHECK(n == 2 && modes[0] == PROCIMG_MODE_CLEAR && modes[1] == PROCIMG_MODE_OPERATE);
    OK(procimg_mode(c, &mode));
    CHECK(mode == PROCIMG_MODE_OPERATE);
    OK(procimg_detach(c));
}

int main(int argc, char **argv)
{
    const char *part = argc > 1 ? argv[1] : "";
    if (strcmp(part, "errors") == 0)
        errors();
    else if (strcmp(part, "sync") == 0)
        sync_part();
    else if (strcmp(part, "async") == 0)
        async_part();
    else if (strcmp(part, "modes") == 0)
        modes_part();
    else {
        fprintf(stderr, "usage: %s errors|sync|async|modes\n", argv[0]);
        return 2;
    }
    if (failures != 0) {
        fprintf(stderr, "%s: %d checks failed\n", part, failures);
        return 1;
    }
    printf("%s: all checks held\n", part);
    return 0;
}
