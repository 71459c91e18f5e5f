// SPDX-License-Identifier: MIT OR Apache-2.0
//
// The exception the C++ examples (pnio_easy.cpp, pnio_dev_easy.cpp) throw for a failed
// IO-Base call, and `check`, which throws it. Header-only, C++17.
#ifndef PROCIMG_EXAMPLES_PNIO_ERROR_HPP
#define PROCIMG_EXAMPLES_PNIO_ERROR_HPP

#include "pniobase.h"
#include "pnioerrx.h"
#include "procimg.h"

#include <cstdio>
#include <stdexcept>
#include <string>

// A failed call: its code, and the library's text for this thread, which names the code
// (PNIO_ERR_...) and says what to do (procimg_last_error() serves both APIs).
struct PnioError : std::runtime_error {
    PnioError(const std::string &what, PNIO_UINT32 code)
        : std::runtime_error(what + " failed with " + hex(code) + "\n  " + procimg_last_error()) {}

    static std::string hex(PNIO_UINT32 code) {
        char text[16];
        std::snprintf(text, sizeof text, "0x%03x", static_cast<unsigned>(code));
        return text;
    }
};

// Throws PnioError for `what` unless `code` is PNIO_OK.
inline void check(const char *what, PNIO_UINT32 code) {
    if (code != PNIO_OK) {
        throw PnioError(what, code);
    }
}

#endif
