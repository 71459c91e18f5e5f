/* SPDX-License-Identifier: MIT OR Apache-2.0 */
/*
 * The server's mode around an IO-Base controller, through procimg's native API (procimg.h,
 * in the same library); shared by pnio_easy.c, pnio_easy.cpp and pnio_isochronous.c.
 * Header-only: static functions, valid C11 and C++17.
 *
 * Why: a procimgd is shared. Other programs (native_cycle, `procimg io`) use it after an
 * IO-Base program, and in OFFLINE they see no data exchanged. PNIO_controller_open with
 * PNIO_CEP_MODE_CTRL takes the server to OFFLINE, the manual's flow ends there, and
 * PNIO_controller_close leaves the mode as it is. The IO-Base API can neither tell the mode
 * before open nor change it after close, so, outside the manual's flow, a program reads the
 * server's mode before it opens and sets it again after it closed:
 *
 *   const char *instance = cp_instance();
 *   uint32_t before = 0;
 *   int known = server_mode("my_program", instance, &before);
 *   ... PNIO_controller_open ... PNIO_controller_close ...
 *   if (known && !restore_mode("my_program", instance, before)) { rc = 1; }
 *
 * Setting it after close keeps the manual's flow as it is and also works when a step failed
 * half-way. When it cannot, restore_mode says which mode it left the server in and how to
 * get the old one back. `program` starts those messages ("my_program: instance ...") and
 * names the short-lived client ("my_program (server mode)", shown by `procimg status`).
 *
 * It waits with nanosleep: a C program defines _POSIX_C_SOURCE (200809L) before its first
 * #include, as the examples do.
 */
#ifndef PROCIMG_EXAMPLES_SERVER_MODE_H
#define PROCIMG_EXAMPLES_SERVER_MODE_H

#include "procimg.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

/* The procimgd instance CP 1 names, found as PNIO_controller_open finds it. */
static inline const char *cp_instance(void) {
    const char *name = getenv("PROCIMG_CP1");
    if (name == NULL || name[0] == '\0') {
        name = getenv("PROCIMG_INSTANCE");
    }
    return name == NULL || name[0] == '\0' ? "procimg" : name;
}

static inline const char *mode_name(uint32_t mode, int lower) {
    switch (mode) {
    case PROCIMG_MODE_OFFLINE:
        return lower ? "offline" : "OFFLINE";
    case PROCIMG_MODE_CLEAR:
        return lower ? "clear" : "CLEAR";
    case PROCIMG_MODE_OPERATE:
        return lower ? "operate" : "OPERATE";
    default:
        return "unknown";
    }
}

/* A short-lived client that takes no part in the cycle and claims nothing, named
 * "<program> (server mode)". */
static inline procimg_error_t attach_observer(const char *program, const char *instance,
                                              procimg_client_t **c) {
    char name[128];
    procimg_attach_options_t opts;
    snprintf(name, sizeof name, "%s (server mode)", program);
    procimg_attach_options_init(&opts);
    opts.role = PROCIMG_ROLE_ASYNCHRONOUS;
    return procimg_attach(instance, name, &opts, c);
}

/* The server's mode now; 0 when there is no server to ask. */
static inline int server_mode(const char *program, const char *instance, uint32_t *mode) {
    procimg_client_t *c = NULL;
    procimg_error_t r;
    if (attach_observer(program, instance, &c) != PROCIMG_OK) {
        return 0;
    }
    r = procimg_mode(c, mode);
    procimg_detach(c);
    return r == PROCIMG_OK;
}

/* Gives the server back `mode` and waits (up to 10 s) until it is there; says what it did.
 * When it cannot, it says which mode the server is left in and how to set it. */
static inline int restore_mode(const char *program, const char *instance, uint32_t mode) {
    procimg_client_t *c = NULL;
    uint32_t now = mode;
    const char *left = "an unknown mode", *why = "";
    procimg_error_t r;
    int i, changed = 0;

    r = attach_observer(program, instance, &c);
    if (r == PROCIMG_OK && (r = procimg_mode(c, &now)) == PROCIMG_OK && now != mode) {
        changed = 1;
        r = procimg_set_mode(c, mode);
        /* The server steps there by itself (OFFLINE -> CLEAR -> OPERATE). */
        for (i = 0; r == PROCIMG_OK && now != mode && i < 1000; i++) {
            struct timespec ten_ms = {0, 10L * 1000 * 1000};
            nanosleep(&ten_ms, NULL);
            r = procimg_mode(c, &now);
        }
    }
    if (r == PROCIMG_OK && now == mode) {
        if (changed) {
            printf("instance \"%s\" back in mode %s, as before the controller opened\n",
                   instance, mode_name(mode, 0));
        }
    } else {
        if (r == PROCIMG_OK) {
            left = mode_name(now, 0);
            why = "the change was not confirmed within 10 s";
        } else {
            why = procimg_last_error();
        }
        fprintf(stderr,
                "%s: instance \"%s\" was in mode %s before the controller opened and is left "
                "in %s%s: %s\n"
                "  `procimg mode %s --instance %s` sets it back (`procimg status` shows it)\n",
                program, instance, mode_name(mode, 0), r == PROCIMG_OK ? "mode " : "", left,
                why, mode_name(mode, 1), instance);
    }
    if (c != NULL) {
        procimg_detach(c);
    }
    return r == PROCIMG_OK && now == mode;
}

#endif /* PROCIMG_EXAMPLES_SERVER_MODE_H */
