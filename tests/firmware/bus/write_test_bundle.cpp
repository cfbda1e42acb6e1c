// SPDX-License-Identifier: MIT
// vpe_write_test_bundle: writes the GLES tests' small vase bundle (tests/renderer/
// gles_test_bundle.h) to a file, for scripts that run vpe-player without baking one
// (scripts/multi-node-report.sh). Device build too: no offline dependency.
//   vpe_write_test_bundle --out scene.vpeb [--size 160x90]
#include <charconv>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "gles_test_bundle.h"

namespace {

bool parseSize(const std::string& text, int& width, int& height) {
    const std::size_t x = text.find('x');
    if (x == std::string::npos) {
        return false;
    }
    const auto [wEnd, wError] = std::from_chars(text.data(), text.data() + x, width);
    const auto [hEnd, hError] =
        std::from_chars(text.data() + x + 1, text.data() + text.size(), height);
    return wError == std::errc{} && hError == std::errc{} && wEnd == text.data() + x &&
           hEnd == text.data() + text.size() && width >= 16 && height >= 16 && width <= 4096 &&
           height <= 4096;
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> arguments(argv + 1, argv + argc);
    std::string out;
    vpe::renderer::testing::GlesBundleSpec spec;
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        const std::string& option = arguments[i];
        if ((option == "--out" || option == "--size") && i + 1 < arguments.size()) {
            const std::string& value = arguments[++i];
            if (option == "--out") {
                out = value;
            } else if (!parseSize(value, spec.projectorWidth, spec.projectorHeight)) {
                std::cerr << "vpe_write_test_bundle: --size: expected WxH (16..4096), got \""
                          << value << "\"\n";
                return 2;
            }
        } else {
            std::cerr << "vpe_write_test_bundle: " << option
                      << ": unknown or incomplete argument (usage: --out FILE [--size WxH])\n";
            return 2;
        }
    }
    if (out.empty()) {
        std::cerr << "vpe_write_test_bundle: --out: missing\n";
        return 2;
    }
    const std::vector<std::byte> bytes = vpe::renderer::testing::buildGlesTestBundle(spec);
    std::ofstream file(out, std::ios::binary);
    file.write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
    if (!file) {
        std::cerr << "vpe_write_test_bundle: " << out << ": cannot write\n";
        return 2;
    }
    std::cout << out << ": " << bytes.size() << " bytes, projector " << spec.projectorWidth << "x"
              << spec.projectorHeight << "\n";
    return 0;
}
