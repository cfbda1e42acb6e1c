// SPDX-License-Identifier: MIT
// CaptureLoop: the show–wait–capture–check loop both of a scan's sequences go through — the
// structured-light patterns (ScanFrameCheck) and the radiometric capture's flat fields
// (FlatFieldCheck). Group by group, in the check's order: each image drawn, shown, the
// projector's latency waited, one frame captured as its shot asks and checked; a group that
// fails is shown again and captured after a longer wait, up to the retries, and the wait that
// worked is kept for the rest (a projector slower than the board says is slow for every image,
// of this sequence and the next). Between captures it asks its caller whether to stop (SIGINT and
// SIGTERM, read by --scan's SignalWatch or by the player lending its display) and stops after
// the current capture.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "vpe/firmware/scan/frame_check.h"
#include "vpe/firmware/scan/pattern_projector.h"
#include "vpe/firmware/scan/scan_camera.h"

namespace vpe::firmware {

struct CaptureTiming {
    double latencyMs = 150;    // the first wait after an image is on screen
    int retries = 3;           // captures of a group after its first
    double retryWaitMs = 100;  // each retry waits this much longer
};

// One image of a sequence: its name (errors say it), how many codes a projector pixel takes
// (1: grey, the same on R, G and B; 3: R, G, B) and how the camera takes it.
struct Shot {
    std::string name;
    int channels = 1;
    CaptureRequest request;
};

// What a run did, for the report.
struct CaptureTally {
    std::size_t captures = 0;  // retries included
    std::size_t retried = 0;   // images that took more than one capture
    std::array<std::uint64_t, kFrameProblemCount> rejected{};  // refused captures, per problem
    std::vector<double> captureMs;  // per capture: image on screen → image in hand
};

class CaptureLoop {
public:
    // Fills `codes` (width·height·channels of the shot, rows from the top) with image `index`.
    using Draw = std::function<void(std::size_t index, std::span<std::uint8_t> codes)>;
    // Image `index` was accepted after `attempts` captures.
    using Accept = std::function<void(std::size_t index, const CameraImage& image, int attempts)>;

    // Called after each capture and each wait: why the capture must stop ("SIGTERM"), empty to
    // go on. The player also services its bus and watchdog there.
    using Interrupted = std::function<std::string()>;

    // Borrows the projector and the camera; `width` × `height` is the projector's (the target's)
    // size.
    CaptureLoop(PatternProjector& projector, ScanCamera& camera, Interrupted interrupted, int width,
                int height, const CaptureTiming& timing);

    // Shows black and returns `ms` after it was on screen (nothing is captured), asking
    // `interrupted` every 100 ms meanwhile. Throws ScanError on SIGINT or SIGTERM.
    void showBlack(double ms);

    // Captures the sequence `shots` (one per index) in `check`'s groups; each image of a group is
    // handed to `accepted` once the whole group passed, in the group's order. Throws ScanError
    // naming the image whose group kept failing ("scan: black: … (2 captures, the last 50 ms
    // after the pattern; raise [scan] latency_ms or retries)") or a signal's stop.
    CaptureTally run(const std::vector<Shot>& shots, FrameCheck& check, const Draw& draw,
                     const Accept& accepted);

    // The wait in use: the latency, or the longer one retries settled on.
    double waitMs() const { return waitMs_; }

private:
    void show(const Shot& shot, std::span<const std::uint8_t> codes, std::int64_t& shownNs);
    void stopOnSignal();

    PatternProjector& projector_;
    ScanCamera& camera_;
    Interrupted interrupted_;
    int width_ = 0, height_ = 0;
    CaptureTiming timing_;
    double waitMs_ = 0;
};

}  // namespace vpe::firmware
