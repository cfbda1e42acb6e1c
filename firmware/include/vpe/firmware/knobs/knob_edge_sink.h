// SPDX-License-Identifier: MIT
// KnobEdgeSink: the one decoding path from GPIO line edges to InputEvents, shared by the
// hardware backend (GpioKnobs) and `vpe-player --replay` (recorded edges). No hardware: it keeps
// the level of every configured line, routes each edge to its encoder's QuadratureDecoder (with
// turn acceleration) or its DebouncedButton, and emits the events. Feed edges in timestamp order
// (mergeByTimestamp).
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "vpe/firmware/input/input_event.h"
#include "vpe/firmware/knobs/debounced_button.h"
#include "vpe/firmware/knobs/knobs_config.h"
#include "vpe/firmware/knobs/line_edge.h"
#include "vpe/firmware/knobs/quadrature_decoder.h"
#include "vpe/firmware/knobs/turn_acceleration.h"

namespace vpe::firmware::knobs {

// Line offset → level (true: high).
using LineLevels = std::map<unsigned, bool>;

class KnobEdgeSink {
public:
    // `initial`: the lines' levels at `startNs` (read from the chip, or a replay's header); a
    // line missing there takes its idle level: high for encoder contacts (open, pulled up) and
    // the released level for buttons. The config's lines are distinct (parseKnobsConfig checks).
    KnobEdgeSink(const KnobsConfig& config, const LineLevels& initial, std::int64_t startNs);

    // One edge; appends the events it completes. Returns false (and ignores it) when the line
    // is not one of the config's.
    bool onEdge(const LineEdge& edge, std::vector<InputEvent>& events);

    // Settles buttons whose level has been stable for their debounce time by `nowNs`.
    void onTick(std::int64_t nowNs, std::vector<InputEvent>& events);

    // The configured lines, ascending, and their current levels.
    std::vector<unsigned> lines() const;
    const LineLevels& levels() const { return levels_; }

private:
    struct Encoder {
        EncoderConfig config;
        QuadratureDecoder decoder;
        TurnAccelerator accelerator;
    };
    struct Button {
        ButtonConfig config;
        DebouncedButton debounced;
    };
    // What a line drives: encoder `index` contact A or B, or button `index`.
    struct Route {
        enum class Kind : std::uint8_t { kEncoderA, kEncoderB, kButton } kind;
        std::size_t index;
    };

    void settleButtons(std::int64_t nowNs, std::vector<InputEvent>& events);

    std::vector<Encoder> encoders_;
    std::vector<Button> buttons_;
    std::map<unsigned, Route> routes_;
    LineLevels levels_;
};

}  // namespace vpe::firmware::knobs
