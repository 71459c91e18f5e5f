// SPDX-License-Identifier: MIT OR Apache-2.0
//
// DevEasy in C++17: the IO-Base manual's IO device flow against procimgd in the device role,
// as pnio_dev_easy.c (open, API 0, plug the DAP and an IO module, start, the PLC's AR
// through the indications, cyclic data echoing the PLC's outputs into the inputs, the
// parameter record in REC_WRITE/REC_READ, a process alarm, a channel diagnosis appearing
// and disappearing, stop, pull, close), with the device in a small RAII class: its
// destructor stops it if it still runs, pulls what it plugged and closes it.
//
//   c++ -std=c++17 pnio_dev_easy.cpp $(pkg-config --cflags --libs procimg)
//   procimgd --demo-device-program &
//   ./a.out [seconds [vendor_id device_id]]
//
// CP 1 is the instance in $PROCIMG_CP1, else $PROCIMG_INSTANCE, else "procimg"; VendorID
// and DeviceID are the demo station's 0x0493 and 0x0100 unless $PNIO_VENDOR_ID and
// $PNIO_DEVICE_ID or the command line say otherwise. Prints each step; exits 0 when all of
// them happened, in this order.
#include "pniousrd.h"
#include "procimg.h"
#include "pnio_error.hpp"

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace {

constexpr PNIO_UINT32 kCpIndex = 1;
constexpr unsigned long kDemoVendorId = 0x0493;
constexpr unsigned long kDemoDeviceId = 0x0100;
// The program defines its station (as pnio_dev_easy.c says): the DAP and an IO module as
// the station's GSDML file describes them (the demo's module 0x10: 8 bytes in and out).
constexpr PNIO_UINT32 kDapModIdent = 0x1, kDapSubIdent = 0x1;
constexpr PNIO_UINT32 kIoModIdent = 0x10, kIoSubIdent = 0x1;
constexpr PNIO_UINT32 kIoSlot = 1, kIoSubslot = 1;
constexpr std::size_t kIoLen = 8;
constexpr PNIO_UINT32 kParamIndex = 1;
constexpr std::size_t kParamLen = 4;
constexpr PNIO_UINT32 kProcessAlarm = 1, kDiagAppears = 2, kDiagDisappears = 3;
constexpr PNIO_UINT16 kDiagTag = 1;
constexpr auto kWait = std::chrono::seconds(30);

enum Phase { kNone, kChecked, kInfo, kPrmEnd, kInData, kEnded };

// What the callbacks saw. They run on a library thread: they note it here and wake the main
// thread, which makes the calls the manual allows outside callbacks only.
struct Seen {
    std::mutex mu;
    std::condition_variable cv;
    int confs = 0;
    PNIO_UINT32 conf_error = PNIO_OK;
    int phase = kNone;
    int out_of_order = 0;
    PNIO_UINT16 ar = 0, sk = 0;
    bool stopped = false;
    bool offline_before_stopped = false;
    PNIO_UINT32 stopped_code = PNIO_OK;
    int rec_writes = 0, rec_reads = 0;
    std::array<PNIO_UINT8, kParamLen> param{};
    std::array<int, 4> done{};
    std::array<PNIO_UINT32, 4> done_status{};
    std::array<PNIO_UINT8, kIoLen> q{};
    PNIO_IOXS q_iops = PNIO_S_BAD;
} seen;

// Waits until `done` holds (under seen.mu).
void wait_for(const char *what, const std::function<bool()> &done) {
    std::unique_lock<std::mutex> lock(seen.mu);
    if (!seen.cv.wait_for(lock, kWait, done)) {
        throw std::runtime_error(std::string(what) + " did not come");
    }
}

void phase(int p, const char *what) {
    // Each indication must follow the one before it (a new AR starts over).
    if (p != kChecked && seen.phase != p - 1) {
        ++seen.out_of_order;
        std::printf("%s out of order\n", what);
    }
    seen.phase = p;
    seen.cv.notify_all();
}

PNIO_DEV_ADDR geo(PNIO_UINT32 slot, PNIO_UINT32 subslot) {
    PNIO_DEV_ADDR a{};
    a.AddrType = PNIO_ADDR_GEO;
    a.IODataType = PNIO_IO_IN;
    a.u.Geo.Slot = slot;
    a.u.Geo.Subslot = subslot;
    return a;
}

bool is_param(PNIO_UINT32 api, const PNIO_DEV_ADDR *a, PNIO_UINT32 index) {
    return api == 0 && a != nullptr && a->u.Geo.Slot == kIoSlot && a->u.Geo.Subslot == kIoSubslot &&
           index == kParamIndex;
}

// ---- Callbacks (they must not throw) ----------------------------------------------------

extern "C" PNIO_IOXS data_write(PNIO_UINT32, PNIO_DEV_ADDR *, PNIO_UINT32 len, PNIO_UINT8 *buf,
                                PNIO_IOXS) {
    std::lock_guard<std::mutex> lock(seen.mu);
    // The inputs: the outputs last read, back to the PLC.
    std::memcpy(buf, seen.q.data(), len < kIoLen ? len : kIoLen);
    return PNIO_S_GOOD;
}

extern "C" PNIO_IOXS data_read(PNIO_UINT32, PNIO_DEV_ADDR *, PNIO_UINT32 len, PNIO_UINT8 *buf,
                               PNIO_IOXS iops) {
    std::lock_guard<std::mutex> lock(seen.mu);
    std::memcpy(seen.q.data(), buf, len < kIoLen ? len : kIoLen);
    seen.q_iops = iops;
    return PNIO_S_GOOD;
}

extern "C" void rec_read(PNIO_UINT32, PNIO_UINT32 api, PNIO_UINT16, PNIO_UINT16, PNIO_UINT32,
                         PNIO_DEV_ADDR *addr, PNIO_UINT32 index, PNIO_UINT32 *len,
                         PNIO_UINT8 *buf, PNIO_ERR_STAT *st) {
    std::lock_guard<std::mutex> lock(seen.mu);
    *st = PNIO_ERR_STAT{};
    if (is_param(api, addr, index)) {
        PNIO_UINT32 n = *len < kParamLen ? *len : static_cast<PNIO_UINT32>(kParamLen);
        std::memcpy(buf, seen.param.data(), n);
        *len = n;
        ++seen.rec_reads;
        std::printf("REC_READ: record %u given back\n", static_cast<unsigned>(index));
    } else {
        *len = 0;
        st->ErrCode = 0xDE; // IODReadRes
        st->ErrDecode = 0x80; // PNIORW
        st->ErrCode1 = 0xB0; // invalid index
        std::printf("REC_READ: record %u refused\n", static_cast<unsigned>(index));
    }
}

extern "C" void rec_write(PNIO_UINT32, PNIO_UINT32 api, PNIO_UINT16, PNIO_UINT16, PNIO_UINT32,
                          PNIO_DEV_ADDR *addr, PNIO_UINT32 index, PNIO_UINT32 *len,
                          PNIO_UINT8 *buf, PNIO_ERR_STAT *st) {
    std::lock_guard<std::mutex> lock(seen.mu);
    *st = PNIO_ERR_STAT{};
    if (!is_param(api, addr, index) || *len != kParamLen) {
        st->ErrCode = 0xDF; // IODWriteRes
        st->ErrDecode = 0x80;
        st->ErrCode1 = is_param(api, addr, index) ? 0xB1 : 0xB0; // length, index
        std::printf("REC_WRITE: record %u refused\n", static_cast<unsigned>(index));
        return;
    }
    std::memcpy(seen.param.data(), buf, kParamLen);
    ++seen.rec_writes;
    std::printf("REC_WRITE: record %u = %02x %02x %02x %02x kept\n", static_cast<unsigned>(index),
                buf[0], buf[1], buf[2], buf[3]);
}

extern "C" void req_done(PNIO_UINT32, PNIO_UINT32 user, PNIO_UINT32 status, PNIO_ERR_STAT *) {
    std::lock_guard<std::mutex> lock(seen.mu);
    if (user < seen.done.size()) {
        ++seen.done[user];
        seen.done_status[user] = status;
    }
    seen.cv.notify_all();
}

// Called only where the PLC expects other ident numbers: what is plugged is the right one.
extern "C" void check_ind(PNIO_UINT32, PNIO_UINT32, PNIO_UINT16, PNIO_UINT16, PNIO_DEV_ADDR *,
                          PNIO_UINT32 *, PNIO_UINT16 *mod_state, PNIO_UINT32 *,
                          PNIO_UINT16 *sub_state) {
    *mod_state = PNIO_MOD_STATE_PROPER_MODULE;
    *sub_state = PNIO_SUB_CHECK_PROPER_SUBMODULE;
}

extern "C" void ar_check_ind(PNIO_UINT32, PNIO_UINT32, PNIO_UINT16, PNIO_UUID_TYPE, PNIO_UINT32,
                             PNIO_UUID_TYPE, PNIO_UINT16 name_len, PNIO_UINT8 *name,
                             PNIO_AR_TYPE *ar) {
    std::lock_guard<std::mutex> lock(seen.mu);
    seen.ar = ar->ArNumber;
    seen.sk = ar->SessionKey;
    std::printf("AR_CHECK_IND: AR %u, session key %u, from \"%.*s\"\n",
                static_cast<unsigned>(ar->ArNumber), static_cast<unsigned>(ar->SessionKey),
                static_cast<int>(name_len), reinterpret_cast<const char *>(name));
    phase(kChecked, "AR_CHECK_IND");
}

extern "C" void ar_info_ind(PNIO_UINT32, PNIO_UINT16 ar, PNIO_UINT16, PNIO_AR_TYPE *p) {
    std::lock_guard<std::mutex> lock(seen.mu);
    std::printf("AR_INFO_IND: AR %u, %u IOCRs, %u modules\n", static_cast<unsigned>(ar),
                static_cast<unsigned>(p->NumOfIocr), static_cast<unsigned>(p->NumOfMod));
    phase(kInfo, "AR_INFO_IND");
}

extern "C" void prm_end_ind(PNIO_UINT32, PNIO_UINT16 ar, PNIO_UINT16, PNIO_UINT32, PNIO_UINT16,
                            PNIO_UINT16 subslot) {
    std::lock_guard<std::mutex> lock(seen.mu);
    std::printf("PRM_END_IND: AR %u, subslot %u\n", static_cast<unsigned>(ar),
                static_cast<unsigned>(subslot));
    if (subslot == 0) {
        phase(kPrmEnd, "PRM_END_IND");
    }
}

extern "C" void ar_indata_ind(PNIO_UINT32, PNIO_UINT16 ar, PNIO_UINT16) {
    std::lock_guard<std::mutex> lock(seen.mu);
    std::printf("AR_INDATA_IND: AR %u in data exchange\n", static_cast<unsigned>(ar));
    phase(kInData, "AR_INDATA_IND");
}

void ar_end(const char *what, PNIO_UINT16 ar, PNIO_AR_REASON reason) {
    std::lock_guard<std::mutex> lock(seen.mu);
    std::printf("%s: AR %u, reason %d\n", what, static_cast<unsigned>(ar), static_cast<int>(reason));
    seen.phase = kEnded;
    seen.cv.notify_all();
}

extern "C" void ar_abort_ind(PNIO_UINT32, PNIO_UINT16 ar, PNIO_UINT16, PNIO_AR_REASON r) {
    ar_end("AR_ABORT_IND", ar, r);
}

extern "C" void ar_offline_ind(PNIO_UINT32, PNIO_UINT16 ar, PNIO_UINT16, PNIO_AR_REASON r) {
    ar_end("AR_OFFLINE_IND", ar, r);
    std::lock_guard<std::mutex> lock(seen.mu);
    seen.offline_before_stopped = !seen.stopped;
}

extern "C" void apdu_status_ind(PNIO_UINT32, PNIO_UINT16, PNIO_UINT16, PNIO_APDU_STATUS_IND st) {
    std::printf("APDU_STATUS_IND: PLC %s\n", (st & PNIO_EVENT_APDU_STATUS_RUN) ? "RUN" : "STOP");
}

extern "C" void cp_stop_req(PNIO_UINT32) {
    std::printf("CP_STOP_REQ: the device should close\n");
}

extern "C" void device_stopped(PNIO_UINT32, PNIO_UINT32 code) {
    std::lock_guard<std::mutex> lock(seen.mu);
    seen.stopped = true;
    seen.stopped_code = code;
    seen.cv.notify_all();
}

extern "C" void pull_plug_conf(PNIO_UINT32, PNIO_UINT32, PNIO_DEV_ACTION, PNIO_DEV_ADDR *,
                               PNIO_UINT32 error) {
    std::lock_guard<std::mutex> lock(seen.mu);
    ++seen.confs;
    if (error != PNIO_OK && seen.conf_error == PNIO_OK) {
        seen.conf_error = error;
    }
    seen.cv.notify_all();
}

PNIO_CBF_FUNCTIONS callbacks() {
    PNIO_CBF_FUNCTIONS c{};
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
    c.cbf_apdu_status_ind = apdu_status_ind;
    c.cbf_prm_end_ind = prm_end_ind;
    c.pnio_cbf_cp_stop_req = cp_stop_req;
    c.pnio_cbf_device_stopped = device_stopped;
    c.cbf_pull_plug_conf = pull_plug_conf; // the LED callbacks are optional
    return c;
}

// ---- The device --------------------------------------------------------------------------

class Device {
  public:
    Device(PNIO_UINT16 vendor, PNIO_UINT16 device) : cbf_(callbacks()) {
        PNIO_ANNOTATION ann{};
        std::strcpy(reinterpret_cast<char *>(ann.deviceType), "procimg device");
        std::strcpy(reinterpret_cast<char *>(ann.orderId), "PROCIMG-DEV");
        ann.hwRevision = 1;
        ann.swRevisionPrefix = 'V';
        ann.swRevision2 = 1;
        // Until the station has an IP address: PNIO_ERR_CONFIG_IN_UPDATE, open again.
        PNIO_UINT32 r = PNIO_ERR_CONFIG_IN_UPDATE;
        for (int tries = 0; r == PNIO_ERR_CONFIG_IN_UPDATE && tries < 30; ++tries) {
            if (tries > 0) {
                std::this_thread::sleep_for(std::chrono::seconds(1));
            }
            r = PNIO_device_open(kCpIndex, PNIO_CEP_MODE_CTRL, vendor, device, 1, 1, &ann, &cbf_,
                                 &h_);
        }
        check("PNIO_device_open", r);
        std::printf("device open: handle %u, VendorID 0x%04x, DeviceID 0x%04x\n",
                    static_cast<unsigned>(h_), vendor, device);
    }

    Device(const Device &) = delete;
    Device &operator=(const Device &) = delete;

    ~Device() {
        if (started_) {
            try {
                stop();
            } catch (const std::exception &e) {
                std::fprintf(stderr, "pnio_dev_easy: %s\n", e.what());
            }
        }
        // The modules in reverse order, the IO module before the DAP.
        while (plugs_ > 0) {
            int confs = count_confs();
            if (PNIO_mod_pull(h_, 0, &plugged_[--plugs_]) == PNIO_OK) {
                try {
                    wait_for("PULL_PLUG_CONF", [&] { return seen.confs > confs; });
                } catch (const std::exception &e) {
                    std::fprintf(stderr, "pnio_dev_easy: %s\n", e.what());
                }
            }
        }
        PNIO_api_remove(h_, 0);
        PNIO_UINT32 r = PNIO_device_close(h_);
        if (r != PNIO_OK) {
            std::fprintf(stderr, "pnio_dev_easy: PNIO_device_close failed with 0x%03x\n",
                         static_cast<unsigned>(r));
        }
        std::printf("device closed\n");
    }

    PNIO_UINT32 handle() const { return h_; }

    // Plugs a module and its submodule, each confirmed; pulled again by the destructor.
    void plug(PNIO_DEV_ADDR *a, PNIO_UINT32 mod, PNIO_UINT32 sub, PNIO_PLUG_IM0_BITS im0,
              const char *what) {
        int confs = count_confs();
        check("PNIO_mod_plug", PNIO_mod_plug(h_, 0, a, mod));
        plugged_[plugs_++] = *a;
        wait_for("PULL_PLUG_CONF", [&] { return seen.confs > confs; });
        check("PNIO_sub_plug_ext_IM", PNIO_sub_plug_ext_IM(h_, 0, a, sub, PNIO_ALARM_TYPE_PLUG, im0));
        wait_for("PULL_PLUG_CONF", [&] { return seen.confs > confs + 1; });
        check("plugging (PULL_PLUG_CONF)", seen.conf_error);
        std::printf("plugged %s: slot %u subslot %u, module 0x%x submodule 0x%x\n", what,
                    static_cast<unsigned>(a->u.Geo.Slot), static_cast<unsigned>(a->u.Geo.Subslot),
                    static_cast<unsigned>(mod), static_cast<unsigned>(sub));
    }

    void start() {
        check("PNIO_device_start", PNIO_device_start(h_));
        started_ = true;
        std::printf("device started\n");
    }

    // The AR_OFFLINE_IND, then DEVICE_STOPPED.
    void stop() {
        started_ = false;
        check("PNIO_device_stop", PNIO_device_stop(h_));
        wait_for("DEVICE_STOPPED", [] { return seen.stopped; });
        check("PNIO_device_stop (DEVICE_STOPPED)", seen.stopped_code);
        std::printf("device stopped%s\n",
                    seen.offline_before_stopped ? " (AR_OFFLINE_IND first)" : "");
    }

  private:
    static int count_confs() {
        std::lock_guard<std::mutex> lock(seen.mu);
        return seen.confs;
    }

    PNIO_CBF_FUNCTIONS cbf_;
    PNIO_UINT32 h_ = 0;
    bool started_ = false;
    std::array<PNIO_DEV_ADDR, 2> plugged_{};
    std::size_t plugs_ = 0;
};

// Waits for the alarm's REQ_DONE.
void acknowledged(const char *what, PNIO_UINT32 r, PNIO_UINT32 handle) {
    check(what, r);
    wait_for("REQ_DONE", [&] { return seen.done[handle] > 0; });
    check("the alarm (REQ_DONE)", seen.done_status[handle]);
}

void put16(PNIO_UINT8 *p, PNIO_UINT16 v) {
    p[0] = static_cast<PNIO_UINT8>(v >> 8);
    p[1] = static_cast<PNIO_UINT8>(v);
}

void dev_easy(double seconds, PNIO_UINT16 vendor, PNIO_UINT16 device_id) {
    Device device(vendor, device_id);
    const PNIO_UINT32 h = device.handle();
    PNIO_DEV_ADDR dap = geo(0, 1), io = geo(kIoSlot, kIoSubslot);

    check("PNIO_api_add", PNIO_api_add(h, 0, kIoSlot, 1));
    device.plug(&dap, kDapModIdent, kDapSubIdent, PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV,
                "the DAP");
    device.plug(&io, kIoModIdent, kIoSubIdent, PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MODULE,
                "the IO module");
    device.start();

    // The AR: parameters, first IO data, application ready, data exchange.
    wait_for("AR_CHECK_IND .. PRM_END_IND", [] { return seen.phase >= kPrmEnd; });
    // The manual's steps 14 and 15: the I data written now is what the PLC gets with the
    // ApplicationReady.
    check("PNIO_initiate_data_write", PNIO_initiate_data_write(h));
    check("PNIO_initiate_data_read", PNIO_initiate_data_read(h));
    PNIO_UINT16 ar, sk;
    {
        std::lock_guard<std::mutex> lock(seen.mu);
        ar = seen.ar;
        sk = seen.sk;
    }
    PNIO_APPL_READY_LIST_TYPE ready{};
    ready.ap_list.Flink = ready.ap_list.Blink = nullptr; // all submodules are ready
    // Said before the call: AR_INDATA_IND may come on the library thread before it returns.
    std::printf("application ready for AR %u\n", static_cast<unsigned>(ar));
    check("PNIO_set_appl_state_ready", PNIO_set_appl_state_ready(h, ar, sk, &ready));
    wait_for("AR_INDATA_IND", [] { return seen.phase >= kInData; });

    // Cyclic data: the outputs come back as inputs; the PLC adds one.
    long rounds = 0, trips = 0;
    std::array<PNIO_UINT8, kIoLen> last{};
    int first = -1;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        check("PNIO_initiate_data_read", PNIO_initiate_data_read(h));
        check("PNIO_initiate_data_write", PNIO_initiate_data_write(h));
        ++rounds;
        std::array<PNIO_UINT8, kIoLen> q;
        PNIO_IOXS iops;
        {
            std::lock_guard<std::mutex> lock(seen.mu);
            q = seen.q;
            iops = seen.q_iops;
        }
        if (iops == PNIO_S_GOOD && q != last) {
            bool plus_one = true;
            for (std::size_t k = 0; k < kIoLen; ++k) {
                plus_one = plus_one && q[k] == static_cast<PNIO_UINT8>(last[k] + 1);
            }
            trips += plus_one;
            if (first < 0) {
                first = q[0];
            }
            last = q;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    std::printf("cyclic data: %ld rounds, %ld round trips through the PLC (outputs 0x%02x .. "
                "0x%02x)\n",
                rounds, trips, first < 0 ? 0 : first, last[0]);
    if (trips == 0) {
        throw std::runtime_error("the PLC's outputs never came back as the inputs + 1");
    }

    // A process alarm.
    std::array<PNIO_UINT8, 4> alarm_data{0x12, 0x34, 0x56, 0x78};
    acknowledged("PNIO_process_alarm_send",
                 PNIO_process_alarm_send(h, 0, ar, sk, &io, alarm_data.data(), alarm_data.size(),
                                         0x0001, kProcessAlarm),
                 kProcessAlarm);
    std::printf("process alarm acknowledged (REQ_DONE, handle %u)\n",
                static_cast<unsigned>(kProcessAlarm));

    // A channel diagnosis: stored, then its alarm; removed, then its alarm. The alarm data
    // (UserStructIdent 0x8000): ChannelNumber, ChannelProperties, ChannelErrorType.
    const PNIO_UINT16 channel = 0x8000; // the whole submodule
    const PNIO_UINT16 error = PNIO_DIAG_CHAN_ERROR_OVERTEMPERATURE;
    std::array<PNIO_UINT8, 6> diag{};
    PNIO_UINT16 prop = PNIO_build_channel_properties(h, PNIO_DIAG_CHANPROP_TYPE_SUBMOD,
                                                     PNIO_DIAG_CHAN_SPEC_ERROR_APPEARS,
                                                     PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE);
    check("PNIO_diag_channel_add", PNIO_diag_channel_add(h, 0, &io, channel, prop, error, kDiagTag));
    put16(&diag[0], channel);
    put16(&diag[2], prop);
    put16(&diag[4], error);
    acknowledged("PNIO_diag_alarm_send(APPEARS)",
                 PNIO_diag_alarm_send(h, 0, ar, sk, PNIO_STATE_ALARM_APPEARS, &io, diag.data(),
                                      diag.size(), PNIO_USR_STRUC_ID_CHANNEL_DIAG, kDiagAppears),
                 kDiagAppears);
    std::printf("channel diagnosis added, diagnosis alarm (appears) acknowledged\n");
    prop = PNIO_build_channel_properties(h, PNIO_DIAG_CHANPROP_TYPE_SUBMOD,
                                         PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_FREE,
                                         PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE);
    check("PNIO_diag_channel_remove", PNIO_diag_channel_remove(h, 0, &io, kDiagTag));
    put16(&diag[2], prop);
    acknowledged("PNIO_diag_alarm_send(DISAPPEARS)",
                 PNIO_diag_alarm_send(h, 0, ar, sk, PNIO_STATE_ALARM_DISAPPEARS, &io, diag.data(),
                                      diag.size(), PNIO_USR_STRUC_ID_CHANNEL_DIAG,
                                      kDiagDisappears),
                 kDiagDisappears);
    std::printf("channel diagnosis removed, diagnosis alarm (disappears) acknowledged\n");

    int writes, reads, disorder;
    {
        std::lock_guard<std::mutex> lock(seen.mu);
        writes = seen.rec_writes;
        reads = seen.rec_reads;
        disorder = seen.out_of_order;
    }
    std::printf("parameter record %u: written %d times, read %d times\n",
                static_cast<unsigned>(kParamIndex), writes, reads);
    if (writes == 0) {
        throw std::runtime_error("the PLC wrote no parameter record");
    }
    if (disorder != 0) {
        throw std::runtime_error(std::to_string(disorder) + " AR indications out of order");
    }
    device.stop();
}

unsigned long parse_id(int argc, char **argv, int at, const char *env, unsigned long demo) {
    const char *v = argc > at ? argv[at] : std::getenv(env);
    return v != nullptr && *v != '\0' ? std::strtoul(v, nullptr, 0) : demo;
}

} // namespace

int main(int argc, char **argv) {
    const double seconds = argc > 1 ? std::strtod(argv[1], nullptr) : 5.0;
    const unsigned long vendor = parse_id(argc, argv, 2, "PNIO_VENDOR_ID", kDemoVendorId);
    const unsigned long device = parse_id(argc, argv, 3, "PNIO_DEVICE_ID", kDemoDeviceId);
    if (seconds <= 0 || vendor > 0xFFFF || device > 0xFFFF) {
        std::fprintf(stderr, "usage: %s [seconds [vendor_id device_id]]\n", argv[0]);
        return 2;
    }
    // Each line as it happens, also into a pipe.
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    try {
        dev_easy(seconds, static_cast<PNIO_UINT16>(vendor), static_cast<PNIO_UINT16>(device));
    } catch (const std::exception &e) {
        std::fprintf(stderr, "pnio_dev_easy: %s\n", e.what());
        return 1;
    }
    std::printf("DevEasy: all steps done\n");
    return 0;
}
