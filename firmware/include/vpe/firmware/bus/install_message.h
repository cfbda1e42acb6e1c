// SPDX-License-Identifier: MIT
// The control page's install steps on the show's bus (proto/BUS.md, "Install steps"): a
// controller asks one node to run a scan or a radiometric capture (InstallCommand on
// vpe/<show>/command/<client id>, not retained); the node says how far it got
// (InstallProgress on vpe/<show>/install/<client id>/progress, retained) and publishes two
// small grey PNGs beside it (.../camera: the camera's view of the white pattern; .../coverage:
// which camera pixels are lit and decodable).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "vpe/firmware/bus/light_message.h"

namespace vpe::firmware::bus {

inline constexpr int kInstallMessageFormat = 1;

enum class InstallAction : std::uint8_t {
    kScan,        // the structured-light scan (and the radiometric capture after it, as --scan)
    kRadiometry,  // the radiometric capture's flat fields alone
};

// "scan", "radiometry".
const char* installActionName(InstallAction action);

struct InstallCommand {
    std::string node;  // who asked (the page's client id)
    std::int64_t timeUs = 0;
    InstallAction action = InstallAction::kScan;
};

std::string encodeInstallCommand(const InstallCommand& command);
// Strict, as decodeLightMessage: "format" 1, "node" 1-64 bytes, "time_us" a wall-clock time in
// whole microseconds, "action" "scan" or "radiometry". A time more than `maxAgeUs` before
// `nowUs` or more than 2 s after it is out of range (a command held back by the network, or
// from a clock that is not the show's, runs no capture).
std::variant<InstallCommand, LightMessageRefusal> decodeInstallCommand(std::string_view payload,
                                                                       std::int64_t nowUs,
                                                                       std::int64_t maxAgeUs);

enum class InstallState : std::uint8_t { kRunning, kDone, kFailed };

// "running", "done", "failed".
const char* installStateName(InstallState state);

struct InstallProgress {
    std::string node;  // the capturing node's client id
    std::int64_t timeUs = 0;
    InstallAction action = InstallAction::kScan;
    std::string requestedBy;  // the command's node
    InstallState state = InstallState::kRunning;
    std::string step;  // what is being done: "opening the camera", a pattern's name, "writing"
    std::uint64_t framesDone = 0, framesTotal = 0;  // images accepted, of all the capture's
    double elapsedS = 0;                            // since the command was taken
    std::string out;                                // the folder written
    std::string result;                             // done: the summary line
    std::string error;                              // failed: the one-line error
    // The coverage map's shares of the camera's pixels (once known).
    std::optional<double> litFraction, decodableFraction;
};

std::string encodeInstallProgress(const InstallProgress& progress);

}  // namespace vpe::firmware::bus
