// SPDX-License-Identifier: MIT
// libFuzzer target: arbitrary bytes as an .lp light file either parse into a well-formed
// capture or fail with an InputError naming the file and line; anything else crashes.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "vpe/capture/light_file_reader.h"
#include "vpe/common/input_error.h"

namespace {

// Every rejection must be "dirs.lp:<line>: <problem>" so that users can find the line.
bool namesFileAndLine(std::string_view message) {
    constexpr std::string_view kPrefix = "fuzz/dirs.lp:";
    if (!message.starts_with(kPrefix)) {
        return false;
    }
    message.remove_prefix(kPrefix.size());
    const std::size_t digits = message.find_first_not_of("0123456789");
    return digits > 0 && digits != std::string_view::npos && message.substr(digits, 2) == ": ";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const vpe::capture::Capture capture = vpe::capture::parseLightFile(text, "fuzz/dirs.lp");
        // What the fitter relies on: at least one image, and unit directions.
        if (capture.images.empty()) {
            std::abort();
        }
        for (const vpe::capture::CaptureImage& image : capture.images) {
            const double length = std::sqrt(vpe::proto::dot(image.light, image.light));
            if (!(std::fabs(length - 1.0) < 1e-12) || image.line < 2 || image.file.empty()) {
                std::abort();
            }
        }
    } catch (const vpe::common::InputError& error) {
        if (!namesFileAndLine(error.what())) {
            std::abort();
        }
    }
    return 0;
}
