// SPDX-License-Identifier: MIT
// ReplayInput: `vpe-player --replay events.jsonl`. Timestamped input events, one JSON object
// per line, fed at their times through the real decoding paths: GPIO edges into the
// KnobEdgeSink (quadrature decoding, acceleration, debouncing), synthetic camera frames into
// the LampTracker (blob, One Euro filter, calibration, hold and release), OSC messages into
// the OscDispatcher (ranges, coercions, counters). Each decoded event carries the time it was
// scheduled for, so the player's latency is measured from there. Format: firmware/README.md.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/knobs/knob_edge_sink.h"
#include "vpe/firmware/knobs/knobs_config.h"
#include "vpe/firmware/loop/event_loop.h"
#include "vpe/firmware/osc/osc_dispatcher.h"
#include "vpe/firmware/osc/osc_message.h"
#include "vpe/firmware/tracking/camera_config.h"
#include "vpe/firmware/tracking/lamp_tracker.h"
#include "vpe/firmware/tracking/synthetic_lamp_frame.h"
#include "vpe/proto/input_error.h"

namespace vpe::firmware {

// One line naming the file and line: "events.jsonl:12: \"edge\": expected \"rising\" or
// \"falling\"".
class ReplayError : public proto::InputError {
public:
    using proto::InputError::InputError;
};

struct ReplayEvent {
    enum class Kind : std::uint8_t { kGpio, kCamera, kOsc };
    Kind kind = Kind::kGpio;
    std::int64_t offsetNs = 0;          // "t", seconds from the replay's start
    knobs::LineEdge edge;               // kGpio (timestamp filled in when played)
    std::optional<SyntheticSpot> lamp;  // kCamera: the lamp in the frame, or none
    OscMessage message;                 // kOsc
    int line = 0;                       // in the file, for errors
};

// Parses a replay file. Throws ReplayError.
std::vector<ReplayEvent> readReplayFile(const std::filesystem::path& path);

// What the replayed events are decoded with: the board's own input settings.
struct ReplayDecoders {
    std::optional<knobs::KnobsConfig> knobs;  // needed by gpio events
    std::optional<CameraConfig> camera;       // needed by camera events
    // The map camera events go through (lampDirectionMapOf: the board's table or the bundle's
    // camera); needed by camera events too.
    std::optional<LampDirectionMap> lampDirection;
    OscLimits oscLimits;
    std::vector<std::string> presetNames;
};

class ReplayInput final : public InputDevice {
public:
    // Throws ReplayError when an event needs a decoder the board does not configure.
    ReplayInput(const std::filesystem::path& path, std::vector<ReplayEvent> events,
                const ReplayDecoders& decoders, bool loop, std::int64_t startNs);

    std::string description() const override;
    std::vector<int> pollDescriptors() const override { return {timer_.fd()}; }
    void onReadable(int fd, std::int64_t nowNs, std::vector<InputEvent>& events) override;
    void onTick(std::int64_t nowNs, std::vector<InputEvent>& events) override;
    // The replayed OSC messages' rejections, as the live server counts them, and the camera
    // frames whose lamp the map could not place, as the live camera counts them.
    std::map<std::string, std::uint64_t> refusals() const override;
    // A reloaded bundle's camera for the camera events still to come (a replay without camera
    // events has no tracker: nothing changes).
    void setLampDirection(LampDirectionMap map);

    // Every event played (never, when looping).
    bool finished() const { return !loop_ && next_ >= events_.size(); }
    const OscDispatcher& oscDispatcher() const { return osc_; }

private:
    void play(const ReplayEvent& event, std::int64_t atNs, std::vector<InputEvent>& events);
    void armNext();

    std::filesystem::path path_;
    std::vector<ReplayEvent> events_;
    bool loop_;
    std::int64_t
        startNs_;  // t = 0: the frame loop's first tick (no earlier than the constructor's)
    bool started_ = false;
    std::int64_t lateNs_ = 0;    // how late the last event was played (the loop was busy)
    std::int64_t periodNs_ = 0;  // looping: the file's length (last event + 1 s)
    std::size_t next_ = 0;
    MonotonicTimer timer_;
    std::optional<knobs::KnobEdgeSink> knobs_;
    std::optional<LampTracker> tracker_;
    OscDispatcher osc_;
    int frameWidth_ = 320, frameHeight_ = 240;
    std::uint32_t frameSeed_ = 1;
};

}  // namespace vpe::firmware
