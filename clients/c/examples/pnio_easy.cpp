// SPDX-License-Identifier: MIT OR Apache-2.0
//
// PnioEasy in C++17: the IO-Base manual's controller flow against procimgd, as pnio_easy.c,
// with the controller in a small RAII class (closed in its destructor).
//
//   c++ -std=c++17 pnio_easy.cpp -I clients/c/include -I shm-layout/include -lprocimg
//   procimgd --demo &
//   ./a.out [exchanges]
//
// CP 1 is the instance in $PROCIMG_CP1, else $PROCIMG_INSTANCE, else "procimg". Exits 0
// when every step worked. As pnio_easy.c, it gives the server back the mode it had before
// the controller opened (the manual's flow leaves it OFFLINE, where other programs see no
// data), through procimg.h after the controller is closed (see server_mode.h).
#include "pniousrx.h"
#include "procimg.h"
#include "pnio_error.hpp"
#include "server_mode.h"

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

namespace {

std::atomic<int> mode_reports{0};
std::atomic<int> current_mode{PNIO_MODE_OFFLINE};

// Callbacks run on threads of the library and must not throw.
extern "C" void on_mode(PNIO_CBE_PRM *p) {
    current_mode = static_cast<int>(p->ModeInd.Mode);
    ++mode_reports;
}

extern "C" void on_record(PNIO_CBE_PRM *p) {
    std::printf("record job confirmed: event %d\n", static_cast<int>(p->CbeType));
}

PNIO_ADDR logical(PNIO_IO_TYPE io, PNIO_UINT32 address) {
    PNIO_ADDR a{};
    a.AddrType = PNIO_ADDR_LOG;
    a.IODataType = io;
    a.u.Addr = address;
    return a;
}

bool wait_mode_reports(int reports) {
    for (int i = 0; i < 1000 && mode_reports < reports; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return mode_reports >= reports;
}

class Controller {
  public:
    explicit Controller(PNIO_UINT32 cp) {
        check("PNIO_controller_open",
              PNIO_controller_open(cp, PNIO_CEP_MODE_CTRL, on_record, on_record, nullptr,
                                   &handle_));
    }
    ~Controller() {
        PNIO_controller_close(handle_);
    }
    Controller(const Controller &) = delete;
    Controller &operator=(const Controller &) = delete;

    PNIO_UINT32 handle() const { return handle_; }

    // Asks for a mode and waits until MODE_IND reported it (`steps` reports).
    void go(PNIO_MODE_TYPE mode, int steps) {
        int before = mode_reports;
        check("PNIO_set_mode", PNIO_set_mode(handle_, mode));
        if (!wait_mode_reports(before + steps) || current_mode != static_cast<int>(mode)) {
            throw std::runtime_error("mode " + std::to_string(mode) + " was not reported");
        }
    }

  private:
    PNIO_UINT32 handle_ = 0;
};

// ---- The manual's flow ----------------------------------------------------------------------

int pnio_easy(long exchanges) {
    try {
        Controller ctl(1);
        std::printf("controller open, handle %u, mode OFFLINE\n", ctl.handle());
        check("PNIO_register_cbf(MODE_IND)",
              PNIO_register_cbf(ctl.handle(), PNIO_CBE_MODE_IND, on_mode));
        ctl.go(PNIO_MODE_OPERATE, 2); // CLEAR, then OPERATE
        std::printf("mode OPERATE\n");

        PNIO_ADDR out = logical(PNIO_IO_OUT, 0), in = logical(PNIO_IO_IN, 0);
        std::array<PNIO_UINT8, 16> q{}, i{};
        long good = 0;
        bool echoed = false;
        for (long round = 0; round < 2000 && good < exchanges; ++round) {
            for (std::size_t k = 0; k < q.size(); ++k) {
                q[k] = static_cast<PNIO_UINT8>(round * 3 + static_cast<long>(k));
            }
            PNIO_IOXS out_remote = PNIO_S_BAD, in_remote = PNIO_S_BAD;
            PNIO_UINT32 r = PNIO_data_write(ctl.handle(), &out, q.size(), q.data(), PNIO_S_GOOD,
                                            &out_remote);
            if (r != PNIO_ERR_NO_CONNECTION) {
                check("PNIO_data_write", r);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            PNIO_UINT32 len = 0;
            r = PNIO_data_read(ctl.handle(), &in, i.size(), &len, i.data(), PNIO_S_GOOD,
                               &in_remote);
            if (r == PNIO_ERR_NO_CONNECTION) {
                continue; // still connecting after OPERATE
            }
            check("PNIO_data_read", r);
            if (!echoed && len == i.size() && in_remote == PNIO_S_GOOD && i == q) {
                std::printf("inputs echo the outputs after %ld rounds\n", round);
                echoed = true;
            }
            if (echoed && in_remote == PNIO_S_GOOD && out_remote == PNIO_S_GOOD) {
                ++good;
            }
        }
        std::printf("%ld good exchanges after the first echo\n", good);
        if (!echoed || good < exchanges) {
            throw std::runtime_error("the inputs did not echo the outputs");
        }
        ctl.go(PNIO_MODE_OFFLINE, 2); // CLEAR, then OFFLINE
        std::printf("mode OFFLINE\n");
    } catch (const std::exception &e) {
        std::fprintf(stderr, "pnio_easy_cpp: %s\n", e.what());
        return 1;
    }
    std::printf("controller closed\n");
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    long exchanges = argc > 1 ? std::strtol(argv[1], nullptr, 10) : 100;
    if (exchanges <= 0) {
        std::fprintf(stderr, "usage: %s [exchanges]\n", argv[0]);
        return 2;
    }
    const char *instance = cp_instance();
    // Without a server this finds nothing, and PNIO_controller_open says what to do.
    std::uint32_t before = 0;
    const bool known = server_mode("pnio_easy_cpp", instance, &before) != 0;
    int rc = pnio_easy(exchanges); // the controller is closed when it returns
    if (known && !restore_mode("pnio_easy_cpp", instance, before)) {
        rc = 1;
    }
    return rc;
}
