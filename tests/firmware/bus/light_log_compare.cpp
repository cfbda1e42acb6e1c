// SPDX-License-Identifier: MIT
// vpe_light_log_compare: the nodes' `vpe-player --light-log` files compared
// (light_log_agreement.h defines the measures); one JSON object on stdout.
//   vpe_light_log_compare agreement --reference A.jsonl [--from-us T] [--to-us T] B.jsonl ...
//       → {"frames", "apart", "p50_ms", "p99_ms", "max_ms"} over every other log's frames
//   vpe_light_log_compare latency --reference A.jsonl [--from-us T] [--to-us T] B.jsonl ...
//       → {"onsets", "matched", "p50_frames", "delays_frames": [...]}: for each time A starts
//         moving after standing still, when each other node starts, minus A's, in 60 Hz frames
//   vpe_light_log_compare settle --reference A.jsonl --from-us T [--to-us T] [--max-lag-ms 16.7]
//       B.jsonl ... → {"settled_ms": [...]}: per other log, from T until it agrees for good
//       (null: never)
//   vpe_light_log_compare gaps [--from-us T] [--to-us T] A.jsonl ... → {"largest_gap_ms"}
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "../../support/median.h"
#include "light_log_agreement.h"

namespace {

using namespace vpe::firmware::bus::testing;
using vpe::testing::median;

constexpr double kFrameMs = 1000.0 / 60.0;

[[noreturn]] void usage(const std::string& problem) {
    std::cerr << "vpe_light_log_compare: " << problem
              << " (usage: agreement|latency|settle|gaps [--reference LOG] [--from-us T] "
                 "[--to-us T] [--max-lag-ms M] LOG...)\n";
    std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> arguments(argv + 1, argv + argc);
    if (arguments.empty()) {
        usage("missing the measure");
    }
    const std::string measure = arguments[0];
    std::string referencePath;
    std::int64_t fromUs = std::numeric_limits<std::int64_t>::min();
    std::int64_t toUs = std::numeric_limits<std::int64_t>::max();
    double maxLagMs = kFrameMs;
    std::vector<std::string> others;
    for (std::size_t i = 1; i < arguments.size(); ++i) {
        const std::string& a = arguments[i];
        if (a == "--reference" || a == "--from-us" || a == "--to-us" || a == "--max-lag-ms") {
            if (i + 1 >= arguments.size()) {
                usage(a + ": missing value");
            }
            const std::string& value = arguments[++i];
            try {
                if (a == "--reference") {
                    referencePath = value;
                } else if (a == "--from-us") {
                    fromUs = std::stoll(value);
                } else if (a == "--to-us") {
                    toUs = std::stoll(value);
                } else {
                    maxLagMs = std::stod(value);
                }
            } catch (const std::exception&) {
                usage(a + ": expected a number, got \"" + value + "\"");
            }
        } else {
            others.push_back(a);
        }
    }
    try {
        if (measure == "gaps") {
            double largest = 0;
            for (const std::string& path : others) {
                largest = std::max(largest, largestGapMs(readLightLog(path), fromUs, toUs));
            }
            std::printf("{\"largest_gap_ms\": %.2f}\n", largest);
            return 0;
        }
        if (referencePath.empty() || others.empty()) {
            usage("--reference and at least one other log are needed");
        }
        const LightTrack reference = readLightLog(referencePath);
        if (measure == "agreement") {
            Agreement all;
            for (const std::string& path : others) {
                const Agreement one = compareTracks(reference, readLightLog(path), fromUs, toUs);
                all.lagsMs.insert(all.lagsMs.end(), one.lagsMs.begin(), one.lagsMs.end());
                all.apart += one.apart;
            }
            std::printf(
                "{\"frames\": %zu, \"apart\": %zu, \"p50_ms\": %.3f, \"p99_ms\": %.3f, "
                "\"max_ms\": %.3f}\n",
                all.lagsMs.size(), all.apart, all.percentile(0.5), all.percentile(0.99),
                all.percentile(1.0));
        } else if (measure == "latency") {
            std::vector<std::int64_t> onsets;
            for (const std::int64_t t : motionOnsets(reference)) {
                if (t >= fromUs && t <= toUs) {
                    onsets.push_back(t);
                }
            }
            std::vector<double> delays;
            for (const std::string& path : others) {
                const std::vector<std::int64_t> theirs = motionOnsets(readLightLog(path));
                for (const std::int64_t t : onsets) {
                    const auto match = std::find_if(
                        theirs.begin(), theirs.end(),
                        [t](std::int64_t u) { return u >= t - 100'000 && u <= t + 500'000; });
                    if (match != theirs.end()) {
                        delays.push_back(static_cast<double>(*match - t) / 1000.0 / kFrameMs);
                    }
                }
            }
            std::printf(
                "{\"onsets\": %zu, \"matched\": %zu, \"p50_frames\": %.3f, \"delays_frames\": [",
                onsets.size() * others.size(), delays.size(), median(delays));
            for (std::size_t i = 0; i < delays.size(); ++i) {
                std::printf("%s%.3f", i == 0 ? "" : ", ", delays[i]);
            }
            std::printf("]}\n");
        } else if (measure == "settle") {
            std::printf("{\"settled_ms\": [");
            for (std::size_t i = 0; i < others.size(); ++i) {
                const auto settled =
                    settledFrom(reference, readLightLog(others[i]), fromUs, toUs, maxLagMs);
                if (settled) {
                    std::printf("%s%.1f", i == 0 ? "" : ", ",
                                static_cast<double>(*settled - fromUs) / 1000.0);
                } else {
                    std::printf("%snull", i == 0 ? "" : ", ");
                }
            }
            std::printf("]}\n");
        } else {
            usage("unknown measure \"" + measure + "\"");
        }
    } catch (const std::runtime_error& error) {
        std::cerr << "vpe_light_log_compare: " << error.what() << "\n";
        return 2;
    }
    return 0;
}
