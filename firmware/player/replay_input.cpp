// SPDX-License-Identifier: MIT
// ReplayInput: reading the file (nlohmann-json, header only: the one JSON reader the project
// uses on both sides) and playing it on a timerfd.
#include "vpe/firmware/player/replay_input.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <utility>

#include <nlohmann/json.hpp>

#include "vpe/firmware/player/player_log.h"
#include "vpe/firmware/tracking/synthetic_lamp_frame.h"

namespace vpe::firmware {

namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::filesystem::path& path, int line, const std::string& problem) {
    throw ReplayError(path.string() + ":" + std::to_string(line) + ": " + problem);
}

double numberField(const json& object, const char* key, const std::filesystem::path& path,
                   int line) {
    const auto found = object.find(key);
    if (found == object.end()) {
        fail(path, line, std::string("\"") + key + "\": missing");
    }
    if (!found->is_number()) {
        fail(path, line, std::string("\"") + key + "\": expected a number");
    }
    const double value = found->get<double>();
    if (!std::isfinite(value)) {
        fail(path, line, std::string("\"") + key + "\": expected a finite number");
    }
    return value;
}

ReplayEvent parseEvent(const json& object, const std::filesystem::path& path, int line) {
    if (!object.is_object()) {
        fail(path, line, "expected a JSON object");
    }
    ReplayEvent event;
    event.line = line;
    const double t = numberField(object, "t", path, line);
    if (t < 0 || t > 1e6) {
        fail(path, line, "\"t\": expected seconds in [0, 1e6]");
    }
    event.offsetNs = static_cast<std::int64_t>(std::llround(t * 1e9));
    const auto type = object.find("type");
    if (type == object.end() || !type->is_string()) {
        fail(path, line, "\"type\": expected \"gpio\", \"camera\" or \"osc\"");
    }
    const std::string kind = type->get<std::string>();
    if (kind == "gpio") {
        event.kind = ReplayEvent::Kind::kGpio;
        const double offset = numberField(object, "line", path, line);
        if (offset < 0 || offset > 1023 || offset != std::floor(offset)) {
            fail(path, line, "\"line\": expected a line offset in 0..1023");
        }
        event.edge.line = static_cast<unsigned>(offset);
        const auto edge = object.find("edge");
        if (edge == object.end() || !edge->is_string() ||
            (*edge != "rising" && *edge != "falling")) {
            fail(path, line, "\"edge\": expected \"rising\" or \"falling\"");
        }
        event.edge.kind = *edge == "rising" ? knobs::EdgeKind::kRising : knobs::EdgeKind::kFalling;
    } else if (kind == "camera") {
        event.kind = ReplayEvent::Kind::kCamera;
        if (object.contains("x") || object.contains("y")) {
            SyntheticSpot spot;
            spot.x = numberField(object, "x", path, line);
            spot.y = numberField(object, "y", path, line);
            if (object.contains("radius")) {
                spot.radius = numberField(object, "radius", path, line);
            }
            if (object.contains("peak")) {
                spot.peak = numberField(object, "peak", path, line);
            }
            event.lamp = spot;
        }
    } else if (kind == "osc") {
        event.kind = ReplayEvent::Kind::kOsc;
        const auto address = object.find("path");
        if (address == object.end() || !address->is_string()) {
            fail(path, line, "\"path\": expected an OSC address string");
        }
        event.message.path = address->get<std::string>();
        if (const auto args = object.find("args"); args != object.end()) {
            if (!args->is_array()) {
                fail(path, line, "\"args\": expected an array");
            }
            for (const json& argument : *args) {
                // JSON integers are OSC int32 (i) when they fit, floats are f: what a typical
                // sender puts on the wire for the same values.
                if (argument.is_number_integer()) {
                    const auto value = argument.get<std::int64_t>();
                    if (value >= INT32_MIN && value <= INT32_MAX) {
                        event.message.arguments.emplace_back(static_cast<std::int32_t>(value));
                    } else {
                        event.message.arguments.emplace_back(value);
                    }
                } else if (argument.is_number()) {
                    event.message.arguments.emplace_back(
                        static_cast<float>(argument.get<double>()));
                } else if (argument.is_string()) {
                    event.message.arguments.emplace_back(argument.get<std::string>());
                } else {
                    fail(path, line, "\"args\": expected numbers and strings");
                }
            }
        }
    } else {
        fail(path, line,
             "\"type\": expected \"gpio\", \"camera\" or \"osc\", got \"" + kind + "\"");
    }
    return event;
}

}  // namespace

std::vector<ReplayEvent> readReplayFile(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) {
        std::error_code error;
        throw ReplayError(
            path.string() + ": cannot read replay file (" +
            (std::filesystem::exists(path, error) ? "permission denied" : "no such file") + ")");
    }
    std::vector<ReplayEvent> events;
    std::string text;
    int line = 0;
    std::int64_t previous = 0;
    while (std::getline(in, text)) {
        ++line;
        if (text.find_first_not_of(" \t\r") == std::string::npos || text[0] == '#') {
            continue;
        }
        const json object = json::parse(text, nullptr, false);
        if (object.is_discarded()) {
            fail(path, line, "not valid JSON");
        }
        ReplayEvent event = parseEvent(object, path, line);
        if (event.offsetNs < previous) {
            fail(path, line, "\"t\" goes back in time (events must be in time order)");
        }
        previous = event.offsetNs;
        events.push_back(std::move(event));
    }
    if (events.empty()) {
        throw ReplayError(path.string() + ": no events");
    }
    return events;
}

ReplayInput::ReplayInput(const std::filesystem::path& path, std::vector<ReplayEvent> events,
                         const ReplayDecoders& decoders, bool loop, std::int64_t startNs)
    : path_(path),
      events_(std::move(events)),
      loop_(loop),
      startNs_(startNs),
      osc_(decoders.oscLimits, playerLog) {
    osc_.setPresetNames(decoders.presetNames);
    for (const ReplayEvent& event : events_) {
        if (event.kind == ReplayEvent::Kind::kGpio && !knobs_) {
            if (!decoders.knobs ||
                (decoders.knobs->encoders.empty() && decoders.knobs->buttons.empty())) {
                fail(path_, event.line, "a gpio event, but the board's [gpio] has no knobs");
            }
            knobs_.emplace(*decoders.knobs, knobs::LineLevels{}, startNs_);
        }
        if (event.kind == ReplayEvent::Kind::kCamera && !tracker_) {
            if (!decoders.camera || !decoders.lampDirection) {
                fail(path_, event.line,
                     "a camera event, but the board's [camera] has no calibration and the "
                     "bundle carries no camera");
            }
            try {
                tracker_.emplace(decoders.camera->tracking, *decoders.lampDirection);
            } catch (const std::exception& error) {
                fail(path_, event.line, error.what());
            }
            frameWidth_ = decoders.camera->tracking.width;
            frameHeight_ = decoders.camera->tracking.height;
        }
    }
    periodNs_ = events_.back().offsetNs + 1'000'000'000;
    // Armed at the loop's first tick (onTick), not here.
}

std::string ReplayInput::description() const {
    return "replay (" + path_.string() + ": " + std::to_string(events_.size()) + " events" +
           (loop_ ? ", looping)" : ")");
}

void ReplayInput::armNext() {
    if (next_ >= events_.size()) {
        if (!loop_) {
            timer_.disarm();
            return;
        }
        next_ = 0;
        startNs_ += periodNs_;
    }
    timer_.arm(startNs_ + events_[next_].offsetNs, 0);
}

void ReplayInput::play(const ReplayEvent& event, std::int64_t atNs,
                       std::vector<InputEvent>& events) {
    switch (event.kind) {
        case ReplayEvent::Kind::kGpio: {
            knobs::LineEdge edge = event.edge;
            edge.timestampNs = atNs;
            knobs_->onEdge(edge, events);
            break;
        }
        case ReplayEvent::Kind::kCamera: {
            SyntheticLampFrame frame;
            frame.width = frameWidth_;
            frame.height = frameHeight_;
            frame.seed = frameSeed_++;
            frame.lamp = event.lamp;
            try {
                tracker_->onFrame(frame.render().view(), atNs, events);
            } catch (const std::invalid_argument& error) {
                // Checked here rather than at load: a frame is rendered only when played.
                fail(path_, event.line, error.what());
            }
            break;
        }
        case ReplayEvent::Kind::kOsc: {
            const OscOutcome outcome =
                osc_.dispatch(event.message.path, event.message.arguments, atNs);
            if (outcome.event) {
                events.push_back(*outcome.event);
            }
            break;
        }
    }
}

void ReplayInput::onReadable(int, std::int64_t nowNs, std::vector<InputEvent>& events) {
    timer_.expirations();
    while (next_ < events_.size() && startNs_ + events_[next_].offsetNs <= nowNs) {
        const std::int64_t scheduledNs = startNs_ + events_[next_].offsetNs;
        play(events_[next_], scheduledNs, events);
        // Measured after playing it: drawing and tracking a synthetic frame takes time too.
        lateNs_ = std::max<std::int64_t>(monotonicNowNs() - scheduledNs, 0);
        ++next_;
        if (next_ >= events_.size() && loop_) {
            next_ = 0;
            startNs_ += periodNs_;
        }
    }
    armNext();
}

std::map<std::string, std::uint64_t> ReplayInput::refusals() const {
    std::map<std::string, std::uint64_t> refusals = osc_.counters().rejectionsByName();
    if (tracker_) {
        for (const auto& [reason, count] : tracker_->refusals()) {
            refusals[reason] += count;
        }
    }
    return refusals;
}

void ReplayInput::setLampDirection(LampDirectionMap map) {
    if (tracker_) {
        tracker_->setDirectionMap(std::move(map));
    }
}

void ReplayInput::onTick(std::int64_t nowNs, std::vector<InputEvent>& events) {
    if (!started_) {
        // The script's clock starts with the frame loop: loading the bundle and opening the
        // display take what they take (seconds on a slow board or under emulation) without
        // bunching the first events together and letting the decoders' timers (the lamp's
        // hold) run out on a session that had not started yet.
        started_ = true;
        startNs_ = std::max(startNs_, nowNs);
        armNext();
    }
    // The decoders tick on the script's clock: this loop's time less how late the last event
    // was played, and never past the next event still to come (until then the script's devices
    // were delivering). So a busy player (a slow first frame, or tracking the synthetic camera
    // frames under emulation) does not run out the lamp's hold or a knob's timeout that the
    // session itself did not; on time, this is the loop's own time.
    std::int64_t decodersNs = nowNs - lateNs_;
    if (next_ < events_.size()) {
        decodersNs = std::min(decodersNs, startNs_ + events_[next_].offsetNs);
    }
    if (knobs_) {
        knobs_->onTick(decodersNs, events);
    }
    if (tracker_) {
        tracker_->tick(decodersNs, events);
    }
}

}  // namespace vpe::firmware
