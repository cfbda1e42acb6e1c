// SPDX-License-Identifier: MIT
// Per-frame cost of the lamp's decoding at the camera's 320 × 240: BrightBlobTracker alone on
// a dark room with the lamp, on a busy frame (many above-level glints and a large bright area,
// the union-find's worst realistic case), and LampTracker's whole path (blob, filter,
// calibration, event). Run by hand: vpe_blob_tracker_benchmark.
#include <vector>

#include <benchmark/benchmark.h>

#include "vpe/firmware/tracking/bright_blob_tracker.h"
#include "vpe/firmware/tracking/lamp_tracker.h"
#include "vpe/firmware/tracking/synthetic_lamp_frame.h"

namespace vpe::firmware {
namespace {

LuminanceFrame lampFrame() {
    SyntheticLampFrame scene;
    scene.noiseSigma = 3.0;
    scene.lamp = SyntheticSpot{161.3, 118.7, 3.0, 400.0};
    scene.distractors = {{60.0, 200.0, 12.0, 90.0}};
    return scene.render();
}

LuminanceFrame busyFrame() {
    SyntheticLampFrame scene;
    scene.noiseSigma = 3.0;
    scene.lamp = SyntheticSpot{161.3, 118.7, 3.0, 400.0};
    for (int i = 0; i < 200; ++i) {
        scene.distractors.push_back({7.0 + (i * 37) % 306, 5.0 + (i * 53) % 230, 0.8, 255.0});
    }
    scene.distractors.push_back({250.0, 60.0, 25.0, 400.0});  // a window
    return scene.render();
}

void findBlob(benchmark::State& state, const LuminanceFrame& frame) {
    BrightBlobTracker tracker(BlobTrackerConfig{});
    for (auto _ : state) {
        benchmark::DoNotOptimize(tracker.find(frame.view()));
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_BlobDarkRoom(benchmark::State& state) {
    findBlob(state, lampFrame());
}
void BM_BlobBusyFrame(benchmark::State& state) {
    findBlob(state, busyFrame());
}

void BM_LampTrackerFrame(benchmark::State& state) {
    const LuminanceFrame frame = lampFrame();
    const std::vector<CalibrationPoint> points{
        {20, 20, -60, 50},  {160, 20, 0, 55},  {300, 20, 60, 50},
        {20, 120, -65, 25}, {160, 120, 0, 30}, {300, 120, 65, 25},
        {20, 220, -60, 5},  {160, 220, 0, 8},  {300, 220, 60, 5}};
    LampTracker tracker(LampTrackerSettings{}, LampCalibration::fit(points));
    std::vector<InputEvent> events;
    std::int64_t timestampNs = 0;
    for (auto _ : state) {
        events.clear();
        timestampNs += 33'333'333;
        tracker.onFrame(frame.view(), timestampNs, events);
        benchmark::DoNotOptimize(events.data());
    }
    state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_BlobDarkRoom)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BlobBusyFrame)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LampTrackerFrame)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace vpe::firmware

BENCHMARK_MAIN();
