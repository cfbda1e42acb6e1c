// SPDX-License-Identifier: MIT
// OSC throughput without sockets: dispatching decoded messages (accepted and rejected), and
// decoding + dispatching the datagrams liblo would put on the wire.
#include <cstdlib>

#include <benchmark/benchmark.h>
#include <lo/lo.h>

#include "vpe/firmware/osc/osc_dispatcher.h"
#include "vpe/firmware/osc/osc_packet.h"

namespace vpe::firmware {
namespace {

void BM_DispatchAccepted(benchmark::State& state) {
    OscDispatcher dispatcher(OscLimits{}, [](const std::string&) {});
    const std::vector<OscArgument> arguments{30.0f, 15.0f};
    std::int64_t now = 0;
    for (auto _ : state) {
        OscOutcome outcome = dispatcher.dispatch("/vpe/light/direction", arguments, ++now);
        benchmark::DoNotOptimize(outcome);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DispatchAccepted);

void BM_DispatchRejected(benchmark::State& state) {
    OscDispatcher dispatcher(OscLimits{}, [](const std::string&) {});
    const std::vector<OscArgument> arguments{999.0f};
    std::int64_t now = 0;
    for (auto _ : state) {
        OscOutcome outcome = dispatcher.dispatch("/vpe/light/azimuth", arguments, ++now);
        benchmark::DoNotOptimize(outcome);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DispatchRejected);

void BM_DecodeAndDispatchDatagram(benchmark::State& state) {
    OscDispatcher dispatcher(OscLimits{}, [](const std::string&) {});
    lo_message message = lo_message_new();
    lo_message_add_float(message, 30.0f);
    std::size_t size = 0;
    auto* data = static_cast<std::uint8_t*>(
        lo_message_serialise(message, "/vpe/light/azimuth", nullptr, &size));
    lo_message_free(message);
    const std::vector<std::uint8_t> datagram(data, data + size);
    std::free(data);
    std::int64_t now = 0;
    for (auto _ : state) {
        OscPacket packet = decodeOscPacket(datagram);
        for (const OscMessage& m : std::get<std::vector<OscMessage>>(packet)) {
            OscOutcome outcome = dispatcher.dispatch(m.path, m.arguments, ++now);
            benchmark::DoNotOptimize(outcome);
        }
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DecodeAndDispatchDatagram);

}  // namespace
}  // namespace vpe::firmware

BENCHMARK_MAIN();
